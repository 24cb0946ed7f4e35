"""Tracks: one animated value each, held between timed moves and eased within them."""

from __future__ import annotations

import bisect
from typing import Any, List, NamedTuple

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

    def at(self, t: float) -> Any:
        t = min(t, self.until)
        if t >= self.end or self.end <= self.start:
            return self.end_value
        progress = self.easing((t - self.start) / (self.end - self.start))
        return _mix(self.start_value, self.end_value, progress)

    @property
    def stop(self) -> float:
        return min(self.end, self.until)


class Track:
    """One animated value: held between pieces, eased within them."""

    def __init__(self, initial: Any) -> None:
        self.initial = initial
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
        self.pieces.append(Piece(start, start + max(0.0, duration), current, target, EASINGS[easing]))
        self._starts.append(start)

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
