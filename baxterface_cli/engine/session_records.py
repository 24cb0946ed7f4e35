"""What a live session keeps of what it runs: each handler installed, each run, each log line.

A run is the main script or one start of a handler: where it is in its body (its `Runner`), the
step it plays and until when, the event it waits for. live_session.py drives them; session_fork.py
copies them field by field, so a field added here must be added there too (it checks).
"""

from __future__ import annotations

from typing import NamedTuple, Optional, Tuple

from ..language import syntax_tree as n
from ..language.events import in_words
from .session_program import Play, Runner


class Logged(NamedTuple):
    at: float
    text: str


class Handler:
    """An `on` installed in the session, with its counts."""

    def __init__(self, on: n.On, script: n.Script) -> None:
        self.on = on
        self.script = script
        self.label = f"line {on.pos.line} 'on {in_words(on.event)}'"
        self.runs = 0
        self.dropped = 0
        self.queued = 0
        self.last_start: Optional[float] = None


class Run:
    """The main script, or one run of a handler, as the session drives it."""

    def __init__(
        self, runner: Runner, script: n.Script, label: str, handler: Optional[Handler] = None
    ) -> None:
        self.runner = runner
        self.script = script
        self.label = label
        self.handler = handler
        self.playing: Optional[Tuple[Play, float, float]] = None  # (step, start, end)
        self.exiting = False
        self.waiting: Optional[Tuple[n.WaitUntil, float]] = None  # (statement, since)
        self.done = False
        self.carry = True  # the next step lets what was begun finish (False after an interrupt)
