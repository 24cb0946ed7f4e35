"""Commands on a live session as the node and the screen take them (engine/live_session.py), the
face read at times a test chooses: what falls due up to each time is done first."""

from __future__ import annotations

from typing import List, Optional

from baxterface_cli.core.face_state import FaceState
from baxterface_cli.engine.effects import Cue, RobotStatus
from baxterface_cli.engine.live_session import LiveSession
from baxterface_cli.engine.timeline import Timeline
from baxterface_cli.language.parser import parse


class SessionFace:
    """A live session driven by hand: commands at their times, the face and the robot's cues read."""

    def __init__(self, start: Optional[FaceState] = None, idle: bool = False, seed: int = 0) -> None:
        self.session = LiveSession(None, seed=seed, now=0.0, start=start, idle=idle)

    def command(self, text: str, now: float, filename: str = "display_chatter") -> None:
        """`text` takes over at `now`, from the face as it is then (what began finishing)."""
        self.session.run(parse(text, filename), now)

    def state(self, t: float) -> FaceState:
        self.session.advance(t)
        return self.session.face.state(t)

    def due(self, t: float) -> List[Cue]:
        """The robot's cues that fell due since the last call."""
        return self.session.tick(t)[1]

    @property
    def robot(self) -> RobotStatus:
        return self.session.face.robot

    @property
    def exited(self) -> bool:
        return self.session.face.exited

    @property
    def timeline(self) -> Timeline:
        return self.session.face.timeline


def command(live: SessionFace, text: str, now: float, filename: str = "display_chatter") -> None:
    live.command(text, now, filename)
