"""The face every screen shows: the face node's live face, without ROS and without the web.

A script plays first, from when the first page opens (a command that comes
before takes over instead); then idle life, and each command takes over from
the face as it is, as on the node's display_chatter. The clock is passed in.
What the face says is listed in the status for the pages to play, and its
sound is kept by key for them to fetch.
"""

from __future__ import annotations

import threading
import time
from collections import OrderedDict
from typing import Any, Callable, Dict, Optional

from ..core.face_state import FaceState
from ..engine.live_face import LiveFace
from ..engine.timeline import Timeline
from ..language.parser import parse
from ..language.syntax_tree import Script
from ..speech.synthesis import Utterance
from ..web.sounds import sound_key, wav_file

KEPT_SOUNDS = 32  # utterances whose sound a page may still ask for


class ScreenFace:
    """What the screens show; every method may be called from any thread."""

    def __init__(
        self,
        script: Optional[Script] = None,
        seed: Optional[int] = None,
        idle: bool = True,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.clock = clock
        self.lock = threading.Lock()
        self.live = LiveFace(start=FaceState(), idle=idle, seed=seed, now=clock())
        self.name = script.filename if script is not None else None
        # Compiled now, so a script that cannot play (`say` without espeak-ng) stops the start.
        self._first: Optional[Timeline] = None if script is None else self.live.prepare(script, FaceState())
        self._sounds: OrderedDict[str, Utterance] = OrderedDict()

    def _begin(self, timeline: Timeline, now: float) -> None:
        self._first = None
        self.live.begin(timeline, now)
        for said in timeline.speech:
            self._sounds[sound_key(said.utterance)] = said.utterance
            self._sounds.move_to_end(sound_key(said.utterance))
        while len(self._sounds) > KEPT_SOUNDS:
            self._sounds.popitem(last=False)

    def open(self) -> None:
        """A page shows the face: the script starts, if nothing has yet."""
        with self.lock:
            if self._first is not None:
                self._begin(self._first, self.clock())

    def command(self, text: str, filename: str = "command") -> Dict[str, Any]:
        """Play `text` from now, taking over from what plays; ScriptError (or MissingTool) if it cannot."""
        script = parse(text, filename)
        now = self.clock()
        # Compiled without the lock, which every frame needs; from the face as it is now.
        timeline = self.live.take_over(script, now)
        with self.lock:
            self._begin(timeline, now)
        return {"duration": round(timeline.duration, 3)}

    def face(self) -> FaceState:
        """The face to show now."""
        with self.lock:
            now = self.clock()
            self.live.due(now)  # the robot's status (following stops the darts), as on the node
            return self.live.state(now)

    def status(self) -> Dict[str, Any]:
        """What the pages need beside the frames: the position in what plays, and what is heard now."""
        with self.lock:
            timeline, started = self.live.timeline, self.live.started
            now = self.clock()
        t = now - started
        heard = [{"key": sound_key(s.utterance), "at": round(s.at, 3)} for s in timeline.sounding(t)]
        return {"kind": "status", "t": round(t, 3), "playing": True, "sounds": heard}

    def state(self) -> Dict[str, Any]:
        """The face and what it is doing, for `GET /api/state`."""
        face = self.face()
        with self.lock:
            timeline, started, robot = self.live.timeline, self.live.started, self.live.robot
            now = self.clock()
            waiting = self._first is not None
        t = now - started
        heard = timeline.sounding(t)
        return {
            "script": self.name,
            "waiting": waiting,  # the script waits for the first page
            "t": round(t, 3),
            "duration": round(timeline.duration, 3),
            "playing": t < timeline.duration,
            "saying": heard[-1].utterance.text if heard else None,
            "sounds": [{"key": sound_key(s.utterance), "at": round(s.at, 3)} for s in heard],
            "following": robot.following,
            "face": face.as_record(),
        }

    def sound(self, key: str) -> Optional[bytes]:
        """The WAV file of an utterance said lately (None for any other key)."""
        with self.lock:
            utterance = self._sounds.get(key)
        if utterance is None:
            return None
        return wav_file(utterance)
