"""A session's log file (session_log_file.py) read back and run again: `render LOG.jsonl`,
`explain LOG.jsonl`.

The log's first script is the one the session runs from the start; the events after it come at
their times, and the scripts after it as what they were: a command that takes over, or one sent
to wait (`queued`), started when the face is free, as the live intake starts it. A studio's log
(or its export) is its last script over the events fired and the commands pressed since its last
`cleared`, each at its `at` on the run (studio/studio_log.py). Times are the
log's, less its first script's: the replay's 0 is the moment the face began it. Its end is the
log's `end` record, if it has one; else where the session comes to rest (session_run.py).

A log cut short (a face stopped hard) or edited by hand is read up to its last good record, and
one line names the first bad one; a log of a later version than this reads says so, and what
this one knows of it is read. A command the live face refused (a mistake in it) is left out, as
it changed nothing there either.
"""

from __future__ import annotations

import json
from typing import TYPE_CHECKING, Any, Dict, List, NamedTuple, Optional, Tuple, Union

from ..core.face_constants import LIMITS
from ..language import syntax_tree as n
from ..language.diagnostics import ScriptError
from ..language.event_line import read_event_line
from ..language.event_trace import Posted, Trace
from ..language.parser import parse
from .live_session import LiveSession
from .session_log_file import VERSION
from .session_run import NeverRests, SessionRun, _Played, run_end, settle
from .stitched import Stitched

if TYPE_CHECKING:
    from ..speech.recordings import Recordings

MOST_RECORDS = 1_000_000  # lines of a log read: a day of a busy face


class LogError(Exception):
    """A log that cannot be replayed (no script in it, a rotated part): the message says why."""


class Later(NamedTuple):
    """A script that came after the first: when, what, and whether it was sent to wait."""

    at: float
    script: n.Script
    queued: bool
    line: int


class Replay(NamedTuple):
    script: n.Script  # the first
    later: Tuple[Later, ...]
    trace: Trace  # the events, each from where the live session had it
    end: Optional[float]  # the `end` record's time, if the log has one
    seed: Optional[int]  # the live session's, if it had one
    notes: Tuple[str, ...]  # lines to say: the first bad record, a later version, refused commands


def read_log(path: str) -> Replay:
    """The scripts and events of the log at `path`; LogError if it has nothing to replay."""
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            lines = f.read().splitlines()[:MOST_RECORDS]
    except OSError as e:
        raise LogError(f"{path}: cannot read: {e.strerror or e}") from None
    notes: List[str] = []
    records: List[Tuple[int, Dict[str, Any]]] = []
    for number, line in enumerate(lines, 1):
        record = _record(line)
        if isinstance(record, str):
            notes.append(f"{path}:{number}: {record}; read up to the record before it")
            break
        records.append((number, record))
    if not records and notes:  # its first line is bad: no log at all
        raise LogError(notes[0].split("; read up to")[0] + ": not a session log")
    if not records or records[0][1]["type"] not in ("start", "continued"):
        raise LogError(f"{path}: not a session log: its first record is no 'start'")
    first = records[0][1]
    if first["type"] == "continued":
        raise LogError(
            f"{path}: this part of a log begins after a rotation (part {first.get('part')}); "
            "replay the part that holds its 'start' (FILE.N with the highest N kept)"
        )
    version = first.get("version")
    if not isinstance(version, int) or version > VERSION:
        notes.insert(
            0,
            f"{path}: a log of version {version}, newer than this baxterface's {VERSION}: read as {VERSION}",
        )
    return _replay(path, records, first, notes)


def _record(line: str) -> Union[Dict[str, Any], str]:
    """The record of one line, or what is wrong with it."""
    try:
        record = json.loads(line)
    except ValueError as e:
        return f"not a record ({e.args[0] if e.args else e})"
    if not isinstance(record, dict) or not isinstance(record.get("type"), str):
        return "not a record: no 'type'"
    t = record.get("t")
    if isinstance(t, bool) or not isinstance(t, (int, float)) or not 0 <= t <= 10 * LIMITS.max_seconds:
        return f"a {record['type']} record without a good time 't'"
    return record


