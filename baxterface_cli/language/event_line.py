"""One event, written as an events file's line is without its time: `signal poke`, `touch left eye`.

What a live end takes over the wire (the screen's and the studio's `POST /api/event`): read by
the events file's own reader (event_trace.py), so the same mistakes get the same messages, with
their columns in the text as it was sent.
"""

from __future__ import annotations

import dataclasses

from . import syntax_tree as n
from .diagnostics import Diagnostic, ScriptError
from .event_trace import parse_trace

_AT = "0 "  # the time an events file's line starts with, put in front and taken off the columns


def read_event_line(text: str, filename: str = "<event>") -> n.Event:
    """The event `text` names; ScriptError, positioned in `text`, when it names none or more than one."""
    lines = text.splitlines() or [""]
    written = [i for i, line in enumerate(lines, 1) if line.strip() and not line.strip().startswith("#")]
    if not written:
        raise ScriptError([Diagnostic(1, 1, "no event: write one, as in 'signal poke'")], filename, text)
    if len(written) > 1:
        message = "one event at a time: this is a second one (an events file with times goes to --events)"
        raise ScriptError([Diagnostic(written[1], 1, message)], filename, text)
    number = written[0]
    try:
        trace = parse_trace("\n" * (number - 1) + _AT + lines[number - 1], filename)
    except ScriptError as e:
        moved = [
            d._replace(column=max(1, d.column - len(_AT))) if d.line == number else d for d in e.diagnostics
        ]
        raise ScriptError(moved, filename, text) from None
    event = trace.events[0].event
    return dataclasses.replace(event, pos=n.Pos(number, event.pos.column - len(_AT)))
