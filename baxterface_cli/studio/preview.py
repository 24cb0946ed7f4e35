"""What the studio's preview shows: the editor's script on a transport, or the live session.

Two sources, one face. The script plays, pauses, seeks and loops along its
own timeline; a press switches the preview to the session, whose face
carries on under the presses (see `presses.py`); pressing play switches back.
No clock inside: every call is given `now`, so it is all tested without
waiting.
"""

from __future__ import annotations

import math
from typing import Any, Dict, List, Optional, Tuple

from ..core.face_state import FaceState
from ..engine.animation import Animation
from ..engine.compiler import compile_script
from ..engine.effects import RobotStatus
from ..engine.timeline import Said
from ..language.event_trace import Posted
from ..language.parser import parse
from ..language.syntax_tree import Script
from ..speech.recordings import Recordings
from ..speech.synthesis import Utterance
from ..web.sounds import sound_key
from . import reacting
from .presses import Pending, Presses

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
        filename: str = "session.face",
        recordings: Optional[Recordings] = None,
    ) -> None:
        """`recordings`: where `say file` reads, for the script and the presses alike (default: nowhere)."""
        self.recordings = recordings or Recordings(None)
        self.presses = Presses(seed, filename, self.recordings)
        self.seed = self.presses.seed
        self.idle = idle
        self.transport = Transport()
        self.mode = SCRIPT
        self.script = parse("", "<script>")
        self.animation = Animation(compile_script(self.script, self.seed), idle, self.seed)
        self.events: List[Posted] = []  # fired by hand at the script (studio/reacting.py)
        self.counts: Dict[str, int] = {"runs": 0, "dropped": 0, "queued": 0}  # what its handlers did
        self.run: Any = None  # the script's run over them, kept to be continued (studio/event_run.py)
        self._presses_animation = Animation(self.presses.timeline, idle, self.seed)

    # -- the script

    def load(self, script: Script) -> None:
        """Play `script` from where the transport is (MissingTool if it says something with no engine,
        RecordingError for a recording it cannot say)."""
        self.show(script, *self.prepare(script))

    def prepare(self, script: Script) -> Tuple[Animation, Dict[str, int], Any]:
        """The slow half of `load`, which changes nothing: compiled, speech synthesised, recordings
        read; a script that reacts, run over the events fired so far. The studio does it before
        taking the lock the frames wait on."""
        return reacting.animation(self, script, list(self.events))

    def show(
        self, script: Script, animation: Animation, counts: Optional[Dict[str, int]] = None, run: Any = None
    ) -> None:
        """The quick half: play a prepared script (and its run, when it reacts) from where the
        transport is."""
        self.animation, self.script, self.run = animation, script, run
        if counts is not None:
            self.counts = counts

    def fired(self, t: float, now: float) -> None:
        """An event was fired at `t`: the script plays on from there, with it."""
        self.mode = SCRIPT
        self.transport.seek(t, now, self.duration)
        self.transport.play(now, self.duration)

    @property
    def duration(self) -> float:
        return self.animation.duration

    def play(self, now: float) -> None:
        self.mode = SCRIPT
        self.transport.play(now, self.duration)

    def pause(self, now: float) -> None:
        self.transport.pause(now, self.duration)

    def seek(self, t: float, now: float) -> None:
        self.mode = SCRIPT
        self.transport.seek(t, now, self.duration)

    def set_loop(self, on: bool, now: float) -> None:
        self.transport.set_loop(on, now, self.duration)

    # -- the session

    def press(self, text: str, now: float) -> float:
        """Play `text` now, in the session; its time there. ScriptError when it is bad."""
        return self.take_press(self.prepare_press(text, now), now)

    def prepare_press(self, text: str, now: float) -> Tuple[Pending, Animation]:
        """The slow half of a press, which changes nothing (see `Session.prepare`)."""
        pending = self.presses.prepare(text, now)
        return pending, Animation(pending.part.timeline, self.idle, self.seed)

    def take_press(self, prepared: Tuple[Pending, Animation], now: float) -> float:
        """The quick half: the prepared press shown from now. Stale if the session moved on."""
        pending, animation = prepared
        at = self.presses.take(pending)
        self._presses_animation = animation
        if self.mode == SCRIPT:
            self.transport.pause(now, self.duration)
        self.mode = SESSION
        return at

    def clear_session(self) -> None:
        self.presses.clear()
        self._presses_animation = Animation(self.presses.timeline, self.idle, self.seed)

    # -- what is shown

    def position(self, now: float) -> float:
        if self.mode == SESSION:
            return self.presses.position(now)
        self.transport.settle(now, self.duration)
        return self.transport.position(now, self.duration)

    def _shown(self) -> Tuple[Animation, float]:
        """What is shown, and where its time 0 is on the position's: the session plays in parts."""
        if self.mode == SESSION:
            return self._presses_animation, self.presses.part.offset
        return self.animation, 0.0

    def at(self, now: float) -> Tuple[float, FaceState, RobotStatus]:
        """The position, the face, and the robot's status at `now` (its times the position's)."""
        animation, offset = self._shown()
        t = self.position(now)
        if self.mode == SESSION:
            part = self.presses.part
            robot = animation.timeline.status(t - offset, part.robot)
            # The part's own times, moved onto the session's.
            robot = robot._replace(
                nodding_until=robot.nodding_until + offset, saying_until=robot.saying_until + offset
            )
            return t, animation.sample(t - offset), robot
        return t, animation.sample(t), animation.timeline.status(t)

    def sounds(self, now: float) -> List[Dict[str, object]]:
        """What is heard now, to be played by the page from `at` (empty while paused)."""
        t = self.position(now)
        if self.mode == SCRIPT and not self.transport.playing:
            return []
        animation, offset = self._shown()
        heard: List[Said] = animation.timeline.sounding(t - offset)
        return [{"key": sound_key(said.utterance), "at": round(said.at + offset, 3)} for said in heard]

    def utterance(self, key: str) -> Optional[Utterance]:
        """The utterance of the script or the session whose sound is called `key`."""
        for animation in (self.animation, self._presses_animation):
            for said in animation.timeline.speech:
                if sound_key(said.utterance) == key:
                    return said.utterance
        return None

    def _length(self, t: float) -> float:
        """How long what is shown is: the script's length, or the session's so far (it goes on
        with the clock past its last press's end)."""
        if self.mode == SESSION:
            return max(self.presses.duration, t)
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
