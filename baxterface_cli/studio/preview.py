"""What the studio's preview shows: its one live session, the run of the editor's script over the
events fired and the commands pressed (reacting.py, event_run.py), on a transport or live.

One run, two ways along it. On the transport (`SCRIPT`) it plays, pauses, seeks and loops along
the run's length. A command pressed takes over the run at the preview's position and makes the
preview live (`SESSION`): its position follows the clock from there, past the run's end (the
session goes on with the clock), so the next press lands as long after it as it came. Play,
pause and seek go back to the transport. No clock inside: every call is given `now`, so it is all
tested without waiting.
"""

from __future__ import annotations

import math
import random
from typing import Any, Dict, List, Optional, Tuple

from ..core.face_state import FaceState
from ..engine.animation import Animation
from ..engine.compiler import compile_script
from ..engine.effects import RobotStatus
from ..engine.timeline import Said
from ..language.parser import parse
from ..language.syntax_tree import Script
from ..speech.recordings import Recordings
from ..speech.synthesis import Utterance
from ..web.sounds import sound_key
from . import reacting
from .event_run import Input

SCRIPT = "script"
SESSION = "session"


class Transport:
    """A position along a script that plays, pauses, seeks and loops."""

    def __init__(self) -> None:
        self.playing = False
        self.loop = False
        self._at = 0.0  # the position when last paused or sought
        self._since = 0.0  # the clock when it last started playing

    def position(self, now: float, duration: float) -> float:
        if not self.playing:
            return min(self._at, duration)
        t = self._at + (now - self._since)
        if t < duration:
            return t
        if self.loop and duration > 0:
            return t % duration
        return duration

    def play(self, now: float, duration: float) -> None:
        if self.playing:
            return
        if self._at >= duration:  # at the end: play starts again
            self._at = 0.0
        self.playing, self._since = True, now

    def pause(self, now: float, duration: float) -> None:
        self._at, self.playing = self.position(now, duration), False

    def seek(self, t: float, now: float, duration: float) -> None:
        self._at, self._since = max(0.0, min(t, duration)), now

    def set_loop(self, on: bool, now: float, duration: float) -> None:
        self._at, self._since, self.loop = self.position(now, duration), now, on

    def settle(self, now: float, duration: float) -> None:
        """Stop at the end of a script that does not loop."""
        if self.playing and not self.loop and self.position(now, duration) >= duration:
            self._at, self.playing = duration, False


class Preview:
    """The face the studio shows at any moment, and what the robot would be doing."""

    def __init__(
        self,
        seed: Optional[int] = None,
        idle: bool = True,
        recordings: Optional[Recordings] = None,
    ) -> None:
        """`recordings`: where `say file` reads, for the script and the presses alike (default: nowhere)."""
        self.recordings = recordings or Recordings(None)
        self.seed = random.randrange(2**31) if seed is None else seed
        self.idle = idle
        self.transport = Transport()
        self.mode = SCRIPT
        self._live = (0.0, 0.0)  # live: the position, and the clock then
        self.script = parse("", "<script>")
        self.animation = Animation(compile_script(self.script, self.seed), idle, self.seed)
        self.inputs: Tuple[Input, ...] = ()  # events fired and commands pressed, in the run's order
        self.commands = 0  # the commands among them
        self.counts: Dict[str, int] = {"runs": 0, "dropped": 0, "queued": 0}  # what its handlers did
        self.run: Any = None  # the script's run over them, kept to be continued (studio/event_run.py)

    # -- the script

    def load(self, script: Script) -> None:
        """Play `script` from where the transport is (MissingTool if it says something with no engine,
        RecordingError for a recording it cannot say)."""
        self.show(script, *self.prepare(script))

    def prepare(self, script: Script) -> Tuple[Animation, Dict[str, int], Any]:
        """The slow half of `load`, which changes nothing: compiled, speech synthesised, recordings
        read; run over the events fired and the commands pressed so far. The studio does it before
        taking the lock the frames wait on."""
        return reacting.animation(self, script, self.inputs)

    def show(
        self, script: Script, animation: Animation, counts: Optional[Dict[str, int]] = None, run: Any = None
    ) -> None:
        """The quick half: play a prepared script (and its run, when it reacts) from where the
        transport is."""
        self.animation, self.script, self.run = animation, script, run
        if counts is not None:
            self.counts = counts

    def took(self, t: float, now: float, live: bool) -> None:
        """The run took an input at `t`: it plays on from there, live after a command (and while
        live), else on the transport."""
        if live or self.mode == SESSION:
            self.transport.pause(now, self.duration)  # live: the transport waits where it was
            self.mode, self._live = SESSION, (t, now)
            return
        self.transport.seek(t, now, self.duration)
        self.transport.play(now, self.duration)

    def _off_live(self, now: float) -> None:
        """Back on the transport, where the live position has got to."""
        if self.mode == SESSION:
            t = self.position(now)
            self.mode = SCRIPT
            self.transport.seek(t, now, self.duration)

    @property
    def duration(self) -> float:
        return self.animation.duration

    def play(self, now: float) -> None:
        self._off_live(now)
        self.transport.play(now, self.duration)

    def pause(self, now: float) -> None:
        self._off_live(now)
        self.transport.pause(now, self.duration)

    def seek(self, t: float, now: float) -> None:
        self.mode = SCRIPT
        self.transport.seek(t, now, self.duration)

    def set_loop(self, on: bool, now: float) -> None:
        self.transport.set_loop(on, now, self.duration)

    # -- what is shown

    def position(self, now: float) -> float:
        if self.mode == SESSION:
            return self._live[0] + (now - self._live[1])
        self.transport.settle(now, self.duration)
        return self.transport.position(now, self.duration)

    def at(self, now: float) -> Tuple[float, FaceState, RobotStatus]:
        """The position, the face, and the robot's status at `now`."""
        t = self.position(now)
        return t, self.animation.sample(t), self.animation.timeline.status(t)

    def sounds(self, now: float) -> List[Dict[str, object]]:
        """What is heard now, to be played by the page from `at` (empty while paused)."""
        t = self.position(now)
        if self.mode == SCRIPT and not self.transport.playing:
            return []
        heard: List[Said] = self.animation.timeline.sounding(t)
        return [{"key": sound_key(said.utterance), "at": round(said.at, 3)} for said in heard]

    def utterance(self, key: str) -> Optional[Utterance]:
        """The utterance the session says whose sound is called `key`."""
        for said in self.animation.timeline.speech:
            if sound_key(said.utterance) == key:
                return said.utterance
        return None

    def _length(self, t: float) -> float:
        """How long what is shown is: the run's length, and live, the time so far (it goes on with
        the clock past its end)."""
        if self.mode == SESSION:
            return max(self.duration, t)
        return self.duration

    def status(self, now: float) -> dict:
        """The preview as the page shows it beside the face."""
        t, state, robot = self.at(now)
        saying = robot.speaking(t)
        return {
            "kind": "status",
            "mode": self.mode,
            "t": round(t, 3),
            "duration": round(self._length(t), 3),
            "playing": self.mode == SESSION or self.transport.playing,
            "loop": self.transport.loop,
            "sounds": self.sounds(now),
            "face": state.as_record(),
            "robot": {
                "head_pan_deg": round(math.degrees(state.head_pan), 1),
                "enabled": robot.enabled,
                "following": robot.following,
                "follow_dynamic": robot.follow_dynamic,
                "seen": None,
                "nodding": robot.nodding(t),
                "saying": saying,
                "exited": robot.exited,
            },
        }
