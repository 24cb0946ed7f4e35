"""Tracks: one animated value each, held between timed moves and eased within them."""

from __future__ import annotations

import bisect
from typing import Any, List, NamedTuple, Optional

from ..core.easing import EASINGS, Easing


class Piece(NamedTuple):
    """A track moving from `start_value` to `end_value` over [start, end).

    A move interrupted at `until` holds the value its curve had reached
    then; the curve itself is kept, so an eased move is cut, not reshaped.
    """

    start: float
    end: float
    start_value: Any
    end_value: Any
    easing: Easing  # looked up once, when the move is made: sampling only calls it
    until: float = float("inf")
    # When the statement that made the move began: a command that takes over lets the moves of
    # statements already begun run their course (see `Track.carry`).
    owner: float = float("-inf")

    def at(self, t: float) -> Any:
        t = min(t, self.until)
        if t >= self.end or self.end <= self.start:
            return self.end_value
        progress = self.easing((t - self.start) / (self.end - self.start))
        return _mix(self.start_value, self.end_value, progress)

    @property
    def stop(self) -> float:
        return min(self.end, self.until)


class Owner:
    """The start of the statement whose moves are being made: the compiler sets it, tracks read it."""

    __slots__ = ("at",)

    def __init__(self) -> None:
        self.at = float("-inf")


class Track:
    """One animated value: held between pieces, eased within them."""

    def __init__(self, initial: Any, owner: Optional[Owner] = None) -> None:
        self.initial = initial
        self.owner = owner
        self.pieces: List[Piece] = []
        self._starts: List[float] = []

    def value(self, t: float) -> Any:
        i = bisect.bisect_right(self._starts, t) - 1
        return self.initial if i < 0 else self.pieces[i].at(t)

    def move(self, start: float, duration: float, target: Any, easing: str = "linear") -> None:
        """From wherever the track is at `start`, move to `target`; later pieces give way."""
        current = self.value(start)
        i = bisect.bisect_left(self._starts, start)
        if i > 0 and self.pieces[i - 1].stop > start:  # interrupt the move under way
            self.pieces[i - 1] = self.pieces[i - 1]._replace(until=start)
        del self.pieces[i:], self._starts[i:]  # and drop moves queued after it
        owner = float("-inf") if self.owner is None else self.owner.at
        self.pieces.append(
            Piece(start, start + max(0.0, duration), current, target, EASINGS[easing], owner=owner)
        )
        self._starts.append(start)

    def carry(self, old: Track, at: float) -> None:
        """Take on, shifted to start at `at` on `old`'s clock, the moves of `old` that statements
        begun by then made and that have not finished: the rest of a move under way, and what a
        begun statement still has to do (a wink's reopening, an emotion's parts after its lids).
        Call before any move of this track's own."""
        kept = [p for p in old.pieces if p.owner <= at and p.stop > at]
        starts = {p.start for p in kept}
        for p in kept:
            # Cut short only by a move that is carried too: one of a statement not begun is dropped.
            until = p.until if p.until in starts else float("inf")
            self.pieces.append(p._replace(start=p.start - at, end=p.end - at, until=until - at))
            self._starts.append(p.start - at)

    def busy(self, start: float, end: float) -> bool:
        """Does any piece move the track during [start, end)?"""
        return any(p.start < end and start < p.stop for p in self.pieces)

    @property
    def end(self) -> float:
        return self.pieces[-1].stop if self.pieces else 0.0


def _mix(a: Any, b: Any, u: float) -> Any:
    if isinstance(a, tuple):
        return tuple(x + (y - x) * u for x, y in zip(a, b))
    return a + (b - a) * u
