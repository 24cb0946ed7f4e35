"""The face every screen shows: one live session (engine/live_session.py), without ROS and without the web.

A script plays first, from when the first page opens (a command that comes
before takes over instead); then idle life, and each command takes over from
the face as it is, as on the node's display_chatter. A script or command with
handlers (`on EVENT { }`) installs them, and events (`post`: `POST /api/event`,
a tap on the page) run them by their policies; a command with only `signal`s
raises them. The clock is passed in. What the face says is listed in the
status for the pages to play, and its sound is kept by key for them to fetch.

Every script and command, reacting or not, goes through the session, statement
by statement, as on the node and in `render`: the same frames for the same seed.

The session is advanced as the face node's is: by its intake's worker
(engine/session_intake.py), which compiles each step (a `say` waits for
espeak-ng), while the frame pump lets time pass with `step` (`LiveSession.catch_up`,
which never compiles and never waits) and reads the face with `face(now)`. A
request that must answer what it did waits for the worker, on its own thread;
the lock here guards only what is quick.
"""

from __future__ import annotations

import threading
import time
from collections import OrderedDict
from concurrent.futures import Future
from typing import Any, Callable, Dict, List, Optional, Tuple

from ..core.face_state import FaceState
from ..engine.live_session import LiveSession
from ..engine.session_intake import SessionIntake
from ..engine.session_log_file import SessionLogFile
from ..engine.timeline import Timeline
from ..language import syntax_tree as n
from ..language.checker import walk
from ..language.events import in_words
from ..language.parser import parse
from ..language.syntax_tree import Script
from ..speech.synthesis import Utterance
from ..web.sounds import sound_key, wav_file

KEPT_SOUNDS = 32  # utterances whose sound a page may still ask for
SETTLING = 10.0  # seconds `GET /api/state` waits for what was sent before it (else: as it is)


