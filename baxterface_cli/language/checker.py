"""Whole-script checks, after parsing: definitions, names, recursion, limits.

Local checks (units, ranges, part names) happen in the parser where the
tokens are; what needs the whole script happens here.
"""

from __future__ import annotations

from typing import Any, Callable, Dict, Iterable, Iterator, List, Optional, Sequence, Set, Tuple

from ..core.face_constants import LIMITS
from . import syntax_tree as n
from .diagnostics import Diagnostic, Hints, shortened
from .events import phrases
from .reaction_checks import check_reactions
from .script_length import in_words, over_limit
from .statements import KEYWORDS, statement_seconds
from .vocabulary import BARE_WORDS, LEGACY_USAGE


def check(body: Sequence[Any], gestures: Iterable[str] = ()) -> List[Diagnostic]:
    """Every whole-script problem in `body`, as diagnostics; `gestures` are offered as "did you mean"."""
    out: List[Diagnostic] = []
    definitions = _definitions(body, out)
    _check_calls(body, definitions, out, list(gestures))
    order = _call_order(definitions, out)
    if order is not None:
        _check_limits(body, definitions, order, out)
        _check_nesting(body, definitions, order, out)
        _check_exit(body, definitions, order, out)
        called = _measured(definitions, order)
        check_reactions(body, definitions, order, lambda statements: measure(statements, called), out)
    return out


def _measured(definitions: Dict[str, n.Define], order: List[str]) -> Dict[str, Measure]:
    called: Dict[str, Measure] = {}
    for name in order:
        called[name] = measure(definitions[name].body, called)
    return called


def walk(body: Sequence[Any]) -> Iterator[Any]:
    """Every statement in `body`, blocks' contents included, depth first."""
    for statement in body:
        yield statement
        if isinstance(statement, n.BLOCKS):
            yield from walk(statement.body)


def phrases_listened(body: Sequence[Any]) -> List[str]:
    """The phrases the `on word` and `wait until word` in `body` listen for, in order, once each."""
    found = [
        phrase
        for s in walk(body)
        for phrase in (
            phrases(s.event)
            if isinstance(s, (n.On, n.WaitUntil)) and s.event is not None and s.event.kind == "word"
            else list(s.phrases)
            if isinstance(s, n.Ask)
            else []
        )
    ]
    return list(dict.fromkeys(found))


def _error(out: List[Diagnostic], node: Any, message: str) -> None:
    out.append(Diagnostic(node.pos.line, node.pos.column, message))


def _definitions(body: Sequence[Any], out: List[Diagnostic]) -> Dict[str, n.Define]:
    found: Dict[str, n.Define] = {}
    for statement in body:
        if not isinstance(statement, n.Define):
            continue
        name = statement.name
        if name in found:
            first = found[name].pos.line
            _error(out, statement, f"'{name}' is already defined on line {first}")
        elif name in BARE_WORDS or name in KEYWORDS or _legacy_command(name):
            _error(out, statement, f"'{name}' is a built-in command; choose another name")
        else:
            found[name] = statement
    for statement in body:
        if isinstance(statement, n.BLOCKS):
            for inner in walk(statement.body):
                if isinstance(inner, n.Define):
                    _error(out, inner, "'define' is only allowed at the top level of a script")
    return found


def _legacy_command(name: str) -> str:
    """The legacy command a word starts like (`look_a_b` -> `look`), or ''."""
    head = name.rsplit("_", 1)[0]
    while head:
        if head in LEGACY_USAGE and name.startswith(head + "_"):
            return head
        if "_" not in head:
            return ""
        head = head.rsplit("_", 1)[0]
    return ""


def _check_calls(
    body: Sequence[Any], definitions: Dict[str, n.Define], out: List[Diagnostic], gestures: List[str]
) -> None:
    used: Set[str] = set()
    known = list(BARE_WORDS) + list(KEYWORDS) + list(definitions) + gestures
    hints = Hints()
    for statement in walk(body):
        if not isinstance(statement, n.Call):
            continue
        name = statement.name
        used.add(name)
        if name in definitions:
            continue
        legacy = _legacy_command(name)
        if legacy:
            usage = LEGACY_USAGE[legacy][1]
            _error(out, statement, f"'{name}' is not a valid legacy command; write {usage}, with numbers")
        else:
            _error(out, statement, f"unknown command '{shortened(name)}'{hints(name, known)}")
    for name, definition in definitions.items():
        if name not in used:
            pos = definition.pos
            out.append(Diagnostic(pos.line, pos.column, f"'{name}' is defined but never used", "warning"))


