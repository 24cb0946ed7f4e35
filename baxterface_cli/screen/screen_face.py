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
"""

from __future__ import annotations

import threading
import time
from collections import OrderedDict
from typing import Any, Callable, Dict, List, Optional

from ..core.face_state import FaceState
from ..engine.live_session import LiveSession
from ..engine.session_program import first_reacting
from ..engine.timeline import Timeline
from ..language import syntax_tree as n
from ..language.events import in_words
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
        self.session = LiveSession(None, seed=seed, now=clock(), start=FaceState(), idle=idle)
        self.live = self.session.face
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
        self._sounds: OrderedDict[str, Utterance] = OrderedDict()
        self._heard: Optional[Timeline] = None  # the timeline whose sounds were kept last

    def _plain(self, script: Script) -> bool:
        """Is `script` played whole, as before the session: nothing in it or in the session reacts?"""
        main = self.session.main
        return not self.session.handlers and (main is None or main.done) and first_reacting(script) is None

    def _begin(self, timeline: Timeline, now: float) -> None:
        self._first = self._first_reacting = None
        self.live.begin(timeline, now)
        self._keep_sounds()

    def _run(self, script: Script, now: float) -> None:
        self._first = self._first_reacting = None
        self.session.run(script, now)
        self._keep_sounds()

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
                self._begin(self._first, self.clock())
            elif self._first_reacting is not None:
                self._run(self._first_reacting, self.clock())

    def command(self, text: str, filename: str = "command") -> Dict[str, Any]:
        """Play `text` from now, taking over from what plays (its handlers installed, its signals
        raised); ScriptError (or MissingTool) if it cannot."""
        script = parse(text, filename)
        now = self.clock()
        if self._plain(script):
            # Compiled without the lock, which every frame needs; from the face as it is now.
            timeline = self.live.take_over(script, now)
            with self.lock:
                if self._plain(script):
                    self._begin(timeline, now)
                    return {"duration": round(timeline.duration, 3)}
        with self.lock:
            self._run(script, self.clock())
            installed = [in_words(s.event) for s in script.body if isinstance(s, n.On)]
            return {"reacting": True, "installed": installed, "handlers": len(self.session.handlers)}

    def post(self, event: n.Event, source: str = "") -> Dict[str, Any]:
        """An event now: a `wait until` it ends, its handlers run by their policies. What it did,
        as the handlers' counts moved."""
        with self.lock:
            before = _totals(self.session)
            self.events += 1
            self.session.post(event, self.clock(), source)
            self._keep_sounds()
            after = _totals(self.session)
        moved = {k: after[k] - before[k] for k in after}
        return {"event": in_words(event), **moved}

    def face(self) -> FaceState:
        """The face to show now."""
        with self.lock:
            # The robot's status (following stops the darts) is folded in by the tick, as on the node.
            state, _ = self.session.tick(self.clock())
            self._keep_sounds()
            return state

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
            "queued": len(session.pending),  # events waiting for their handler's turn now
            "events": self.events,
            "dropped": sum(h["dropped"] for h in handlers),
            "exited": session.exited,
        }

    def sound(self, key: str) -> Optional[bytes]:
        """The WAV file of an utterance said lately (None for any other key)."""
        with self.lock:
            utterance = self._sounds.get(key)
        if utterance is None:
            return None
        return wav_file(utterance)


def _totals(session: LiveSession) -> Dict[str, int]:
    counts = session.counts().values()
    return {key: sum(c[key] for c in counts) for key in ("runs", "dropped", "queued")}
