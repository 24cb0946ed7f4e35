"""What a live session keeps of what it runs: each handler installed, each run, each log line.

A run is the main script or one start of a handler: where it is in its body (its `Runner`), the
step it plays and until when, the event it waits for. live_session.py drives them; session_fork.py
copies them field by field, so a field added here must be added there too (it checks).
"""

from __future__ import annotations

import itertools
from collections import deque
from typing import List, NamedTuple, Optional, Tuple

from ..language import syntax_tree as n
from ..language.events import in_words
from .session_program import Play, Runner


class LogKind:
    """What a log line tells, so that a reader (the node's log, a session's record) picks lines by
    their kind, never by the words of their text."""

    EVENT = "event"  # an event came
    STARTED = "started"  # a handler's run began
    QUEUED = "queued"  # an event waits for its handler's turn
    DROPPED = "dropped"  # an event was let go, and why
    INTERRUPTED = "interrupted"  # a handler's run was cut by an `interrupt` handler
    TIMED_OUT = "timed out"  # a `wait until` gave up
    ENDED = "ended"  # a run came to its end
    RESUMED = "resumed"  # the main script goes on after the handlers
    REPLACED = "replaced"  # a handler sent later replaced the one for its event
    STOPPED = "stopped"  # a run stopped by a bound: steps or starts at one instant, falling behind
    TAKEN_OVER = "taken over"  # a handler's run stopped by a new main script
    ENTERED = "entered"  # the face entered a state
    ANSWERED = "answered"  # an `ask` heard its answer (or nothing)
    EXITED = "exited"  # the face exited


class Logged(NamedTuple):
    """One line of a session's log: when, what it says, and what kind of thing it tells."""

    at: float
    text: str
    kind: str


class AtOnce:
    """How many times something happened at one instant of the session's clock: a loop that
    takes no time (handlers that start one another, states that go to one another) is bounded."""

    __slots__ = ("at", "count")

    def __init__(self) -> None:
        self.at: Optional[float] = None
        self.count = 0

    def add(self, at: float) -> int:
        if at != self.at:
            self.at, self.count = at, 0
        self.count += 1
        return self.count


class SessionLog(deque):
    """A session's log: its last `maxlen` lines (all, for None), and how many were ever logged."""

    def __init__(self, maxlen: Optional[int]) -> None:
        super().__init__(maxlen=maxlen)
        self.logged = 0

    def note(self, at: float, kind: str, text: str) -> None:
        self.append(Logged(at, text, kind))
        self.logged += 1

    def since(self, logged: int) -> List[Logged]:
        """The lines after the first `logged` ever logged (those it still keeps), the new only: a
        storm's log is not read whole for its last few lines."""
        new = min(self.logged - logged, len(self))
        return list(itertools.islice(reversed(self), new))[::-1]


class Handler:
    """An `on` installed in the session, with its counts."""

    def __init__(self, on: n.On, script: n.Script, state: Optional[str] = None) -> None:
        self.on = on
        self.script = script
        self.state = state  # live only while the face is in this state; None: in every state
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
