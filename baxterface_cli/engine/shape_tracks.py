"""The expression's numbers on a timeline: one track each, so moves of different parts compose.

`together { mouth curve 1 in 1s; brows height 1 in 1s }` moves the mouth and the brows at
once; were the expression one track, the second move would cut the first short.
"""

from __future__ import annotations

from typing import Iterable, List, Optional

from ..core.expression import Expression
from .tracks import Owner, Track


class ShapeTracks:
    """An `Expression` over time: a `Track` per field."""

    def __init__(self, initial: Expression, owner: Optional[Owner] = None) -> None:
        self.tracks: List[Track] = [Track(v, owner) for v in initial]
        self._initial = initial

    def value(self, t: float) -> Expression:
        if not any(track.pieces for track in self.tracks):
            return self._initial
        return Expression(*(track.value(t) for track in self.tracks))

    def move(
        self,
        at: float,
        duration: float,
        target: Expression,
        easing: str = "linear",
        fields: Optional[Iterable[str]] = None,
    ) -> None:
        """Move `fields` (by default every one) toward `target` from `at`; the rest go on."""
        wanted = None if fields is None else set(fields)
        for name, track, goal in zip(Expression._fields, self.tracks, target):
            if wanted is not None and name not in wanted:
                continue
            if at >= track.end and track.value(at) == goal:
                continue  # already there, and nothing under way to stop: no piece to add
            track.move(at, duration, goal, easing)

    def busy(self, fields: Iterable[str], start: float, end: float) -> bool:
        named = set(fields)
        return any(
            track.busy(start, end) for name, track in zip(Expression._fields, self.tracks) if name in named
        )

    def carry(self, old: ShapeTracks, at: float) -> None:
        """Each field's `Track.carry`."""
        for track, before in zip(self.tracks, old.tracks):
            track.carry(before, at)

    @property
    def end(self) -> float:
        return max(track.end for track in self.tracks)
