"""A body of statements on its way through the live session: what to do next, one step at a time.

The session (live_session.py) runs the main script and each handler's run as a `Runner`: a
statement the compiler can take is handed out whole, to be compiled and played from the face as
it is; `wait until`, `signal`, `go` and an `ask`'s listening (after its question, a `say`) are
handed out for the session to do; `repeat`, calls and `forever` that hold them are walked here,
and `one of` chooses here, from the session's seeded random stream, so the same seed makes the
same choices.
"""

from __future__ import annotations

import random
from typing import Any, Dict, List, NamedTuple, Optional, Sequence, Tuple, Union

from ..language import syntax_tree as n
from ..language.diagnostics import Diagnostic, ScriptError
from ..language.statements import describe

_CHOOSING = (n.OneOf, n.WaitUntil, n.Forever, n.Signal, n.Go, n.Ask)  # what the compiler never sees


class Play(NamedTuple):
    """A statement for the compiler (its `one of`s chosen): played from the face as it is."""

    statement: Any


class Await(NamedTuple):
    statement: n.WaitUntil


class Raise(NamedTuple):
    statement: n.Signal


class Listen(NamedTuple):
    """`ask`'s question is said: the session listens for its answers (session_answers.py)."""

    statement: n.Ask


class _Listening(NamedTuple):
    """In a frame after an `ask`'s question: where the runner hands out `Listen`."""

    ask: n.Ask


class Goto(NamedTuple):
    """`go NAME`: the session enters the state (session_states.py)."""

    statement: n.Go


class Lap(NamedTuple):
    """A round of a `forever` begins: the session makes each last `LIMITS.least_round` at least."""

    frame: _Frame


Step = Union[Play, Await, Raise, Goto, Listen, Lap]


class _Frame:
    """A sequence being walked: its statements, the next one's index, rounds left (None: forever),
    and for a `forever`, when its round began (the session's to set: the runner knows no time)."""

    __slots__ = ("body", "index", "rounds", "forever", "lap")

    def __init__(
        self, body: Sequence[Any], rounds: Optional[int], forever: Optional[n.Forever] = None
    ) -> None:
        self.body = body
        self.index = 0
        self.rounds = rounds
        self.forever = forever
        self.lap: Optional[float] = None


class Runner:
    """One body of statements, a step at a time (see the module's docstring)."""

    def __init__(self, body: Sequence[Any], definitions: Dict[str, n.Define], rng: random.Random) -> None:
        self.definitions = definitions
        self.rng = rng
        self.frames: List[_Frame] = [_Frame(body, 1)]
        self.again: Optional[Play] = None  # a statement cut short, to play again first
        self._holding: Dict[str, bool] = {}

    @property
    def forever(self) -> bool:
        """Is a `forever` under way: will the body never end by itself?"""
        return any(frame.rounds is None for frame in self.frames)

    def cut(self, play: Play, elapsed: float) -> None:
        """`play` was stopped `elapsed` seconds in: it starts over when the runner goes on (a `wait`
        waits out what was left of it)."""
        statement = play.statement
        if isinstance(statement, n.Wait):
            left = max(0.0, statement.duration - elapsed)
            self.again = None if left <= 0 else Play(n.Wait(left, pos=statement.pos))
        else:
            self.again = play

    def then(self, body: Sequence[Any]) -> None:
        """Go on with `body` first (an answer's), then where the runner was."""
        if body:
            self.frames.append(_Frame(body, 1))

    def next(self) -> Optional[Step]:
        """The next step, or None when the body is done."""
        if self.again is not None:
            step, self.again = self.again, None
            return step
        while self.frames:
            frame = self.frames[-1]
            if frame.index >= len(frame.body):
                if frame.rounds is not None:
                    frame.rounds -= 1
                if frame.rounds is None or frame.rounds > 0:
                    frame.index = 0
                    if frame.forever is not None:
                        return Lap(frame)
                    continue
                self.frames.pop()
                continue
            statement = frame.body[frame.index]
            frame.index += 1
            step = self._step(statement)
            if step is not None:
                return step
        return None

    def _step(self, s: Any) -> Optional[Step]:
        if isinstance(s, (n.Define, n.On, n.State, n.Use)):
            return None
        if isinstance(s, n.WaitUntil):
            return Await(s)
        if isinstance(s, n.Go):
            return Goto(s)
        if isinstance(s, _Listening):
            return Listen(s.ask)
        if isinstance(s, n.Ask):  # its question, said as `say` is; then it listens
            self.frames.append(_Frame((s.question, _Listening(s)), 1))
            return None
        if isinstance(s, n.Signal):
            return Raise(s)
        if isinstance(s, n.OneOf):
            self.frames.append(_Frame(s.choices[self.rng.randrange(len(s.choices))], 1))
        elif isinstance(s, n.Forever):
            self.frames.append(_Frame(s.body, None, s))
            return Lap(self.frames[-1])
        elif isinstance(s, n.Repeat) and self.holds(s):
            self.frames.append(_Frame(s.body, s.count))
        elif isinstance(s, n.Call) and self.holds(s):
            self.frames.append(_Frame(self.definitions[s.name].body, 1))
        else:
            return Play(self.resolved(s))
        return None

    def holds(self, s: Any) -> bool:
        """Does `s` hold (through its calls) a statement that the compiler never sees?"""
        if isinstance(s, _CHOOSING):
            return True
        if isinstance(s, n.Call):
            if s.name not in self._holding:
                self._holding[s.name] = False  # a definition cannot recurse: the checker saw to it
                body = self.definitions[s.name].body if s.name in self.definitions else ()
                self._holding[s.name] = any(self.holds(inner) for inner in body)
            return self._holding[s.name]
        return isinstance(s, n.BLOCKS) and any(self.holds(inner) for inner in s.body)

    def resolved(self, s: Any) -> Any:
        """`s` with each `one of` inside it chosen (a `together`'s: nothing else can be in one)."""
        if not self.holds(s):
            return s
        if isinstance(s, n.OneOf):
            return n.Repeat(1, self._all(s.choices[self.rng.randrange(len(s.choices))]), pos=s.pos)
        if isinstance(s, n.Together):
            return n.Together(tuple(self.resolved(child) for child in s.body), pos=s.pos)
        if isinstance(s, n.Repeat):  # each round chooses anew
            return n.Repeat(1, tuple(x for _ in range(s.count) for x in self._all(s.body)), pos=s.pos)
        if isinstance(s, n.Call):
            return n.Repeat(1, self._all(self.definitions[s.name].body), pos=s.pos)
        return s

    def _all(self, body: Sequence[Any]) -> Tuple[Any, ...]:
        return tuple(self.resolved(s) for s in body if not isinstance(s, n.Define))


def first_reacting(script: n.Script) -> Optional[Any]:
    """The first statement that only the live session runs (a handler, a wait, a signal, `forever`,
    `one of`), or None: a script without any needs no events to come to rest."""
    from ..language.checker import walk
    from ..language.statements import SESSION_KINDS

    return next((s for s in walk(script.body) if type(s) in SESSION_KINDS), None)


def not_here(script: n.Script, where: str) -> Optional[ScriptError]:
    """The error for an end that does not run the session yet, at the first statement it cannot
    run; None for a script it can."""
    found = first_reacting(script)
    if found is None:
        return None
    message = (
        f"'{describe(found)}' runs in render, play and explain (with --events FILE); "
        f"{where} does not run handlers, waits, signals, 'forever' or 'one of' yet"
    )
    return ScriptError(
        [Diagnostic(found.pos.line, found.pos.column, message)], script.filename, script.source
    )
