"""The states a live session knows, the one the face is in, and the one it came from.

A script's `state NAME { ... }` is installed with its handlers (a later script's state of the same
name replaces it); `go NAME` enters it, `go back` the state the face came from. What entering
does to the runs is the session's (live_session.py): what ran stops as an `interrupt` stops it,
and the state's body becomes what the face does. States entered one after another without time
passing are stopped at `MAX_ENTRIES_AT_ONCE`, as handlers that start one another are.
"""

from __future__ import annotations

import copy
from typing import Dict, Optional, Tuple

from ..language import syntax_tree as n
from ..language.state_checks import BACK
from .session_handlers import kept_for
from .session_records import AtOnce

MAX_ENTRIES_AT_ONCE = 100  # states entered without time passing: `state a { go b }`, `state b { go a }`


class States:
    """See the module's docstring."""

    def __init__(self) -> None:
        self.known: Dict[str, Tuple[n.State, n.Script]] = {}  # each with what its body needs
        self.current: Optional[str] = None
        self.came_from: Optional[str] = None
        self._entries = AtOnce()  # states entered at one instant

    def install(self, script: n.Script) -> None:
        definitions = script.definitions
        for state in script.states.values():
            self.known[state.name] = (state, kept_for(script, state.body, definitions))

    def target(self, go: n.Go, at: float) -> Tuple[Optional[str], str]:
        """The state `go` enters at `at`, or (None, why not)."""
        name = self.came_from if go.name == BACK else go.name
        if name is None:
            return None, "has no state to go back to: the face came from none"
        if name not in self.known:
            return None, f"goes to no state: this face has no state '{name}'"
        if self._entries.add(at) > MAX_ENTRIES_AT_ONCE:
            return None, f"stopped: {MAX_ENTRIES_AT_ONCE} states were entered without time passing"
        return name, ""

    def enter(self, name: str) -> Tuple[n.State, n.Script]:
        self.came_from, self.current = self.current, name
        return self.known[name]

    def live(self, state: Optional[str]) -> bool:
        """Is a handler of `state` (None: of every state) live now?"""
        return state is None or state == self.current

    def copy(self) -> States:
        twin = States()
        twin.known = dict(self.known)
        twin.current, twin.came_from, twin._entries = self.current, self.came_from, copy.copy(self._entries)
        return twin
