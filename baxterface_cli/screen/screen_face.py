"""The face every screen shows: one live session (engine/live_session.py), without ROS and without the web.

A script plays first, from when the first page opens (a command that comes
before takes over instead); then idle life, and each command takes over from
the face as it is, as on the node's display_chatter. A script or command with
handlers (`on EVENT { }`) installs them, and events (`post`: `POST /api/event`,
a tap on the page) run them by their policies; a command with only `signal`s
raises them. The clock is passed in. What the face says is listed in the
status for the pages to play, and its sound is kept by key for them to fetch.

A script that reacts to nothing, while no handler is installed, is compiled
whole and played as `render` plays it (the same frames); anything else goes
through the session, statement by statement, so a handler can pause it.

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
from ..engine.session_program import first_reacting
from ..engine.timeline import Timeline
from ..language import syntax_tree as n
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
        # Compiled now, so a script that cannot play (`say` without espeak-ng) stops the start; one
        # that reacts is run by the session when the first page opens, a statement at a time.
        self._first: Optional[Timeline] = None
        self._first_reacting: Optional[Script] = None
        if script is not None and first_reacting(script) is not None:
            self._first_reacting = script
        elif script is not None:
            self._first = self.live.prepare(script, FaceState())
        self._first_script = script
        self._sounds: OrderedDict[str, Utterance] = OrderedDict()
        self._heard: Optional[Timeline] = None  # the timeline whose sounds were kept last

    def close(self) -> None:
        self.intake.close()

    def _plain(self, script: Script) -> bool:
        """Is `script` played whole, as before the session: nothing in it or in the session reacts?"""
        return not self.session.handlers and self.session.free and first_reacting(script) is None

    def _begin(self, timeline: Timeline, now: float) -> None:
        self._first = self._first_reacting = None
        self.live.begin(timeline, now)
        self._keep_sounds()

    def _recorded(self, script: Optional[Script], at: float) -> None:
        """A script played whole, not through the intake, in the session's log file."""
        if self.record is not None and script is not None:
            self.record.script(at, script.source, script.filename)

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
            if self._first is not None:
                self._recorded(self._first_script, self.clock())
                self._begin(self._first, self.clock())
            elif self._first_reacting is not None:
                script, self._first_reacting = self._first_reacting, None
                # Called in the server's loop: its first steps are compiled on the intake's worker.
                self.intake.take(script).add_done_callback(self._handed)

    def command(self, text: str, filename: str = "command") -> Dict[str, Any]:
        """Play `text` from now, taking over from what plays (its handlers installed, its signals
        raised); ScriptError (or MissingTool) if it cannot."""
        script = parse(text, filename)
        self.intake.settled()  # what came before (the first script, events) is in the session first
        now = self.clock()
        if self._plain(script):
            # Compiled without the lock, which every frame needs; from the face as it is now.
            timeline = self.live.take_over(script, now)
            with self.lock:
                if self._plain(script):
                    self._recorded(script, now)
                    self._begin(timeline, now)
                    return {"duration": round(timeline.duration, 3)}
        with self.lock:
            self._first = self._first_reacting = None
        self.intake.take(script).result()  # compiled on the worker; this thread waits, frames do not
        installed = [in_words(s.event) for s in script.body if isinstance(s, n.On)]
        return {"reacting": True, "installed": installed, "handlers": len(self.session.handlers)}

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

    def status(self, now: float) -> Dict[str, Any]:
        """What the pages need beside the frames: the position in what plays, and what is heard now."""
        timeline, started = self.live.playing
        t = now - started
        heard = [{"key": sound_key(s.utterance), "at": round(s.at, 3)} for s in timeline.sounding(t)]
        return {"kind": "status", "t": round(t, 3), "playing": True, "sounds": heard}

    def state(self) -> Dict[str, Any]:
        """The face and what it is doing, for `GET /api/state`: once what was sent before is in."""
        self.intake.settled(SETTLING)
        now = self.clock()
        self.step(now)
        face = self.face(now)
        with self.lock:
            timeline, started, robot = self.live.timeline, self.live.started, self.live.robot
            waiting = self._first is not None or self._first_reacting is not None
            reacting = self._reacting()
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
