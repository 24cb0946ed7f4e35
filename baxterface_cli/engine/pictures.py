"""The named parts a theme of pictures shows, read off the expression's numbers.

The numbers (shape_tracks.py) are the one model of the face: nothing keeps named parts beside
them. A theme of pictures shows, from the moment a move of the skin, mouth or brows begins, the
named parts nearest where the numbers are heading, crossfading from the ones it showed over the
move's time, as it always has; `explain` lists the same changes. They are derived here, once
per timeline, from the moves on its tracks.
"""

from __future__ import annotations

from itertools import groupby
from typing import List, NamedTuple

from ..core.expression import Expression
from ..core.presets import FACE_FIELDS, Parts, nearest_parts
from .shape_tracks import ShapeTracks

_FACE = tuple(Expression._fields.index(f) for f in FACE_FIELDS)


class PartsChange(NamedTuple):
    """From `at`, the pictures show the named parts nearest `shows` (where the numbers are
    heading), crossfading from the ones before over `fade` seconds."""

    at: float
    shows: Expression
    fade: float  # seconds

    @property
    def parts(self) -> Parts:
        return nearest_parts(self.shows)


def picture_changes(shape: ShapeTracks, start: Parts) -> List[PartsChange]:
    """Each time a move of the skin, mouth or brows begins whose goal shows other named parts
    than the pictures do: the named parts nearest that goal, over the longest move begun then."""
    heading = list(shape.value(float("-inf")))
    begun = sorted((p.start, i, p) for i in _FACE for p in shape.tracks[i].pieces)
    changes: List[PartsChange] = []
    shown = start
    for at, moves in groupby(begun, key=lambda move: move[0]):
        fade = 0.0
        for _, i, piece in moves:
            heading[i] = piece.end_value
            fade = max(fade, round(piece.end - piece.start, 9))  # the move's duration, unrounded by its times
        goal = Expression(*heading)
        parts = nearest_parts(goal)
        if parts != shown:
            changes.append(PartsChange(at, goal, fade))
            shown = parts
    return changes
