"""The tables the studio's page is built with: the words its editor highlights, and what its mood
pad and intensity slider offer, each from the tables the language itself uses."""

from __future__ import annotations

from typing import Any, Dict, List

from ..core.easing import EASINGS
from ..core.face_constants import BROWS, DIRECTIONS, EMOTIONS, MOUTHS
from ..core.presets import MOOD_CIRCLE
from ..language.parser import grammar_words
from ..language.vocabulary import BARE_WORDS


def vocabulary() -> Dict[str, List[str]]:
    """The words the editor highlights, from the tables the parser uses."""
    return {
        "keywords": grammar_words(),
        "words": sorted(BARE_WORDS),
        "emotions": sorted(name for name in EMOTIONS if " " not in name),
        "easings": sorted(EASINGS),
        "mouths": list(MOUTHS),
        "brows": list(BROWS),
        "directions": sorted(DIRECTIONS),
    }


def feelings() -> Dict[str, Any]:
    """What the mood pad and the intensity slider offer: the emotions a script may give an
    intensity (`happy 0.4`; `default` at any intensity is the neutral face, so it is left out),
    and where each emotion sits on the mood circle, in degrees from pleasant (core/presets.py)."""
    return {
        "emotions": [name.replace(" ", "_") for name in EMOTIONS if name != "default"],
        "mood_circle": [{"emotion": name, "degrees": degrees} for name, degrees in MOOD_CIRCLE],
    }
