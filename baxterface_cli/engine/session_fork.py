"""A copy of a live session that goes on by itself: a checkpoint to continue a run from.

The studio keeps its run of a script over the events fired so far (studio/event_run.py) at the
last event, and continues a copy of it with the next one, rather than running the script again
over all of them: the same calls on an exact copy make the same timelines, to the bit, as
`render --events` does in one go.

What is copied is what the session changes as it runs: its handlers' counts, the runs' places in
their bodies, the queue, the clock, its random streams. What it only reads is shared: the
scripts, the compiled timelines, the recordings. The copy starts with an empty log and records
its own timelines from the moment of the copy (`segments`), so that a run kept for an hour does
not copy its history at every event.
"""

from __future__ import annotations

import copy
import dataclasses
import random
import threading
from collections import deque
from typing import Dict, List, Optional

from ..language import syntax_tree as n
from .effects import StatusFold
from .live_face import LiveFace
from .live_session import LiveSession
from .session_handlers import by_kind, install
from .session_program import Runner, _Frame
from .session_records import Handler, Run, SessionLog

# Every attribute a session has, so that one added to it later is not silently left shared.
_SESSION = {
    "lock", "face", "rng", "recordings", "crossfade", "clock", "handlers", "main", "active", "pending",
    "log", "segments", "cues", "exited", "ignored", "last_event", "_idle_fired", "_every",
    "_starts", "steps", "exited_at", "_kinds", "keep_up", "_behind", "_driving", "states",
}  # fmt: skip
_FACE = {"rng", "recordings", "idle_on", "_robot", "pending", "_playing", "begun"}
_RUN = {"runner", "script", "label", "handler", "playing", "exiting", "waiting", "done", "carry"}
_RUNNER = {"definitions", "rng", "frames", "again", "_holding"}


class CannotFork(Exception):
    """The session holds state a copy would share: a bug to fix here, not a user's mistake."""


def _same_fields(thing: object, known: set) -> None:
    found = set(vars(thing))
    if found != known:
        raise CannotFork(f"{type(thing).__name__} has fields {sorted(found ^ known)} this copy does not know")


def _random(rng: random.Random) -> random.Random:
    twin = random.Random()
    twin.setstate(rng.getstate())
    return twin


def fork(session: LiveSession) -> LiveSession:
    """An exact copy of `session` that goes on without changing it (see the module's docstring).
    Only a session without idle life (a recorded run's) is copied."""
    with session.lock:
        _same_fields(session, _SESSION)
        twin = copy.copy(session)
        twin.lock = threading.RLock()
        twin.face = _face(session.face)
        twin.rng = _random(session.rng)
        handlers: Dict[int, Handler] = {}

        def handler(h: Optional[Handler]) -> Optional[Handler]:
            if h is None:
                return None
            if id(h) not in handlers:  # a replaced handler may still run or wait in the queue
                handlers[id(h)] = copy.copy(h)
            return handlers[id(h)]

        twin.handlers = [handler(h) for h in session.handlers]  # type: ignore[misc]
        twin._kinds = by_kind(twin.handlers)
        twin.main = _run(session.main, handler, twin.rng)
        twin.active = _run(session.active, handler, twin.rng)
        twin.pending = deque((handler(h), event) for h, event in session.pending)
        twin.log = SessionLog(session.log.maxlen)
        twin.segments = None if session.segments is None else []
        twin.cues = list(session.cues)
        twin._idle_fired = set(session._idle_fired)
        twin._every = session._every.copy()
        twin.states = session.states.copy()
        twin._starts = copy.copy(session._starts)
        return twin


def rebase(session: LiveSession, script: n.Script) -> LiveSession:
    """A copy of `session` that goes on with `script`'s handlers: each of its own kept where
    `script` has the same `on` (its counts, and a run of it under way, with it), the others
    installed anew, in the order a run of `script` from its start installs them. Only for a
    `script` that differs from the session's in handlers no event has reached yet: the studio's
    edit (studio/event_run.py says which); ScriptError past the handlers' bounds, as that run."""
    twin = fork(session)
    fresh, _ = install([], script)
    old: List[Handler] = list(twin.handlers)
    handlers = []
    for new in fresh:
        same = next((h for h in old if exactly(h.on, new.on) and h.state == new.state), None)
        if same is not None:
            old.remove(same)
        handlers.append(same or new)
    twin.handlers, twin._kinds = handlers, by_kind(handlers)
    return twin


def exactly(a: object, b: object) -> bool:
    """Equal, places in the text too (a node's `==` leaves them out): what a run shows of a
    statement (its line, in the studio's timeline and the session's log) is the same."""
    return a == b and _places(a) == _places(b)


def _places(node: object) -> List[object]:
    found, stack = [], [node]
    while stack:
        item = stack.pop()
        if isinstance(item, (tuple, list)):
            stack.extend(item)
        elif dataclasses.is_dataclass(item):
            for f in dataclasses.fields(item):
                value = getattr(item, f.name)
                if f.name == "pos":
                    found.append((value.line, value.column))
                else:
                    stack.append(value)
    return found


def _face(face: LiveFace) -> LiveFace:
    _same_fields(face, _FACE)
    if face.idle is not None:
        raise CannotFork("a face with idle life is not copied: its plans are its own")
    twin = copy.copy(face)
    twin.rng = _random(face.rng)
    twin._robot = StatusFold(face._robot.status)
    twin.pending = list(face.pending)
    twin.begun = None  # a copy's steps are not the face's: no log is told of them
    return twin


def _run(run: Optional[Run], handler, rng: random.Random) -> Optional[Run]:
    if run is None:
        return None
    _same_fields(run, _RUN)
    twin = copy.copy(run)
    twin.handler = handler(run.handler)
    twin.runner = _runner(run.runner, rng)
    return twin


def _runner(runner: Runner, rng: random.Random) -> Runner:
    _same_fields(runner, _RUNNER)
    twin = copy.copy(runner)
    twin.rng = rng  # the session's `one of` stream, which every runner shares
    twin.frames = []
    for frame in runner.frames:
        copied = _Frame(frame.body, frame.rounds, frame.forever)
        copied.index, copied.lap = frame.index, frame.lap
        twin.frames.append(copied)
    twin._holding = dict(runner._holding)
    return twin
