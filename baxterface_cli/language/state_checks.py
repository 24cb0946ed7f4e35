"""The whole-script checks of states: each state named once (and never `back`, which `go back`
means), each `go` to a state the script has (with a "did you mean"), and a warning at a state no
`go` reaches. reaction_checks.py calls `check_states`; where a `state` and its handlers may be is
checked there, with the other statements that react.
"""

from __future__ import annotations

from typing import Any, Dict, List, Sequence

from . import syntax_tree as n
from .diagnostics import Diagnostic, did_you_mean

BACK = "back"  # `go back`: to the state the face came from


def check_states(body: Sequence[Any], everything: Sequence[Any], out: List[Diagnostic]) -> None:
    """Every problem of `body`'s states and `go`s, into `out`; `everything` is every statement of
    the script, blocks' contents included."""
    states: Dict[str, n.State] = {}
    for state in (s for s in body if isinstance(s, n.State)):
        if state.name == BACK:
            _error(
                out,
                state,
                "a state cannot be called 'back': 'go back' returns to the state the face came from",
            )
        elif state.name in states:
            _error(
                out, state, f"state '{state.name}' is already defined on line {states[state.name].pos.line}"
            )
        else:
            states[state.name] = state
    reached = set()
    for go in (s for s in everything if isinstance(s, n.Go)):
        if go.name == BACK:
            if not states:
                _error(out, go, "'go back' returns to the state the face came from, and this script has none")
        elif go.name in states:
            reached.add(go.name)
        else:
            known = f"; the script's states are {', '.join(states)}" if states and len(states) <= 8 else ""
            hint = did_you_mean(go.name, states) or known
            _error(out, go, f"unknown state '{go.name}'{hint}")
    for name, state in states.items():
        if name not in reached:
            _error(out, state, f"state '{name}' is never entered: no 'go {name}' in the script", "warning")


def _error(out: List[Diagnostic], node: Any, message: str, severity: str = "error") -> None:
    out.append(Diagnostic(node.pos.line, node.pos.column, message, severity))
