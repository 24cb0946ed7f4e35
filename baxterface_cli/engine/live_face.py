"""The face a live session plays on, taking each timeline as it is handed over.

A `LiveSession` (live_session.py) is every live end's engine (the node, `stream`, the screen,
`play`, and the recorded ends): it compiles each step of its scripts and handlers (`prepare`) and
hands the timeline here with `begin`. The face plays one timeline at a
time, each taking over from the one before, with idle blinks on top between and after them.
Robot effects (head, nod, enable, follow, exit) fall due as time passes and are handed out once
(`due`); the robot's status (following, exited) carries over from timeline to timeline.
"""

from __future__ import annotations

import random
from typing import TYPE_CHECKING, Callable, List, Optional, Tuple

from ..core.face_constants import EMOTIONS
from ..core.face_state import FaceState
from ..language.diagnostics import ScriptError
from ..language.parser import parse
from ..language.syntax_tree import Script
from .animation import Idle
from .compiler import Carry, compile_script
from .effects import Cue, RobotStatus, StatusFold
from .timeline import Timeline

if TYPE_CHECKING:
    from ..speech.recordings import Recordings

IDLE_AHEAD = 30.0  # seconds of idle blinks planned ahead of the clock


def sleep_face() -> FaceState:
    """The face the original node started with and ended on."""
    spec = EMOTIONS["sleep"]
    return FaceState(
        skin=spec.skin, mouth=spec.mouths[0], brows=spec.brows[0], eyelids=spec.eyelids, emotion="sleep"
    )


class LiveFace:
    """Timelines in, face states and robot effects out, on a clock the caller gives.

    Compiling (`prepare`) is safe from any thread and may wait (a `say` waits for
    espeak-ng); `begin` hands the result over, which is cheap, and `state` and `due`, read by a
    frame loop, never compile.
    """

    def __init__(
        self,
        start: Optional[FaceState] = None,
        idle: bool = True,
        seed: Optional[int] = None,
        now: float = 0.0,
        recordings: Optional[Recordings] = None,
    ) -> None:
        """`recordings`: where `say file` may read; by default nowhere, as commands come from afar."""
        self.rng = random.Random(seed)
        self.recordings = recordings
        self.idle_on = idle
        self._robot = StatusFold()
        # Told of every timeline begun, with its start (a session's log file: session_log_file.py).
        self.begun: Optional[Callable[[Timeline, float], None]] = None
        self.begin(compile_script(parse(""), start=start or FaceState()), now)

    # -- timelines

    def prepare(self, script: Script, start: FaceState, carry: Optional[Carry] = None) -> Timeline:
        """Compile `script` to start from `start`; safe from another thread."""
        from ..speech.recordings import RecordingError, Recordings

        if self.recordings is None:
            self.recordings = Recordings(None)
        # A recording's length is in its header, which parsing does not read: the length limit with it.
        unsaid = self.recordings.check(script) if "file" in script.source.lower() else []
        if unsaid:
            raise ScriptError(unsaid, script.filename, script.source)
        seed = self.rng.randrange(2**32)
        try:
            return compile_script(script, seed=seed, start=start, recordings=self.recordings, carry=carry)
        except RecordingError as e:  # found only in saying it: a text espeak-ng crashed on
            raise ScriptError([e.diagnostic()], script.filename, script.source) from None

    def begin(self, timeline: Timeline, now: float) -> None:
        """Play `timeline` from `now`, dropping what was playing and its effects not yet due."""
        idle = Idle(timeline, seed=self.rng.randrange(2**32), until=IDLE_AHEAD) if self.idle_on else None
        self.pending: List[Cue] = list(timeline.cues)
        # One assignment, so a reader on another thread (a frame loop, while the live session's
        # worker starts a step) sees the timeline, its start and its idle life together.
        self._playing = (timeline, now, idle)
        if self.begun is not None:
            self.begun(timeline, now)

    @property
    def idle(self) -> Optional[Idle]:
        return self._playing[2]

    @property
    def timeline(self) -> Timeline:
        return self._playing[0]

    @property
    def playing(self) -> Tuple[Timeline, float]:
        """The timeline and its start, read together (a worker may begin another meanwhile)."""
        return self._playing[:2]

    @property
    def started(self) -> float:
        return self._playing[1]

    def finished(self, now: float) -> bool:
        timeline, started, _ = self._playing
        return now - started >= timeline.duration

    # -- the face

    @property
    def showing(self) -> Tuple[Timeline, float, Optional[Idle]]:
        """The timeline, its start and its idle life, read together: what `state` draws from. A
        player that runs the session ahead of its picture keeps the last few to draw with `at`."""
        return self._playing

    def state(self, now: float) -> FaceState:
        """The face to show at `now`: the commands' face with idle life on top."""
        return self.at(self._playing, now)

    def at(self, showing: Tuple[Timeline, float, Optional[Idle]], now: float) -> FaceState:
        """The face `showing` (read from `showing` earlier) shows at `now`, idle life on top."""
        timeline, started, idle = showing
        t = max(0.0, now - started)  # a frame's clock read just before another thread began a step
        state = timeline.sample(t)
        if idle is not None:
            idle.extend(t + IDLE_AHEAD)  # cheap: it plans only past what it has
            state = idle.apply(t, state, darts=self.robot.following is None)
        return state

    @property
    def robot(self) -> RobotStatus:
        """The robot's status as the effects handed out so far left it (times on the caller's clock)."""
        return self._robot.status

    @property
    def exited(self) -> bool:
        return self.robot.exited

    def due(self, now: float) -> List[Cue]:
        """Robot effects whose time has come since the last call, each handed out once."""
        t = now - self.started
        ready = [c for c in self.pending if c.at <= t]
        self.pending = [c for c in self.pending if c.at > t]
        for cue in ready:  # on the caller's clock: the status outlives the script that set it
            cue.effect.visit(self._robot, self.started + cue.at)
        return ready