class ScreenFace:
    """What the screens show; every method may be called from any thread."""

    def __init__(
        self,
        script: Optional[Script] = None,
        seed: Optional[int] = None,
        idle: bool = True,
        clock: Callable[[], float] = time.monotonic,
        log_file: Optional[Tuple[str, int, Dict[str, Any]]] = None,
    ) -> None:
        """`log_file`: (its path, its size before it rotates, the settings) for the session's log."""
        self.clock = clock
        self.origin = clock()  # the screen's start: `t` in the status counts from it, as in the log
        self.lock = threading.Lock()
        self.session = LiveSession(None, seed=seed, now=clock(), start=FaceState(), idle=idle, keep_up=True)
        self.live = self.session.face
        self.ready: Callable[[], None] = lambda: None  # the server's: a step began, draw it now
        self.log: Callable[[str], None] = lambda text: None  # the server's log
        said = lambda _, text: self.log(text)  # noqa: E731 - (level, text): the server's log is one level
        woken = lambda: self.ready()  # noqa: E731 - set by the server after this
        self.record: Optional[SessionLogFile] = None
        if log_file is not None:
            path, size, settings = log_file
            self.record = SessionLogFile(path, clock(), settings, lambda text: self.log(text), size)
        self.intake = SessionIntake(
            self.session, clock, ready=woken, log=said, filename="command", record=self.record
        )
        self.name = script.filename if script is not None else None
        self.events = 0  # posted, whether a handler took them or not
        if script is not None and any(isinstance(s, n.Say) and s.file is None for s in walk(script.body)):
            from ..speech.espeak import espeak_library

            espeak_library()  # MissingTool now: a script that cannot speak stops the start, not the page
        self._first = script  # run by the session when the first page opens
        self._sounds: OrderedDict[str, Utterance] = OrderedDict()
        self._heard: Optional[Timeline] = None  # the timeline whose sounds were kept last

    def close(self) -> None:
        self.intake.close()

    def _handed(self, done: Future) -> None:
        """The first script, handed over when the first page opened: a failure is logged."""
        if not done.cancelled() and done.exception() is not None:
            self.log(f"the script: {done.exception()}")

    def _keep_sounds(self) -> None:
        """Keep the sounds of what the face plays now, for the pages to fetch by key (under the lock)."""
        timeline = self.live.timeline
        if timeline is self._heard:
            return
        self._heard = timeline
        for said in timeline.speech:
            self._sounds[sound_key(said.utterance)] = said.utterance
            self._sounds.move_to_end(sound_key(said.utterance))
        while len(self._sounds) > KEPT_SOUNDS:
            self._sounds.popitem(last=False)

    def open(self) -> None:
        """A page shows the face: the script starts, if nothing has yet."""
        with self.lock:
            script, self._first = self._first, None
        if script is not None:  # called in the server's loop: its steps are compiled on the intake's worker
            self.intake.take(script).add_done_callback(self._handed)

    def command(self, text: str, filename: str = "command") -> Dict[str, Any]:
        """Play `text` from now, taking over from what plays (its handlers installed, its signals
        raised); ScriptError (or MissingTool) if it cannot."""
        script = parse(text, filename)
        with self.lock:
            self._first = None  # a command before the first page: the script never comes
        self.intake.take(script).result()  # compiled on the worker; this thread waits, frames do not
        installed = [in_words(s.event) for s in script.body if isinstance(s, n.On)]
        return {"installed": installed, "handlers": len(self.session.handlers)}

    def posting(self, event: n.Event, source: str = "") -> Future:
        """An event now: a `wait until` it ends, its handlers run by their policies. A future: what
        it did, as the handlers' counts moved (intake's Refused if too many wait)."""
        with self.lock:
            self.events += 1
        return self.intake.posting(event, source)

    def post(self, event: n.Event, source: str = "") -> Dict[str, Any]:
        """`posting`, waited for: the event and what it did."""
        return {"event": in_words(event), **self.posting(event, source).result()}

    def step(self, now: float) -> None:
        """Time passes to `now` (the frame pump's, each turn): the robot's status takes the cues due
        (following stops the darts, as on the node), the sounds of a step the worker began are kept."""
        with self.lock:
            self.session.catch_up(now)
            self._keep_sounds()

    def face(self, now: float) -> FaceState:
        """The face at `now`: a read, which moves no clock and takes no cue (`step` does). Never
        waits for a step being compiled (the intake's worker takes them): the face plays on."""
        return self.live.state(now)

    def _sounding(self, now: float) -> List[Dict[str, Any]]:
        """What is heard at `now`: each sound's key and its start, on the status's clock."""
        timeline, started = self.live.playing
        heard = timeline.sounding(now - started)
        return [{"key": sound_key(s.utterance), "at": round(started + s.at - self.origin, 3)} for s in heard]

    def status(self, now: float) -> Dict[str, Any]:
        """What the pages need beside the frames: the time since the screen started, and what is
        heard now, its start on that clock (a page plays a sound from `t - at`)."""
        t = round(now - self.origin, 3)
        return {"kind": "status", "t": t, "playing": True, "sounds": self._sounding(now)}

    def state(self) -> Dict[str, Any]:
        """The face and what it is doing, for `GET /api/state`: once what was sent before is in."""
        self.intake.settled(SETTLING)
        now = self.clock()
        self.step(now)
        face = self.face(now)
        with self.lock:
            robot, waiting, reacting = self.live.robot, self._first is not None, self._reacting()
            playing = not self.session.free or not self.live.finished(now)  # a run, or its last step
        timeline, started = self.live.playing
        heard = timeline.sounding(now - started)
        return {
            "script": self.name,
            "waiting": waiting,  # the script waits for the first page
            "t": round(now - self.origin, 3),
            "playing": playing,
            "saying": heard[-1].utterance.text if heard else None,
            "sounds": self._sounding(now),
            "following": robot.following,
            "face": face.as_record(),
            **reacting,
        }

    def _reacting(self) -> Dict[str, Any]:
        """The handlers and their counts, for `GET /api/state` (under the lock)."""
        session = self.session
        handlers: List[Dict[str, Any]] = [
            {
                "on": in_words(h.on.event),
                "line": h.on.pos.line,
                "policy": h.on.policy,
                "cooldown": h.on.cooldown,
                "runs": h.runs,
                "dropped": h.dropped,
                "queued": h.queued,
            }
            for h in session.handlers
        ]
        return {
            "handlers": handlers,
            "running": session.active.label if session.active is not None else None,
            "state": session.states.current,
            "queued": len(session.pending),  # events waiting for their handler's turn now
            "events": self.events,
            "dropped": sum(h["dropped"] for h in handlers),
            "exited": session.exited,
        }

    def sound(self, key: str) -> Optional[bytes]:
        """The WAV file of an utterance said lately (None for any other key)."""
        with self.lock:
            self._keep_sounds()
            utterance = self._sounds.get(key)
        if utterance is None:
            return None
        return wav_file(utterance)
