"""How long each statement takes: the one place a default duration is resolved.

The compiler, the checker (a script's length) and `explain` all ask here, so
they can never disagree about how long `look left` lasts. `say` is the one
statement whose length only the speech engine knows; here it is estimated,
for checking a script's length without an engine.
"""

from __future__ import annotations

from typing import Any, Dict

from ..core.tables import EMOTIONS, TIMING
from ..core.voices import DEFAULT_RATE, estimated_seconds
from . import syntax_tree as n

# The moves a script may time with `in T`, and how long they take when it does not.
DEFAULT_MOVE_SECONDS: Dict[type, float] = {
    n.Look: TIMING.look,
    n.Wobble: TIMING.wobble,
    n.Eyelids: TIMING.eyelids,
    n.Mood: TIMING.mood,
    n.Adjust: TIMING.adjust,
}


def move_seconds(statement: Any) -> float:
    """A timed move's duration: its own `in T`, or its kind's default."""
    duration = statement.timing.duration
    return DEFAULT_MOVE_SECONDS[type(statement)] if duration is None else duration


def statement_seconds(statement: Any) -> float:
    """How long one simple (not block) statement takes on the script's clock."""
    if type(statement) in DEFAULT_MOVE_SECONDS:
        return move_seconds(statement)
    if isinstance(statement, n.Emotion):
        return EMOTIONS[statement.name].lid_seconds
    if isinstance(statement, n.Feeling):
        # Timed, a morph of that length; else a morph as long as the slowest emotion's lids take.
        if statement.timing.duration is not None:
            return statement.timing.duration
        return max(EMOTIONS[name].lid_seconds for name, _ in statement.weights)
    if isinstance(statement, n.Wink):
        return TIMING.wink_close + TIMING.wink_hold + TIMING.wink_open
    if isinstance(statement, n.Wait):
        return statement.duration
    if isinstance(statement, n.Blink):
        return TIMING.blink_close + TIMING.blink_open
    if isinstance(statement, n.Nod):
        return TIMING.nod
    if isinstance(statement, n.Say):
        # A recording's length is in its file, which the language does not read: its words at the
        # default rate stand in.
        return estimated_seconds(statement.text, statement.rate or DEFAULT_RATE)
    return 0.0