def _calls_in(body: Sequence[Any]) -> List[n.Call]:
    return [s for s in walk(body) if isinstance(s, n.Call)]


def _call_order(definitions: Dict[str, n.Define], out: List[Diagnostic]) -> Any:
    """Definitions ordered callees first, or None if one calls itself.

    Iterative depth-first search, so a long chain of definitions cannot
    exhaust Python's stack.
    """
    order: List[str] = []
    state: Dict[str, int] = {}  # 1 = on the current path, 2 = done
    recursive = False
    for root in definitions:
        if state.get(root):
            continue
        path: List[str] = [root]
        stack: List[Iterator[n.Call]] = [iter(_calls_in(definitions[root].body))]
        state[root] = 1
        while stack:
            call = next(stack[-1], None)
            if call is None:
                stack.pop()
                done = path.pop()
                state[done] = 2
                order.append(done)
                continue
            callee = call.name
            if callee not in definitions or state.get(callee) == 2:
                continue
            if state.get(callee) == 1:
                cycle = path[path.index(callee) :] + [callee]
                chain = " -> ".join(cycle)
                _error(
                    out, definitions[callee], f"'{callee}' calls itself ({chain}); definitions cannot recurse"
                )
                recursive = True
                continue
            state[callee] = 1
            path.append(callee)
            stack.append(iter(_calls_in(definitions[callee].body)))
    return None if recursive else order


# -- length and size -------------------------------------------------------


Measure = Tuple[float, int]  # (seconds, steps once unrolled)
Seconds = Callable[[Any], float]  # how long one simple statement takes


def measure(body: Sequence[Any], called: Dict[str, Measure], timed: Seconds = statement_seconds) -> Measure:
    """Length and unrolled size of a sequence; `called` measures definitions."""
    seconds, steps = 0.0, 0
    for statement in body:
        s, k = _measure_one(statement, called, timed)
        seconds, steps = seconds + s, steps + k
    return seconds, steps


def _measure_one(statement: Any, called: Dict[str, Measure], timed: Seconds = statement_seconds) -> Measure:
    if isinstance(statement, n.Define):
        return 0.0, 0
    if isinstance(statement, n.Call):
        return called.get(statement.name, (0.0, 0))
    if isinstance(statement, n.Repeat):
        seconds, steps = measure(statement.body, called, timed)
        return statement.count * seconds, statement.count * steps
    if isinstance(statement, n.Together):
        parts = [_measure_one(child, called, timed) for child in statement.body]
        return max((p[0] for p in parts), default=0.0), sum(p[1] for p in parts)
    if isinstance(statement, n.OneOf):  # the longest choice; every choice is compiled, one at a time
        choices = [measure(choice, called, timed) for choice in statement.choices]
        return max(c[0] for c in choices), sum(c[1] for c in choices)
    if isinstance(statement, n.Ask):  # the question, then the longest answer (`nothing` after its wait)
        said = _measure_one(statement.question, called, timed)
        branches = [measure(a.body, called, timed) for a in statement.answers]
        branches += [measure(statement.otherwise, called, timed)] if statement.otherwise else []
        if statement.nothing is not None:
            wait, body = statement.nothing
            after = measure(body, called, timed)
            branches.append((wait + after[0], after[1]))
        return said[0] + max(b[0] for b in branches or [(0.0, 0)]), said[1] + sum(b[1] for b in branches)
    if isinstance(statement, (n.On, n.State)):  # its length is its own (reaction_checks.py), not the script's
        return 0.0, measure(statement.body, called, timed)[1]
    if isinstance(statement, n.Forever):  # one round: the rounds after it are the session's
        return measure(statement.body, called, timed)
    return timed(statement), 1


