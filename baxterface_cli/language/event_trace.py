"""An events file: what happened to the face and when, for `render`, `play` and `explain --events`.

One event a line, after the seconds it comes at::

    # a person walks up and says hello
    2.5 face seen
    4 word "hello"
    6 button ok
    7.2 touch left eye
    9 signal poke

Blank lines and `#` comments are allowed; times go forward (two events may share one). Events
are written as after `on` (events.py), without options; `every` and `idle` are the script's own
clock, not something that happens to it. Every problem is reported as a script's is,
`file:line:col: message`, all of them in one run.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any, List, NamedTuple, Optional, Tuple, Union

from lark import Token

from ..core.face_constants import LIMITS, UNITS
from . import syntax_tree as n
from .diagnostics import Diagnostic, Hints, ScriptError, keep_first, one_of
from .events import KINDS, NUMBER, PLACES, TIMERS, read_event
from .script_length import in_words
from .source import decode, read_bounded

MOST_EVENTS = 100_000  # lines of events in one file: a storm of 27 a second for an hour

_TOKEN = re.compile(
    r'(?P<STRING>"(?:\\.|[^"\\\n])*")'
    rf"|(?P<QUANTITY>{NUMBER}(?:[a-z%][a-z0-9_%]*)?)"
    r"|(?P<NAME>[a-z_][a-z0-9_]*(?:-[a-z0-9_]+)*)"
    r"|(?P<SPACE>[ \t\f\r]+)"
    r"|(?P<COMMENT>#.*)",
    re.I,
)
_NUMBER = re.compile(rf"({NUMBER})(.*)", re.S)
_ESCAPE = re.compile(r"\\(.)", re.S)


class Posted(NamedTuple):
    """One event of a trace: when it comes (seconds from the start) and where it is written."""

    at: float
    event: n.Event
    line: int
    origin: str = ""  # where it came from when that is not a line of the file: "heard in x.wav"


class Trace(NamedTuple):
    events: Tuple[Posted, ...]
    filename: str

    def source(self, posted: Posted) -> str:
        """Where `posted` came from, as the session's log names it: `greeter.events:4`."""
        return posted.origin or f"{self.filename}:{posted.line}"

    @property
    def end(self) -> float:
        """When the last event comes (0 for none)."""
        return self.events[-1].at if self.events else 0.0


def read_trace(path: Union[str, Path, Any], display_name: Optional[str] = None) -> Trace:
    """Read an events file (a path or a binary stream; UTF-8, as big as a script may be)."""
    name = display_name or str(path)
    return parse_trace(decode(read_bounded(path, name), name), name)


def parse_trace(text: str, filename: str = "<events>") -> Trace:
    """The events of `text`; ScriptError with every problem, positioned, if any."""
    reader = _Reader()
    events: List[Posted] = []
    for number, line in enumerate(text.splitlines(), 1):
        tokens = reader.tokens(line, number)
        if tokens is None or not tokens:
            continue
        if len(events) >= MOST_EVENTS:
            reader.error(tokens[0], f"too many events: the limit is {MOST_EVENTS} in one file")
            break
        posted = reader.event(tokens)
        if posted is not None:
            events.append(posted)
    shown, more_errors, more_warnings = keep_first(reader.diagnostics)
    if shown:
        raise ScriptError(shown, filename, text, more_errors, more_warnings)
    return Trace(tuple(events), filename)


class _Reader:
    def __init__(self) -> None:
        self.diagnostics: List[Diagnostic] = []
        self.hints = Hints()
        self.last = 0.0  # the latest good time, though its event was bad: times are checked apart

    def error(self, token: Token, message: str) -> None:
        self.diagnostics.append(Diagnostic(token.line, token.column, message))

    def tokens(self, line: str, number: int) -> Optional[List[Token]]:
        found: List[Token] = []
        at = 0
        while at < len(line):
            m = _TOKEN.match(line, at)
            if m is None:
                shown = repr(line[at]) if line[at] in "'\"" or not line[at].isprintable() else f"'{line[at]}'"
                message = f"unexpected character {shown}"
                if line[at] == '"':
                    message = "unterminated string: it needs a closing '\"' on the same line"
                self.diagnostics.append(Diagnostic(number, at + 1, message, kind="syntax"))
                return None
            if m.lastgroup not in ("SPACE", "COMMENT"):
                found.append(Token(m.lastgroup, m.group(), line=number, column=at + 1))
            at = m.end()
        return found

    def event(self, tokens: List[Token]) -> Optional[Posted]:
        when, *words = tokens
        if when.type != "QUANTITY":
            # `face seen`: the line is the event; `five touch`: the event comes after a time in words.
            firsts = {kind.split()[0] for kind in KINDS}
            event = tokens if str(when).lower() in firsts else words
            # the hint is a line that reads: the line's own event, else one every face knows
            known = bool(event) and str(event[0]).lower() in firsts
            example = " ".join(str(t) for t in event) if known else "face seen"
            self.error(when, f"a line starts with the seconds its event comes at, as in '2.5 {example}'")
            return None
        before = len(self.diagnostics)
        at = self.seconds(when, "a time")
        if len(self.diagnostics) > before:
            return None
        if at < self.last:
            self.error(when, f"times go forward: {when} comes after {self.last:g} s")
            return None
        self.last = at
        if at > LIMITS.max_seconds:
            self.error(when, f"{when} is past the limit of {in_words(LIMITS.max_seconds)}")
            return None
        if not words:
            self.error(when, "an event is missing after the time, as in '2.5 face seen'")
            return None
        event, rest = read_event(words, self.error, self.seconds, self.string, self.hints)
        if event is None:
            return None
        if event.kind in TIMERS:
            self.error(words[0], f"'{event.kind}' is the script's own clock, not an event a file can bring")
            return None
        if rest and event.kind == "touch" and not event.arg and rest[0].type == "NAME":
            hint = self.hints(str(rest[0]).lower(), PLACES) or f"; it lands on {one_of(PLACES)}, or anywhere"
            self.error(rest[0], f"unknown place '{rest[0]}' for a touch{hint}")
            return None
        if rest:
            self.error(rest[0], f"unexpected '{rest[0]}' after the event; an events file has no options")
            return None
        return Posted(
            at, n.Event(event.kind, event.arg, event.seconds, n.Pos(when.line, words[0].column)), when.line
        )

    def seconds(self, token: Token, what: str) -> float:
        number, unit = _NUMBER.fullmatch(str(token)).groups()  # type: ignore[union-attr]
        scale = UNITS["seconds"].get(unit.lower())
        value = float(number) * scale if scale is not None else math.nan
        if scale is None:
            self.error(
                token, f"unknown unit '{unit}' for {what}; use {one_of(u for u in UNITS['seconds'] if u)}"
            )
        elif not math.isfinite(value) or value < 0:
            self.error(token, f"{what} must be a number of seconds from 0, not {token}")
        return value if math.isfinite(value) and value >= 0 else 0.0

    def string(self, token: Token) -> Optional[str]:
        body = str(token)[1:-1]
        for m in _ESCAPE.finditer(body):
            if m.group(1) not in '"\\':
                self.diagnostics.append(
                    Diagnostic(token.line, token.column + 1 + m.start(), f"unknown escape '\\{m.group(1)}'")
                )
                return None
        return _ESCAPE.sub(r"\1", body)
