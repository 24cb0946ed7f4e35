"""How long each statement takes: the one place a default duration is resolved.

The compiler, the checker (a script's length) and `explain` all ask here, so
they can never disagree about how long `look left` lasts. `say` is the one
statement whose length only the speech engine knows: here it is bounded from
above (`speech_bound`), so that a script that passes the length limit cannot
speak longer than it; a recording's length is in its file, which
speech/recordings.py reads (`checker.check_length`).
"""

from __future__ import annotations

from typing import Any, Dict

from ..core.tables import EMOTIONS, TIMING
from ..core.voices import DEFAULT_RATE
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
        if statement.file is not None:  # read from its header where the file is read
            return 0.0
        return speech_bound(statement.text, statement.rate or DEFAULT_RATE)
    return 0.0


# The most seconds one character takes to say at 80 words a minute, espeak-ng's slowest, in any
# of its voices. Measured with espeak-ng 1.51 on every voice (assets/speech_bound.py), a voice
# spells what it cannot read by name ("Ethiopic syllable ..." in sw: 5.7 s a character; "}" in
# ky: 3.7 s; "1234567890" in tn: 2.2 s; spelled Latin letters in qdb: 1.0 s), with about 15%
# to spare. Any other character counts as the worst.
SECONDS_A_CHARACTER_AT_80 = {"letter": 1.1, "space": 1.1, "digit": 2.5, "sign": 4.3}
WORST_AT_80 = 6.6
# A faster rate shortens speech by less than the ratio of the rates (at 400, 0.26 of 80's, not 0.2).
RATE_POWER = 0.8


def speech_bound(text: str, rate: int = DEFAULT_RATE) -> float:
    """The longest `text` can take to say at `rate`, in any voice, without speaking it."""
    total = 0.0
    for char in text:
        if char.isascii():
            kind = "digit" if char.isdigit() else "letter" if char.isalpha() else "space"
            if not (char.isalnum() or char.isspace()):
                kind = "sign"
            total += SECONDS_A_CHARACTER_AT_80[kind]
        else:
            total += WORST_AT_80
    return total * (80.0 / max(rate, 1)) ** RATE_POWER
