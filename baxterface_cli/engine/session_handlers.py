"""The handlers a live session installs, and the clock that raises its `every` events.

Installing is all or nothing: a script whose handlers would take the face past the handlers it
keeps (`LIMITS.max_handlers`, of which `LIMITS.max_every` run by the clock) is refused whole,
with one error saying why, and nothing it says is installed. Each handler keeps only what it runs:
its `on`, and the definitions its body calls (through each other), not the whole script it came
in, so a 250 KB script of definitions costs its handlers nothing once read.

`EveryClock` keeps each `every` period's next tick in a heap: the session asks for the earliest
only, so a script's timers cost the same however many periods it has.
"""

from __future__ import annotations

import heapq
from typing import Dict, List, Optional, Sequence, Tuple

from ..core.face_constants import LIMITS
from ..language import syntax_tree as n
from ..language.borrowing import called
from ..language.diagnostics import Diagnostic, ScriptError
from .session_records import Handler, Run

Key = Tuple[str, str, str, float]
MAX_QUEUE = 32  # events a `queue` handler holds; more are dropped, and counted


def key_of(handler: Handler) -> Key:
    """What makes two handlers the same: the same event in the same state (or both in none); a
    later one replaces the earlier."""
    event = handler.on.event
    return (handler.state or "", event.kind, event.arg, event.seconds)


def ons_of(script: n.Script) -> List[Tuple[n.On, Optional[str]]]:
    """The script's handlers, each with the state it is live in (None: every state)."""
    found: List[Tuple[n.On, Optional[str]]] = [(s, None) for s in script.body if isinstance(s, n.On)]
    for state in (s for s in script.body if isinstance(s, n.State)):
        found.extend((s, state.name) for s in state.body if isinstance(s, n.On))
    return found


def install(installed: List[Handler], script: n.Script) -> Tuple[List[Handler], List[Handler]]:
    """`installed` with `script`'s handlers added, each replacing an installed handler of its
    event (a script's own are all kept: the first starts, the others follow their policies), and
    the handlers replaced. ScriptError, and nothing changed, past the bounds."""
    ons = ons_of(script)
    if not ons:
        return installed, []
    definitions = script.definitions
    added = [Handler(on, kept_for(script, on.body, definitions), state) for on, state in ons]
    keys = {key_of(h) for h in added}
    kept = [h for h in installed if key_of(h) not in keys]
    replaced = [h for h in installed if key_of(h) in keys]
    _within_bounds(kept, [on for on, _ in ons], script)
    return kept + added, replaced


def kept_for(script: n.Script, body: Sequence[n.Statement], definitions: Dict[str, n.Define]) -> n.Script:
    """`script` cut down to what `body` needs to run: the definitions it calls (`definitions`,
    the script's, read once by the caller). The source is one string every handler of the script
    shares, so an error still shows its line. The definitions keep the script's order."""
    needed = {d.name for d in called(body, definitions)}
    kept = tuple(d for name, d in definitions.items() if name in needed)
    return n.Script(kept, script.filename, source=script.source, legacy=script.legacy)


def _within_bounds(kept: List[Handler], ons: List[n.On], script: n.Script) -> None:
    """Refuse, at the first handler past it, a script that takes the face past either bound."""
    every = sum(1 for h in kept if h.on.event.kind == "every")
    for count, on in enumerate(ons, start=len(kept) + 1):
        every += on.event.kind == "every"
        if count > LIMITS.max_handlers:
            why = (
                f"more handlers than the {LIMITS.max_handlers} a face keeps: it has {len(kept)}, and this "
                f"script adds {len(ons)} (a handler for an event already handled replaces it)"
            )
        elif every > LIMITS.max_every:
            why = f"more 'every' handlers than the {LIMITS.max_every} a face keeps in time"
        else:
            continue
        raise ScriptError([Diagnostic(on.pos.line, on.pos.column, why)], script.filename, script.source)


def why_dropped(handler: Handler, at: float, active: Optional[Run], queued: int) -> Optional[str]:
    """Why `handler`'s event at `at` is let go, as the log says it after "dropped EVENT"; None if
    its handler takes it (starts, queues or interrupts), by its policy, with `active` running and
    `queued` of its events waiting."""
    on = handler.on
    if on.cooldown and handler.last_start is not None and at < handler.last_start + on.cooldown:
        return f": {handler.label} cools down till {handler.last_start + on.cooldown:.2f} s"
    if active is None:
        return None
    if on.policy == "drop":
        whose = "" if active.handler is handler else f" for {handler.label}"
        return f"{whose}: {active.label} is running"
    if on.policy == "queue" and queued >= MAX_QUEUE:
        return f": {handler.label} has {MAX_QUEUE} queued"
    return None


def by_kind(handlers: Sequence[Handler]) -> Dict[str, List[Handler]]:
    """The handlers of each kind of event, in the order installed: an event looks at its own."""
    found: Dict[str, List[Handler]] = {}
    for h in handlers:
        found.setdefault(h.on.event.kind, []).append(h)
    return found


class EveryClock:
    """Each `every` period's next tick, earliest first (see the module's docstring)."""

    def __init__(self) -> None:
        self._heap: List[Tuple[float, float]] = []  # (next tick, period)
        self._periods: set = set()

    def add(self, period: float, at: float) -> None:
        """Tick every `period` from `at` on; a period already ticking keeps its time."""
        if period not in self._periods:
            self._periods.add(period)
            heapq.heappush(self._heap, (at + period, period))

    def first(self) -> Optional[Tuple[float, float]]:
        """(the earliest tick, its period), or None."""
        return self._heap[0] if self._heap else None

    def tick(self) -> float:
        """Take the earliest tick; its period ticks again a period later. Returns the period."""
        at, period = self._heap[0]
        heapq.heapreplace(self._heap, (at + period, period))
        return period

    def skip_past(self, now: float) -> None:
        """Ticks missed by a face that fell behind are not made up: each period's next is its
        first after `now`, as a clock's alarm that was held up rings once, not again and again."""
        moved = []
        for at, period in self._heap:
            if at <= now:
                at += period * (int((now - at) // period) + 1)
            moved.append((at, period))
        heapq.heapify(moved)
        self._heap = moved

    def copy(self) -> EveryClock:
        twin = EveryClock()
        twin._heap, twin._periods = list(self._heap), set(self._periods)
        return twin
