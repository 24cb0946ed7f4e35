"""The phonemes in a recording, recognised without its words by hama (the `[lipsync]` extra).

hama's phoneme recogniser (Apache-2.0) is a small CTC model, 4.7 MB, that
ships inside its wheel with the native engine that runs it (numpy only;
nothing is downloaded). It hears IPA phonemes, word by word, far more
surely than pocketsphinx's phoneme loop, but it places them only roughly
(CTC emits a phoneme at a peak, not over its length). So its phonemes are
renamed into pocketsphinx's phones (`IPA_PHONES`) and each word it heard
is aligned to the sound by pocketsphinx as a word of those phones
(phones_heard.py), as the words of a `text` are.
"""

from __future__ import annotations

import threading
import unicodedata
from typing import Any, Dict, List, Tuple

import numpy as np

from ..extras import need
from .audio_files import EXTRA

# hama's IPA tokens as pocketsphinx's phones (ARPAbet). It hears many languages' phonemes; an
# English speaker's are mostly the first lines. Tokens not here are looked up by their longest
# start that is (kʰ as k); marks, tones and what has no phone (the glottal stop) are left out.
IPA_PHONES: Dict[str, Tuple[str, ...]] = {
    **{k: (v,) for k, v in {
        # vowels
        "i": "IY", "ɪ": "IH", "e": "EY", "ɛ": "EH", "æ": "AE", "a": "AE", "ɑ": "AA", "ɒ": "AA",
        "ɔ": "AO", "o": "OW", "ʊ": "UH", "u": "UW", "ʌ": "AH", "ə": "AH", "ɐ": "AH", "ᵊ": "AH",
        "ɘ": "AH", "ɤ": "AH", "ɜ": "ER", "ɝ": "ER", "ɚ": "ER", "ɨ": "IH", "ʉ": "UW", "y": "UW",
        "ʏ": "UH", "ø": "OW", "ɵ": "OW", "œ": "AO", "ɯ": "UW", "aɪ": "AY", "aʊ": "AW", "eɪ": "EY",
        "oʊ": "OW", "ɔɪ": "OY", "à": "AA", "ä": "AA", "å": "AO", "ã": "AA", "ẽ": "EH", "ĩ": "IY",
        "õ": "OW", "ũ": "UW", "ì": "IY", "ǐ": "IY",
        # consonants
        "p": "P", "b": "B", "β": "B", "ʙ": "B", "ɓ": "B", "t": "T", "ʈ": "T", "d": "D", "ɖ": "D",
        "ɗ": "D", "ɾ": "D", "k": "K", "c": "K", "g": "G", "ɡ": "G", "ɟ": "G", "ɣ": "G", "m": "M",
        "ɱ": "M", "n": "N", "ɲ": "N", "ñ": "N", "ŋ": "NG", "ɴ": "NG", "f": "F", "ɸ": "F", "v": "V",
        "ʋ": "V", "θ": "TH", "ð": "DH", "s": "S", "z": "Z", "ẑ": "Z", "ʃ": "SH", "ɕ": "SH", "ʂ": "SH",
        "ʒ": "ZH", "ʑ": "ZH", "ʐ": "ZH", "t͡ʃ": "CH", "t͡ɕ": "CH", "d͡ʒ": "JH", "h": "HH", "ɦ": "HH",
        "x": "HH", "ç": "HH", "χ": "HH", "ħ": "HH", "l": "L", "ɫ": "L", "ɮ": "L", "ʎ": "L", "r": "R",
        "ɹ": "R", "ɻ": "R", "ɽ": "R", "ʀ": "R", "ʁ": "R", "˞": "R", "w": "W", "ɰ": "W", "j": "Y",
        "ʝ": "Y", "ɥ": "Y",
    }.items()},
    "ɪə": ("IY", "R"), "eə": ("EH", "R"), "ɯi": ("UW", "IY"),
    "ja": ("Y", "AA"), "je": ("Y", "EH"), "jo": ("Y", "OW"), "ju": ("Y", "UW"), "jʌ": ("Y", "AH"),
    "wa": ("W", "AA"), "we": ("W", "EH"), "wi": ("W", "IY"), "wʌ": ("W", "AH"),
}  # fmt: skip
# hama hears each word as a dictionary spells it; speech reduces "the" and "to" before a
# consonant to a schwa ("the" before a vowel is "thee"), and says "I" for the lone "ee" it writes.
REDUCED = {
    ("DH", "IY"): ("DH", "AH"),
    ("DH", "AE"): ("DH", "AH"),
    ("T", "UW"): ("T", "AH"),
    ("T", "OW"): ("T", "AH"),
}
SAID = {("IY",): ("AY",)}
VOWELS = frozenset(["AA", "AE", "AH", "AO", "AW", "AY", "EH", "ER", "EY", "IH", "IY", "OW", "OY", "UH", "UW"])
_LOCK = threading.Lock()  # one model a process, used by one thread at a time
_models: List[Any] = []
_missing: List[bool] = []


def available() -> bool:
    """Whether hama can be loaded here (installed, and its engine built for this machine)."""
    if _missing:
        return False
    try:
        _model()
    except Exception:  # MissingTool; RuntimeError where no engine is built for the machine
        _missing.append(True)  # asked at every `say file`: not looked for again
        return False
    return True


def _model() -> Any:
    with _LOCK:
        if not _models:
            hama = need("hama", EXTRA, "lip-sync from a recording without its words")
            _models.append(hama.ASRModel())
        return _models[0]


def phones(token: str) -> Tuple[str, ...]:
    """pocketsphinx's phones for one of hama's IPA tokens: the longest start of it in IPA_PHONES
    (t͡ɕʰ as t͡ɕ, õ as o); () for a mark, a tone or a pause."""
    token = unicodedata.normalize("NFD", token)
    for end in range(len(token), 0, -1):
        found = IPA_PHONES.get(unicodedata.normalize("NFC", token[:end]))
        if found is not None:
            return found
    return ()


def recognise(sound: np.ndarray, rate: int, english: bool = True) -> List[List[str]]:
    """The words heard in int16 mono `sound`, each as pocketsphinx's phones (none: no word); in
    `english`, as connected speech says them."""
    model = _model()
    with _LOCK:
        result = model.transcribe_waveform(np.asarray(sound), rate)
    words = []
    for word in result.word_phoneme_text.split(" | "):
        spelled = [phone for token in word.split() for phone in phones(token)]
        if spelled:
            words.append(spelled)
    return connected(words) if english else words


def connected(words: List[List[str]]) -> List[List[str]]:
    """The words as they are said one after another (REDUCED, SAID)."""
    out = []
    for i, word in enumerate(words):
        key = tuple(word)
        after = words[i + 1][0] if i + 1 < len(words) else ""
        if key in REDUCED and after and after not in VOWELS:
            key = REDUCED[key]
        out.append(list(SAID.get(key, key)))
    return out
