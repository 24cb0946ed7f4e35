"""The whole-script checks of reacting: where handlers, waits and signals may be, what never runs
after a `forever`, a `forever` that would spin, a handler's length, how many handlers a face keeps.

checker.py calls `check_reactions` once the definitions are known not to recurse.
"""

from __future__ import annotations

from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

from ..core.face_constants import LIMITS
from . import syntax_tree as n
from .diagnostics import Diagnostic
from .events import in_words, phrases
from .script_length import in_words as length_in_words
from .script_length import over_limit
from .state_checks import check_states

# What cannot run inside a `together`, whose statements are compiled side by side into one
# timeline: each of these holds the session up, or hands it an event, at its own moment.
_ON_THEIR_OWN = (n.WaitUntil, n.Forever, n.Signal, n.On, n.Go, n.Ask)
_NAMES = {
    n.WaitUntil: "wait until",
    n.Forever: "forever",
    n.Signal: "signal",
    n.On: "on",
    n.Go: "go",
    n.Ask: "ask",
}

Measure = Callable[[Sequence[Any]], Tuple[float, int]]


def check_reactions(
    body: Sequence[Any],
    definitions: Dict[str, n.Define],
    order: Sequence[str],
    measure: Measure,
    out: List[Diagnostic],
) -> None:
    """Every problem of `body`'s reacting statements, into `out` (see the module's docstring);
    `order` is the definitions', callees first."""
    held = _holding(definitions, order)
    waiting: set = set()  # definitions that wait for an event, through their calls
    for name in order:
        if any(_waits(s, waiting) for s in _inside(definitions[name].body)):
            waiting.add(name)
    seen: Dict[Tuple[str, str, str, float], int] = {}
    handlers = every = 0
    for statement, state in _top_levels(body):
        if isinstance(statement, n.On):
            _handler(statement, state, measure, seen, out)
            handlers += 1
            every += statement.event.kind == "every"
            _too_many(statement, handlers, every, out)
        if isinstance(statement, n.BLOCKS) and not isinstance(statement, n.State):
            for inner in _inside(statement.body):
                if isinstance(inner, n.On):
                    _error(out, inner, "'on' is only allowed at the top level of a script or of a state")
        if isinstance(statement, n.BLOCKS) and state is None:
            for inner in _inside(statement.body):
                if isinstance(inner, n.State):
                    _error(out, inner, "'state' is only allowed at the top level of a script")
    check_states(body, _everything(body), out)
    for statement in _everything(body):
        if isinstance(statement, n.Together):
            _together(statement, held, out)
        if isinstance(statement, n.Forever):
            _spinning(statement, waiting, measure, out)
    for sequence in _sequences(body):
        _after_forever(sequence, out)
    _phrases(_everything(body), out)


def _top_levels(body: Sequence[Any]) -> List[Tuple[Any, Optional[str]]]:
    """The script's statements and each state's own, with the state each is in (None: the script)."""
    found: List[Tuple[Any, Optional[str]]] = [(s, None) for s in body]
    for state in (s for s in body if isinstance(s, n.State)):
        found.extend((s, state.name) for s in state.body)
    return found


def _error(out: List[Diagnostic], node: Any, message: str, severity: str = "error") -> None:
    out.append(Diagnostic(node.pos.line, node.pos.column, message, severity))


def _inside(body: Sequence[Any]) -> List[Any]:
    """Every statement in `body`, blocks' contents included, depth first; without recursion, so
    blocks nested as deep as the parser allows cost no stack."""
    found: List[Any] = []
    stack = [iter(body)]
    while stack:
        statement = next(stack[-1], None)
        if statement is None:
            stack.pop()
            continue
        found.append(statement)
        if isinstance(statement, n.BLOCKS):
            stack.append(iter(statement.body))
    return found


def _everything(body: Sequence[Any]) -> List[Any]:
    return _inside(body)


def _sequences(body: Sequence[Any]) -> List[Sequence[Any]]:
    """`body` and every block's body, each a sequence run in order (a `one of`'s choices each)."""
    out: List[Sequence[Any]] = [body]
    for statement in _inside(body):
        if isinstance(statement, n.OneOf):
            out.extend(statement.choices)
        elif isinstance(statement, n.BLOCKS) and not isinstance(statement, n.Together):
            out.append(statement.body)
    return out