def _replay(
    path: str, records: List[Tuple[int, Dict[str, Any]]], start: Dict[str, Any], notes: List[str]
) -> Replay:
    script: Optional[n.Script] = None
    origin = 0.0
    settings = start.get("settings") if isinstance(start.get("settings"), dict) else {}
    # The studio runs its events and pressed commands again over each script it plays, at their
    # times on that run (`at`): its replay is the last script over those since the last `cleared`.
    studio = settings.get("end") == "studio"
    later: List[Later] = []
    events: List[Posted] = []
    refused = 0
    end = None
    for number, record in records[1:]:
        kind, t = record["type"], float(record["t"])
        if kind == "script":
            pressed = studio and record.get("press") is True
            at = record.get("at")
            if pressed and (isinstance(at, bool) or not isinstance(at, (int, float))):
                continue  # a press of a studio before its presses were the session's: played apart
            try:
                read = parse(str(record.get("text", "")), str(record.get("source") or path))
            except ScriptError:
                refused += 1
                continue
            if pressed:  # a command pressed in the studio's panel: it takes over at `at` on the run
                later.append(Later(max(0.0, at), read, False, number))  # type: ignore[arg-type]
            elif script is None or studio:
                script, origin = read, t
            else:
                later.append(Later(t - origin, read, record.get("queued") is True, number))
        elif kind == "event" and script is not None:
            try:
                event = read_event_line(str(record.get("event", "")), f"{path}:{number}")
            except ScriptError as e:
                notes.append(f"{path}:{number}: an event this baxterface does not know: {e.summary()}")
                continue
            at = record.get("at") if studio else t - origin
            if isinstance(at, bool) or not isinstance(at, (int, float)):
                notes.append(f"{path}:{number}: a studio's event without its time 'at' left out")
                continue
            events.append(Posted(max(0.0, at), event, number, str(record.get("source") or "")))
        elif kind == "cleared" and studio:
            events.clear()
            later.clear()
        elif kind == "end" and script is not None and not studio:
            end = max(0.0, t - origin)
    if script is None:
        raise LogError(f"{path}: no script in it to replay")
    if refused:
        notes.append(f"{path}: {refused} command{'s' if refused != 1 else ''} the face refused live left out")
    events.sort(key=lambda e: (e.at, e.line))  # the studio's, fired as its preview was sought
    later.sort(key=lambda e: (e.at, e.line))
    seed = settings.get("seed")
    seed = seed if isinstance(seed, int) and not isinstance(seed, bool) else None
    return Replay(script, tuple(later), Trace(tuple(events), path), end, seed, tuple(notes))


def run_log(
    replay: Replay,
    seed: Optional[int] = 0,
    duration: Optional[float] = None,
    crossfade: Optional[float] = None,
    recordings: Optional[Recordings] = None,
) -> SessionRun:
    """Run `replay` as `run_over` runs a script over events (see above): `duration` if given, else
    to the log's end, else until it rests (NeverRests if it would not)."""
    session = LiveSession(
        None, seed=seed, idle=False, recordings=recordings, crossfade=crossfade, record=True, log_lines=None
    )
    played = session.segments = _Played(session)
    session.run(replay.script, 0.0)
    limit = LIMITS.max_seconds if duration is None else duration
    inputs = sorted([*replay.trace.events, *replay.later], key=lambda i: (i.at, i.line))
    waiting: List[n.Script] = []
    for item in inputs:
        if item.at > limit:
            break
        _start_waiting(session, waiting, item.at)
        if isinstance(item, Later):
            if item.queued:
                waiting.append(item.script)
                _start_waiting(session, waiting, item.at)
            else:
                waiting.clear()  # a take-over lets the waiting ones go, as the intake does
                session.run(item.script, max(item.at, session.clock))
        else:
            session.post(item.event, item.at, replay.trace.source(item))
    _start_waiting(session, waiting, limit)
    until = duration if duration is not None else replay.end
    last = inputs[-1].at if inputs else 0.0
    try:
        end = settle(session, replay.script, last, bool(inputs), until)
    except NeverRests:
        if not waiting:
            raise
        end = session.clock
    segments = session.segments or [(0.0, session.face.timeline)]
    end = run_end(session, segments, end, until)
    return SessionRun(Stitched(segments, end, played.marks), list(session.log), session)


def _start_waiting(session: LiveSession, waiting: List[n.Script], until: float) -> None:
    """The queued scripts started as the face comes free, up to `until`."""
    while waiting and not session.exited:
        if session.free:
            session.run(waiting.pop(0), session.clock)
            continue
        due = session.next_due()
        if due is None or due[0] > until:
            return
        session.advance(due[0])
