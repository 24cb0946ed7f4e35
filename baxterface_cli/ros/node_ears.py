"""The face node's ears: words heard by a microphone, or a recording played as one, raised as
`word "..."` events on a live session (the node's `_listen`, `stream --listen`).

`play --listen` hears with the same parts (speech/word_spotter.py, speech/sound_device.py); here
the phrases are not a script's, known at the start: they are those the handlers installed in the
session and the waits of its runs listen for, which change as handlers are sent live, so the
spotter is made again whenever they change (on the audio's own thread, never the frame loop).
A recording (`_listen:=hello.wav`) is fed in blocks of 50 ms at the pace a microphone gives them,
from the moment something listens for a word: how tests and benchmarks speak to the node.

The face does not hear itself: what it says is read from the timelines the session starts, as
`play` does, and a phrase heard while it spoke is ignored unless `barge_in`. Nothing here stops
the node: a missing extra, device or recording is said once, in one line, and the ears stay shut.
"""

from __future__ import annotations

import threading
import time
from typing import Any, Callable, List, Optional, Tuple

import numpy as np

from ..closing import ClosedOnExit
from ..engine.live_session import LiveSession
from ..engine.speaking_times import SpeakingTimes
from ..extras import MissingTool
from ..language import syntax_tree as n
from ..language.checker import phrases_listened
from ..language.events import MOST_HEARD

BLOCK = 0.05  # seconds of sound a block, as the microphone gives them
TRAILING_QUIET = 1.0  # seconds of silence after a recording: a phrase at its very end is decided
DEVICE = "default"  # `_listen:=default`: the default input device
Log = Callable[[str, str], None]  # (level, text)


def words_listened(session: LiveSession) -> List[str]:
    """The phrases the session's handlers, and the waits of its runs, listen for: once each. A
    run's own `on`s are not read: those installed are among the handlers (a later one may have
    replaced them)."""
    listening: List[Any] = [h.on for h in list(session.handlers)]  # swapped whole: no lock needed
    for run in (session.main, session.active):
        if run is not None:
            listening += [s for s in run.script.body if not isinstance(s, n.On)]
    return phrases_listened(listening)


