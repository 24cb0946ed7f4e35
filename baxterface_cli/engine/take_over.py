"""A command that takes over a live face lets what the face already began finish.

Without this, `sad` followed 0.1 s later by `wink left` left the face happy while its state
said sad: the wink, compiled from the face as it was, dropped sad's mouth, due after its lids.
"""

from __future__ import annotations

from typing import Any, NamedTuple

from .timeline import Timeline


class Carry(NamedTuple):
    """What a command that takes over lets run on: the timeline it takes over from, and how far
    into it the take-over comes. The moves of statements already begun there
    finish (a wink still reopens, `sad` still changes its mouth after its lids); the statements
    not yet begun are dropped."""

    timeline: Timeline
    at: float


def carry_over(compiler: Any, carry: Carry) -> None:
    """Give `compiler` (compiler.py's, which imports this), before it compiles a statement, what
    statements begun in `carry.timeline` still have to do. Moves of the same number by the new
    script take over from these as from any move under way."""
    old, at = carry.timeline, carry.at
    for track, before in ((compiler.eyes, old.eyes), (compiler.lids, old.lids), (compiler.head, old.head)):
        track.carry(before, at)
    if old.shape is not None:
        compiler.shape.carry(old.shape, at)
