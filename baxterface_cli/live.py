"""A face that runs for as long as it is wanted, taking commands as they come.

The face node is this plus ROS. Each command is parsed and compiled by the
same engine as `play` and `render`, starting from the face as it is at that
moment; it takes over from whatever was playing (or waits its turn, when
queued). Idle blinks go on between and after commands. Robot effects (head,
nod, enable, follow, exit) fall due as time passes and are handed out once;
the robot's status (following, exited) carries over from script to script.
"""

from __future__ import annotations

import random
from collections import deque
from typing import Deque, List, Optional, Tuple

from .effects import Cue, RobotStatus, StatusFold
from .idle import Idle
from .nodes import Script
from .parser import parse
from .state import FaceState
from .tables import EMOTIONS
from .timeline import Timeline, compile_script

IDLE_AHEAD = 30.0  # seconds of idle blinks planned ahead of the clock


def sleep_face() -> FaceState:
    """The face the original node started with and ended on."""
    spec = EMOTIONS["sleep"]
    return FaceState(
        skin=spec.skin, mouth=spec.mouths[0], brows=spec.brows[0], eyelids=spec.eyelids, emotion="sleep"
    )


class LiveFace:
    """Commands in, face states and robot actions out, on a clock the caller gives."""

    def __init__(
        self,
        start: Optional[FaceState] = None,
        idle: bool = True,
        seed: Optional[int] = None,
        now: float = 0.0,
    ) -> None:
        self.rng = random.Random(seed)
        self.idle_on = idle
        self.queue: Deque[Tuple[Script, float]] = deque()
        self._robot = StatusFold()
        self._begin(parse(""), start or FaceState(), now)

    # -- commands

    def command(
        self, text: str, now: float, queue: bool = False, filename: str = "display_chatter"
    ) -> Script:
        """Run `text` from now (or after what is playing, with `queue`); ScriptError if it is bad."""
        script = parse(text, filename)
        if queue and not self.finished(now):
            self.queue.append((script, now))
        else:
            self.queue.clear()
            self._begin(script, self.base_state(now), now)
        return script

    def _begin(self, script: Script, start: FaceState, now: float) -> None:
        self.timeline: Timeline = compile_script(script, seed=self.rng.randrange(2**32), start=start)
        self.started = now
        self.pending: List[Cue] = list(self.timeline.cues)
        self.idle = (
            Idle(self.timeline, seed=self.rng.randrange(2**32), until=IDLE_AHEAD) if self.idle_on else None
        )

    def finished(self, now: float) -> bool:
        return now - self.started >= self.timeline.duration

    # -- the face

    def base_state(self, now: float) -> FaceState:
        """The face the commands make, without idle blinks."""
        return self.timeline.sample(now - self.started)

    def state(self, now: float) -> FaceState:
        """The face to show at `now`: the commands' face with idle life on top."""
        if self.queue and self.finished(now):
            script, _ = self.queue.popleft()
            self._begin(script, self.base_state(now), self.started + self.timeline.duration)
        state = self.base_state(now)
        if self.idle is not None:
            t = now - self.started
            self.idle.extend(t + IDLE_AHEAD)  # cheap: it plans only past what it has
            state = self.idle.apply(t, state, darts=self.robot.following is None)
        return state

    @property
    def robot(self) -> RobotStatus:
        """The robot's status as the effects handed out so far left it."""
        return self._robot.status

    @property
    def exited(self) -> bool:
        return self.robot.exited

    def due(self, now: float) -> List[Cue]:
        """Robot effects whose time has come since the last call, each handed out once."""
        t = now - self.started
        ready = [c for c in self.pending if c.at <= t]
        self.pending = [c for c in self.pending if c.at > t]
        for cue in ready:
            cue.effect.visit(self._robot, cue.at)
        return ready
