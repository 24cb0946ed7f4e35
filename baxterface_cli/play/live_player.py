"""A script that reacts, played live: `play --listen`, or a script with handlers in a window.

The live session (engine/live_session.py) runs on the player's clock, ticked a frame at a time.
Events come as they happen: words from the microphone (a WordSpotter on the microphone's
thread, whose words wait in a queue for the next frame), touches from clicks in the window (the
place found on the face as it was shown: drawing/touch_places.py), and an events file's lines at
their times. What the face says is heard: each timeline the session starts has its speech
started on the sound device, and whatever it cuts short falls silent.
"""

from __future__ import annotations

import contextlib
import queue
import time
from typing import Any, Callable, Optional, Tuple

from ..core.face_state import FaceState
from ..drawing.renderer import Renderer
from ..drawing.touch_places import touched_place
from ..engine.live_session import LiveSession
from ..engine.session_log_file import SessionLogFile
from ..engine.speaking_times import SpeakingTimes
from ..language import syntax_tree as n
from ..language.events import MOST_HEARD
from ..speech.sound_device import SoundOut, SpeechCues
from .player import status_line

Clock = Callable[[], float]


class LivePlayer:
    """Frames of a live session on a screen, in real time, with the events that reach it."""

    def __init__(
        self,
        session: LiveSession,
        renderer: Renderer,
        screen: Any,
        fps: float = 30.0,
        trace: Any = None,
        duration: Optional[float] = None,
        clock: Clock = time.monotonic,
        sleep: Callable[[float], None] = time.sleep,
        sound: Optional[Callable[[], SoundOut]] = None,
        record: Optional[SessionLogFile] = None,
    ) -> None:
        """`record`: the session's log file, told of each event and the session's lines as the
        frames take them (it only queues them: its own thread writes)."""
        self.session = session
        self.record = record
        if record is not None:  # its lines from the first (a session made with its script has some)
            record.watch(session.face)
        self.renderer = renderer
        self.screen = screen
        self.fps = fps
        self.trace = list(trace.events) if trace is not None else []
        self.source = trace.source if trace is not None else (lambda posted: "")
        self.duration = duration
        self.clock = clock
        self.sleep = sleep
        self.open_sound = sound
        self.sound: Optional[SoundOut] = None
        self.inbox: queue.Queue[Tuple[n.Event, Optional[float], str]] = queue.Queue(maxsize=1000)
        self.origin: Optional[float] = None
        self.frames_shown = 0
        self.position = 0.0
        self.note = ""
        self._state: Optional[FaceState] = None
        self._cues: Optional[SpeechCues] = None
        self._said = SpeakingTimes()  # on the player's clock
        if hasattr(screen, "on_click"):
            screen.on_click(self.touch)

    # -- events in (any thread)

    def now(self) -> float:
        """Seconds since the show began (0 before): the session's clock, and the spotter's."""
        return 0.0 if self.origin is None else self.clock() - self.origin

    def hear(self, word: str, at: float) -> None:
        """A word heard, ending at `at` (the player's clock): the spotter's `on_word`."""
        self._put(n.Event("word", word), at, "microphone")

    def hear_said(self, text: str, at: float) -> None:
        """A whole utterance heard, ending at `at`: the listener's `on_heard`."""
        self._put(n.Event("heard", text[:MOST_HEARD]), at, "microphone")

    def touch(self, x: float, y: float) -> None:
        """A click at (x, y), fractions of the picture's width and height."""
        state = self._state
        place = touched_place(self.renderer.layers, state, x, y) if state is not None else ""
        self._put(n.Event("touch", place), None, "window")

    def speaking(self, at: float) -> bool:
        """Was the face speaking at `at` (the player's clock)? For the spotter, on its thread."""
        return self._said.speaking(at)

    def saying(self, start: float, end: float) -> str:
        """What the face said between `start` and `end`: for the listener, with barge-in."""
        return self._said.saying(start, end)

    def _put(self, event: n.Event, at: Optional[float], source: str) -> None:
        with contextlib.suppress(queue.Full):  # a storm beyond what the frames keep up with is lost
            self.inbox.put_nowait((event, at, source))

    # -- the show

    def run(self) -> float:
        """Play until the window closes, `duration` passes or the face exits; the seconds played."""
        self.origin = self.clock()
        index = 0
        try:
            while self.screen.alive():
                t = max(index / self.fps, self.now())  # a late frame is dropped, not shown late
                if self.duration is not None:
                    t = min(t, self.duration)
                index = int(t * self.fps + 1e-9)
                self._post_due(index / self.fps)
                self._show(index / self.fps)
                if self.session.exited or (self.duration is not None and t >= self.duration):
                    break
                index += 1
                wait = self.origin + index / self.fps - self.clock()
                if wait > 0:
                    self.sleep(wait)
        finally:
            if self.sound is not None:
                self.sound.stop()
        return self.now()

    def _post_due(self, t: float) -> None:
        while self.trace and self.trace[0].at <= t:
            posted = self.trace.pop(0)
            self._post(posted.event, posted.at, self.source(posted))
        while True:
            try:
                event, at, source = self.inbox.get_nowait()
            except queue.Empty:
                return
            self._post(event, t if at is None else min(at, t), source)

    def _post(self, event: n.Event, at: float, source: str) -> None:
        if self.record is not None:
            self.record.event(at, event, source)
        self.session.post(event, at, source)

    def _show(self, t: float) -> None:
        self.position = t
        state, _ = self.session.tick(t)
        if self.record is not None:
            self.record.follow(self.session)
        self._state = state
        self._follow_speech(t)
        face = self.session.face
        length = self.duration if self.duration is not None else t
        status = status_line(t, length, face.robot, state.head_pan, self.note)
        self.screen.show(self.renderer.render(state), status)
        self.frames_shown += 1

    def _follow_speech(self, t: float) -> None:
        """A timeline begun since the last frame: its speech is what the face says from now on."""
        face = self.session.face
        timeline, started = face.timeline, face.started
        if not self._said.follow(timeline, started, t):
            if self._cues is not None:
                self._cues.tick(self.clock())
            return
        if self.sound is not None:
            self.sound.stop()
        self._cues = None
        if timeline.speech and self.open_sound is not None:
            if self.sound is None:
                self.sound = self.open_sound()
            assert self.origin is not None
            self._cues = SpeechCues(self.sound, timeline.speech, self.origin + started)
            self._cues.tick(self.clock())
