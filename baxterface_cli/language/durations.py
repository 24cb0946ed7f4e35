"""How long speech may take, bounded without speaking it: `speech_bound`.

A statement's length is resolved in statements.py, for the compiler, the checker (a script's
length) and `explain` alike. `say` is the one statement whose length only the speech engine
knows: it is bounded from above here, so that a script that passes the length limit cannot
speak longer than it; a recording's length is in its file, which speech/recordings.py reads
(`checker.check_length`).
"""

from __future__ import annotations

from ..core.voices import DEFAULT_RATE

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