def check_length(body: Sequence[Any], recorded: Seconds) -> List[Diagnostic]:
    """The length limit again, with each `say file` as long as `recorded(say)` says (its header:
    speech/recordings.py reads it, the language cannot); for a script that passed `check`."""
    definitions = {s.name: s for s in body if isinstance(s, n.Define)}
    order = _call_order(definitions, [])
    out: List[Diagnostic] = []

    def timed(statement: Any) -> float:
        if isinstance(statement, n.Say) and statement.file is not None:
            return recorded(statement)
        return statement_seconds(statement)

    if order is not None:
        _check_limits(body, definitions, order, out, timed)
    return out


def _check_limits(
    body: Sequence[Any],
    definitions: Dict[str, n.Define],
    order: List[str],
    out: List[Diagnostic],
    timed: Seconds = statement_seconds,
) -> None:
    called: Dict[str, Measure] = {}
    for name in order:
        called[name] = measure(definitions[name].body, called, timed)
    seconds, steps = 0.0, 0
    for statement in body:
        s, k = _measure_one(statement, called, timed)
        seconds, steps = seconds + s, steps + k
        if over_limit(seconds):
            total = measure(body, called, timed)[0]
            _error(
                out,
                statement,
                f"the script runs {in_words(total)}; the limit is {in_words(LIMITS.max_seconds)}",
            )
            return
        if steps > LIMITS.max_steps:
            total_steps = measure(body, called, timed)[1]
            _error(
                out, statement, f"the script unrolls to {total_steps} steps; the limit is {LIMITS.max_steps}"
            )
            return


# -- nesting and exit ------------------------------------------------------


def _check_nesting(
    body: Sequence[Any], definitions: Dict[str, n.Define], order: List[str], out: List[Diagnostic]
) -> None:
    """Bound how deep blocks and calls nest through definitions: compiling recurses that deep."""
    height: Dict[str, int] = {}  # the depth a definition's body reaches, its call at depth 0
    for name in order:
        height[name] = _reach(definitions[name].body, 1, height)
    for statement in body:
        depth = _reach((statement,), 0, height)
        if depth > LIMITS.max_nesting:
            _error(
                out,
                statement,
                f"blocks and calls nest {depth} levels deep here, counting each call into a definition; "
                f"the limit is {LIMITS.max_nesting} levels",
            )


def _reach(body: Sequence[Any], depth: int, height: Dict[str, int]) -> int:
    """The deepest level `body`'s statements reach, they being at `depth`."""
    deepest = 0
    stack = [(statement, depth) for statement in body]
    while stack:
        statement, level = stack.pop()
        if isinstance(statement, n.Define):  # defines nothing to run here
            continue
        if isinstance(statement, n.Call):
            level += height.get(statement.name, 0)
        elif isinstance(statement, n.BLOCKS):
            stack.extend((child, level + 1) for child in statement.body)
        deepest = max(deepest, level)
    return deepest


def _check_exit(
    body: Sequence[Any], definitions: Dict[str, n.Define], order: List[str], out: List[Diagnostic]
) -> None:
    """Warn at what never runs because an 'exit' before it ends the script."""
    ends: Dict[str, int] = {}  # a definition whose body exits: the line of that 'exit'
    for name in order:
        line = _exit_line(definitions[name].body, ends, out)
        if line is not None:
            ends[name] = line
    _exit_line(body, ends, out)


def _exit_line(body: Sequence[Any], ends: Dict[str, int], out: List[Diagnostic]) -> Optional[int]:
    """The line of the 'exit' that ends the script within `body`, if one does.

    A `together` counts as a sequence: its children are compiled one after
    another, and nothing is compiled after an exit.
    """
    ended: Optional[int] = None
    for statement in body:
        if isinstance(statement, (n.Define, n.On, n.State)):  # a handler's exit ends it, not what follows
            continue
        if ended is not None:
            pos = statement.pos
            message = f"never runs: 'exit' on line {ended} ends the script"
            out.append(Diagnostic(pos.line, pos.column, message, "warning"))
            return ended
        if isinstance(statement, n.Exit):
            ended = statement.pos.line
        elif isinstance(statement, n.Call):
            ended = ends.get(statement.name)
        elif isinstance(statement, (n.Repeat, n.Together, n.Forever)):
            ended = _exit_line(statement.body, ends, out)
    return ended