def _holding(definitions: Dict[str, n.Define], order: Sequence[str]) -> Dict[str, Any]:
    """For each definition, the first statement in it (through its calls) that must run on its own;
    `order` has callees first, so a chain of calls is followed without recursion."""
    held: Dict[str, Any] = {}
    for name in order:
        for statement in _inside(definitions[name].body):
            if isinstance(statement, _ON_THEIR_OWN):
                held[name] = statement
                break
            if isinstance(statement, n.Call) and statement.name in held:
                held[name] = held[statement.name]
                break
    return held


def _together(block: n.Together, held: Dict[str, Any], out: List[Diagnostic]) -> None:
    for statement in _inside(block.body):
        if isinstance(statement, _ON_THEIR_OWN) and not isinstance(statement, n.On):
            what = _NAMES[type(statement)]
            _error(out, statement, f"'{what}' cannot be inside 'together', whose statements run side by side")
        elif isinstance(statement, n.Call) and statement.name in held:
            inner = held[statement.name]
            what = _NAMES[type(inner)]
            _error(
                out,
                statement,
                f"'{statement.name}' cannot be inside 'together': it holds a '{what}' "
                f"(line {inner.pos.line}), "
                "and the statements of a 'together' run side by side",
            )


def _waits(statement: Any, waiting: set) -> bool:
    return isinstance(statement, (n.WaitUntil, n.Ask)) or (
        isinstance(statement, n.Call) and statement.name in waiting
    )


def _spinning(forever: n.Forever, waiting: set, measure: Measure, out: List[Diagnostic]) -> None:
    """A `forever` whose body takes no time and waits for nothing would repeat without end at one instant."""
    if measure(forever.body)[0] > 0 or any(_waits(s, waiting) for s in _inside(forever.body)):
        return
    _error(
        out,
        forever,
        "'forever' would repeat without end in no time: its body needs a statement that takes time, "
        "or a 'wait until'",
    )


def _too_many(handler: n.On, handlers: int, every: int, out: List[Diagnostic]) -> None:
    """The handler past what a face keeps (`LIMITS.max_handlers`, `LIMITS.max_every` of them by
    the clock): the live session would refuse the script whole."""
    if handlers == LIMITS.max_handlers + 1:
        _error(out, handler, f"more handlers than the {LIMITS.max_handlers} a face keeps")
    if every == LIMITS.max_every + 1 and handler.event.kind == "every":
        _error(out, handler, f"more 'every' handlers than the {LIMITS.max_every} a face keeps in time")


def _after_forever(sequence: Sequence[Any], out: List[Diagnostic]) -> None:
    running: Optional[n.Forever] = None
    for statement in sequence:
        if isinstance(statement, (n.Define, n.On, n.State)):  # these run from elsewhere
            continue
        if running is not None:
            message = f"never runs: 'forever' on line {running.pos.line} does not end"
            _error(out, statement, message, "warning")
            return
        if isinstance(statement, n.Forever):
            running = statement


def _handler(
    handler: n.On,
    state: Optional[str],
    measure: Measure,
    seen: Dict[Tuple[str, str, str, float], int],
    out: List[Diagnostic],
) -> None:
    key = (state or "", handler.event.kind, handler.event.arg, handler.event.seconds)
    if key[1:] == ("signal", "?", 0.0):  # an event already reported as unknown: no second word on it
        pass
    elif key in seen:
        message = (
            f"'{in_words(handler.event)}' already has a handler, on line {seen[key]}: "
            "this one runs only when that one is not running, by its policy"
        )
        _error(out, handler, message, "warning")
    else:
        seen[key] = handler.pos.line
    seconds, _ = measure(handler.body)
    if over_limit(seconds):
        limit = length_in_words(LIMITS.max_seconds)
        _error(out, handler, f"the handler runs {length_in_words(seconds)}; the limit is {limit}")


def _phrases(statements: Any, out: List[Diagnostic]) -> None:
    """Listening costs work for every phrase in every second of sound heard (docs/speech.md): a
    script listens for LIMITS.max_phrases phrases at most, said at the statement of the first past it."""
    listened: Dict[str, bool] = {}
    for statement in statements:
        event = getattr(statement, "event", None)
        heard: List[str] = []
        if isinstance(statement, (n.On, n.WaitUntil)) and event is not None and event.kind == "word":
            heard = phrases(event)
        elif isinstance(statement, n.Ask):
            heard = list(statement.phrases)
        if heard:
            for phrase in heard:
                if phrase not in listened and len(listened) == LIMITS.max_phrases:
                    most = LIMITS.max_phrases
                    _error(
                        out, statement, f"one phrase too many: a script listens for {most} phrases at most"
                    )
                    return
                listened[phrase] = True