class Ears(ClosedOnExit):
    """Sound in (a device or a recording), the words the session listens for out to `hear(event,
    at)` on the audio's thread, as `word` events (and `heard` ones, each utterance's words, where the
    listener tells them); `at` is when it ended, on `clock`."""

    def __init__(
        self,
        session: LiveSession,
        hear: Callable[[n.Event, float], None],
        source: str,
        barge_in: bool = False,
        log: Log = lambda level, text: None,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.session = session
        self.hear = hear
        self.source = source
        self.barge_in = barge_in
        self.log = log
        self.clock = clock
        self.spotter: Any = None
        self.words: List[str] = []
        self.unknown: List[str] = []  # phrases the model cannot spot, said once each
        self._over: List[str] = []  # phrases past LIMITS.max_phones, said when they change
        self.shut = False  # the extra is missing: no spotter is ever made
        self._seen: Tuple[Any, ...] = ()
        self._stop = threading.Event()
        self._thread: Optional[threading.Thread] = None
        self._microphone: Any = None
        self._said = SpeakingTimes()  # on `clock`

    # -- starting and stopping

    def start(self) -> Optional[str]:
        """Open the device, or start the recording's thread; why not, in one line, or None."""
        from ..speech.listening import check

        try:
            check()
        except MissingTool as e:
            self.shut = True
            return str(e)
        if self.source == DEVICE:
            from ..speech.sound_device import Microphone, MicrophoneError

            try:
                self._microphone = Microphone(lambda block: self._feed(block, None)).__enter__()
            except MicrophoneError as e:
                self.shut = True
                return str(e)
            return None
        from ..speech.audio_files import AudioError
        from ..speech.word_spotter import read_recording

        try:
            samples = read_recording(self.source)
        except AudioError as e:
            self.shut = True
            return f"cannot read {self.source}: {e}"
        self._thread = threading.Thread(
            target=self._play, args=(samples,), name="baxterface-ears", daemon=True
        )
        self._thread.start()
        return None

    def close(self) -> None:
        self._stop.set()
        if self._microphone is not None:
            self._microphone.__exit__(None, None, None)
        if self._thread is not None:
            self._thread.join(timeout=2.0)
        if self.spotter is not None:
            self.spotter.close()

    # -- the sound

    def _play(self, samples: np.ndarray) -> None:
        """The recording, a block each BLOCK seconds from when a word is first listened for."""
        from ..speech.word_spotter import RATE

        while self._current() is None:
            if self._stop.wait(BLOCK) or self.shut:
                return
        step = int(BLOCK * RATE)
        quiet = np.zeros(int(TRAILING_QUIET * RATE), np.int16)
        sound = np.concatenate([samples.astype(np.int16), quiet])
        start, wall = self.clock(), time.time()
        self.log(
            "info",
            f"listening to {self.source} as a microphone, {len(samples) / RATE:.2f} s of it, "
            f"from {wall:.3f} (seconds since the epoch)",
        )
        for index, at in enumerate(range(0, len(sound), step)):
            end = start + (index + 1) * BLOCK  # when the block's last sample has been heard
            if self._stop.wait(max(0.0, end - self.clock())):
                return
            self._feed(sound[at : at + step], end)
        self.log("info", f"{self.source} is heard to its end")

    def _feed(self, block: np.ndarray, end: Optional[float]) -> None:
        spotter = self._current()
        if spotter is None:
            return
        self._follow_speech()
        spotter.feed(block, end=end)

    def _heard(self, word: str, at: float) -> None:
        self.hear(n.Event("word", word), at)
        self.log("info", f'heard word "{word}", {self.clock() - at:.2f} s after it ended')

    def _heard_said(self, text: str, at: float) -> None:
        self.hear(n.Event("heard", text[:MOST_HEARD]), at)
        self.log("info", f'heard "{text}", {self.clock() - at:.2f} s after it ended')

    # -- the words

    def _current(self) -> Any:
        """The spotter for the phrases listened for now (made again when they changed); None when
        nothing listens for a word."""
        if self.shut:
            return None
        s = self.session
        seen = (s.handlers, s.main, s.active)  # each swapped whole when it changes
        if len(seen) == len(self._seen) and all(a is b for a, b in zip(seen, self._seen)):
            return self.spotter
        self._seen = seen
        words = [w for w in words_listened(s) if w not in self.unknown]
        if words == self.words:
            return self.spotter
        if self.spotter is not None:
            self.spotter.close()
            self.spotter = None
        self.words = words
        if words:
            self.spotter = self._spotter(words)
        return self.spotter

    def _spotter(self, words: List[str]) -> Any:
        from ..core.face_constants import LIMITS
        from ..speech.listening import listenable, listener

        try:
            kept, unknown, over = listenable(words)
        except MissingTool as e:
            self.shut = True
            self.log("error", f"no words are heard: {e}")
            return None
        for phrase, why in unknown:  # never listened for: said once
            self.unknown.append(phrase)
            self.log("warn", f'not listening for "{phrase}": {why}')
        if over and over != self._over:  # listened for once handlers before them go
            most = LIMITS.max_phones
            phrases = ", ".join(f'"{phrase}"' for phrase in over)
            self.log("warn", f"not listening for {phrases}: past {most} phones, every spelling counted")
        self._over = over
        if not kept:
            return None
        return listener(
            kept,
            self._heard,
            clock=self.clock,
            speaking=self.speaking,
            barge_in=self.barge_in,
            on_heard=self._heard_said,
            saying=self._said.saying,
        )

    # -- what the face says

    def _follow_speech(self) -> None:
        """A timeline begun since the last block: its speech is what the face says from now on."""
        face = self.session.face
        self._said.follow(face.timeline, face.started, self.clock())

    def speaking(self, at: float) -> bool:
        """Was the face speaking at `at`? For the spotter, on the audio's thread."""
        return self._said.speaking(at)
