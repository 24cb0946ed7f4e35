"""A live session run on a clock of its own, over an events file or none: how `render`, `explain`
and the studio's preview play every script, reacting or not (`play` steps the session in real
time: play/live_player.py, which ends where this run would).

The session (live_session.py) takes the file's events at their times, so
the same script, events and seed give the same timelines and the same frames, to the bit.

How long it lasts: `duration` if given. Otherwise until the session comes to rest after the file's
last event (no handler running or queued, and the main script done, in a `forever`, or waiting
for an event the file does not bring), and the face has finished moving. A script that reaches
a `forever` with no events to react to would never end, and must be given a duration.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, List, NamedTuple, Optional

from ..core.face_constants import LIMITS
from ..language import syntax_tree as n
from ..language.checker import walk
from ..language.event_trace import Trace
from ..language.events import TIMERS
from ..language.events import in_words as event_words
from ..language.script_length import in_words
from .live_session import LiveSession
from .session_program import first_reacting
from .session_records import Logged
from .stitched import Stitched

if TYPE_CHECKING:
    from ..speech.recordings import Recordings


class NeverRests(Exception):
    """The run does not come to rest by itself: it needs a duration. The message says why, in one line."""


class _Played(list):
    """A session's `segments`, each timeline it began noted with how many lines its log had then:
    `explain` reads a step after the lines that led to it, before those that followed."""

    def __init__(self, session: LiveSession) -> None:
        super().__init__()
        self.session = session
        self.marks: List[int] = []

    def append(self, segment: Any) -> None:
        self.marks.append(self.session.logged)
        super().append(segment)


class SessionRun(NamedTuple):
    timeline: Stitched
    log: List[Logged]
    session: LiveSession


def reactive(script: n.Script) -> bool:
    """Does `script` need the session: a handler, a wait, a signal, `forever` or `one of`?"""
    return first_reacting(script) is not None


def run_over(
    script: n.Script,
    trace: Optional[Trace] = None,
    seed: Optional[int] = 0,
    duration: Optional[float] = None,
    crossfade: Optional[float] = None,
    recordings: Optional[Recordings] = None,
) -> SessionRun:
    """Run `script` with the events of `trace` (none if None) for `duration` seconds, or until it
    rests (see the module's docstring); NeverRests if it would not."""
    session = LiveSession(
        None, seed=seed, idle=False, recordings=recordings, crossfade=crossfade, record=True, log_lines=None
    )
    played = session.segments = _Played(session)
    session.run(script, 0.0)
    events = trace.events if trace is not None else ()
    limit = LIMITS.max_seconds if duration is None else duration
    for posted in events:
        if posted.at > limit:
            break
        session.post(posted.event, posted.at, trace.source(posted))  # type: ignore[union-attr]
    end = settle(session, script, trace.end if trace is not None else 0.0, bool(events), duration)
    # A script that never played a step (handlers, and no event for them): the face it started with.
    segments = session.segments or [(0.0, session.face.timeline)]
    end = run_end(session, segments, end, duration)
    return SessionRun(Stitched(segments, end, played.marks), list(session.log), session)


def run_end(session: LiveSession, segments: List[Any], rested: float, duration: Optional[float]) -> float:
    """Where a run that came to rest at `rested` ends (the studio's ends as `run_over`'s): without
    a duration, once its last timeline has played out; at the face's exit, if it exited, as the
    events after it changed nothing."""
    end = rested
    if duration is None:
        start, timeline = segments[-1]
        end = max(end, start + timeline.duration)
    if session.exited_at is not None:
        end = min(end, session.exited_at)
    return end


def settle(
    session: LiveSession, script: n.Script, last: float, evented: bool, duration: Optional[float]
) -> float:
    """Take the session, given its events up to `last`, on to its end: `duration`, or where it
    comes to rest (NeverRests if it would not). The studio continues a copy of its run with it."""
    if duration is not None:
        session.advance(duration)
        return duration
    session.advance(last)
    return _rest(session, script, evented)


def resting(session: LiveSession) -> bool:
    """Is nothing left to do but wait for events: no handler running or queued, and the main
    script done, in a `forever`, or waiting for an event without a timeout?"""
    if session.exited:
        return True
    if session.active is not None or session.pending:
        return False
    main = session.main
    if main is None or main.done:
        return True
    waiting = (
        main.waiting is not None and main.waiting[0].timeout is None and main.waiting[0].event.kind != "idle"
    )
    return waiting or main.runner.forever


def _rest(session: LiveSession, script: n.Script, evented: bool) -> float:
    """When the session comes to rest, stepping it from its clock."""
    while not resting(session):
        active = session.active
        if active is not None and active.runner.forever:  # only a duration ends it
            line = next(f.forever.pos.line for f in active.runner.frames if f.forever is not None)
            raise NeverRests(
                f"'forever' on line {line} never ends once {active.label} runs it; give --duration"
            )
        due = session.next_due()
        if due is None:
            break
        if due[0] > LIMITS.max_seconds:
            raise NeverRests(
                f"the script does not come to rest within {in_words(LIMITS.max_seconds)}; give --duration"
            )
        session.advance(due[0])
    main = session.main
    if main is not None and not main.done and main.runner.forever and not session.exited and not evented:
        line = next((s.pos.line for s in walk(script.body) if isinstance(s, n.Forever)), 0)
        raise NeverRests(f"'forever' on line {line} never ends and no events come to end it; give --duration")
    timed = [h.on for h in session.handlers if h.on.event.kind in TIMERS]
    if timed and not evented and session.clock == 0.0 and not session.exited:  # else a run of nothing
        on = timed[0]
        raise NeverRests(
            f"'on {event_words(on.event)}' on line {on.pos.line} runs by the clock, and nothing else "
            "happens; give --duration"
        )
    return session.clock
