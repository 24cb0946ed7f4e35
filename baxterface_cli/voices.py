"""The voices and rates `say` accepts, known without a speech engine.

The voice names are a table carried with the package (data/voices.txt, made
from `espeak-ng --voices`), so `check` validates a script on a machine with
no espeak-ng; the speech engine itself is in `speech`.
"""

from __future__ import annotations

from functools import lru_cache
from typing import FrozenSet, Tuple

from .resources import resource

DEFAULT_VOICE = "en"
DEFAULT_RATE = 175  # words a minute: espeak-ng's own default
# espeak-ng speaks from 80 words a minute; from 450 it switches to a speed-up mode
# whose phoneme times drift (and, in 1.51, which speaks slower than 449).
RATES = (80, 400)


@lru_cache(maxsize=1)
def voice_names() -> Tuple[str, ...]:
    """Every voice name, sorted."""
    text = resource("data/voices.txt").read_text(encoding="utf-8")
    lines = (line.strip() for line in text.splitlines())
    return tuple(sorted({line.lower() for line in lines if line and not line.startswith("#")}))


@lru_cache(maxsize=1)
def _known() -> FrozenSet[str]:
    return frozenset(voice_names())


def known_voice(name: str) -> bool:
    return name.lower() in _known()


def estimated_seconds(text: str, rate: int = DEFAULT_RATE) -> float:
    """About how long `text` takes to say, without speaking it: for checking a script's length."""
    words = len(text.split())
    pauses = sum(text.count(mark) for mark in ",.;:!?")
    return words * 60.0 / rate + 0.3 * pauses
