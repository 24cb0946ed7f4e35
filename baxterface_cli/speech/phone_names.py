"""pocketsphinx's phones (ARPAbet) as espeak-ng's phonemes, timed as espeak-ng times its own.

The mouth's table and rules (visemes.py) speak espeak-ng's names, so a
recording's phones are renamed into them (`ESPEAK_NAMES`), with what the
names alone do not carry:

- A stop (p, t, k, b, d, g, ch, j) starts at its burst, as espeak-ng reports
  its stops: the silent closure before it is the sound's (or the pause's) before.
- An r after a vowel, not before one ("there", "more"), is the vowel's: it
  colours the vowel, as espeak-ng's "e@", "O@" do, and the mouth holds it;
  an l there ("bill", "cold") is half the vowel's, the dark l's vowel colour.
- The "th" of "the", "this" before its vowel is short, as espeak-ng says it
  (`SHORT_DH`); pocketsphinx's runs on into the vowel.
- AH is "cup" (open) or the unstressed "the", "a" (slight): louder than the
  recording's middling vowel, the first.

`SPELLINGS` is the way back, for the words pocketsphinx's dictionary lacks,
which espeak-ng spells.
"""

from __future__ import annotations

from typing import Dict, List, Tuple

import numpy as np

from .phones_heard import FRAME
from .synthesis import Phoneme

ESPEAK_NAMES: Dict[str, str] = {
    "AA": "A:", "AE": "a", "AH": "V", "AO": "O:", "AW": "aU", "AY": "aI", "B": "b", "CH": "tS",
    "D": "d", "DH": "D", "EH": "E", "ER": "3:", "EY": "eI", "F": "f", "G": "g", "HH": "h", "IH": "I",
    "IY": "i:", "JH": "dZ", "K": "k", "L": "l", "M": "m", "N": "n", "NG": "N", "OW": "oU", "OY": "OI",
    "P": "p", "R": "r", "S": "s", "SH": "S", "T": "t", "TH": "T", "UH": "U", "UW": "u:", "V": "v",
    "W": "w", "Y": "j", "Z": "z", "ZH": "Z",
}  # fmt: skip
SCHWA = "@"
PAUSE = "_"  # silence, and pocketsphinx's noises (+NSN+, +SPN+, +BREATH+...)
STOPS = frozenset(["P", "B", "T", "D", "K", "G", "CH", "JH"])
VOWELS = frozenset(["AA", "AE", "AH", "AO", "AW", "AY", "EH", "ER", "EY", "IH", "IY", "OW", "OY", "UH", "UW"])
BURST = 0.3  # a stop's burst: its first frame this loud, relative to its loudest
SHORT_DH = 0.03  # the longest a "th" of "the", "this" lasts before its vowel

# espeak-ng's English phonemes in pocketsphinx's phones, to spell the words its dictionary lacks.
SPELLINGS: Dict[str, Tuple[str, ...]] = {
    **{k: (v,) for k, v in {
        "p": "P", "b": "B", "t": "T", "t#": "T", "d": "D", "d#": "D", "k": "K", "g": "G", "m": "M",
        "m-": "M", "n": "N", "n-": "N", "N": "NG", "f": "F", "v": "V", "T": "TH", "D": "DH", "s": "S",
        "z": "Z", "S": "SH", "Z": "ZH", "tS": "CH", "dZ": "JH", "h": "HH", "x": "HH", "l": "L",
        "l/": "L", "r": "R", "r-": "R", "w": "W", "w#": "W", "j": "Y", "@": "AH", "@2": "AH",
        "@5": "AH", "a#": "AH", "a2": "AH", "V": "AH", "3": "ER", "3:": "ER", "a": "AE", "aa": "AE",
        "A:": "AA", "A#": "AA", "0": "AA", "E": "EH", "eI": "EY", "i": "IY", "i:": "IY", "I": "IH",
        "I2": "IH", "I#": "IH", "O:": "AO", "O2": "AO", "OI": "OY", "oU": "OW", "U": "UH", "u:": "UW",
        "aI": "AY", "aI2": "AY", "aI3": "AY", "aU": "AW",
    }.items()},
    "@L": ("AH", "L"), "A@": ("AA", "R"), "e@": ("EH", "R"), "i@": ("IY", "R"), "i@3": ("IY", "R"),
    "IR": ("IH", "R"), "O@": ("AO", "R"), "o@": ("AO", "R"), "U@": ("UH", "R"), "u@": ("UH", "R"),
    "aI@": ("AY", "ER"),
}  # fmt: skip


def spelled(names: List[str]) -> List[str]:
    """espeak-ng's phoneme names (a word it said) as pocketsphinx's phones; unknown ones left out."""
    return [phone for name in names for phone in SPELLINGS.get(name, ())]


def frame_loudness(sound: np.ndarray, rate: int) -> np.ndarray:
    """RMS of each FRAME of `sound`."""
    step = max(1, round(rate * FRAME))
    count = len(sound) // step
    blocks = np.asarray(sound[: count * step], np.float64).reshape(count, step)
    return np.sqrt((blocks * blocks).mean(axis=1)) if count else np.zeros(0)


def espeak_phonemes(
    phones: Tuple[Tuple[float, float, str], ...], sound: np.ndarray, rate: int
) -> Tuple[Phoneme, ...]:
    """The phones (end to end, from `phones_heard`) as espeak-ng's phonemes, by the rules above."""
    loud = frame_loudness(sound, rate)
    spans = [[start, end, name] for start, end, name in phones]
    _stops_at_their_bursts(spans, loud)
    for i in range(len(spans) - 1):
        if spans[i][2] == "DH" and spans[i + 1][2] in VOWELS and spans[i][1] - spans[i][0] > SHORT_DH:
            spans[i][1] = spans[i + 1][0] = spans[i][0] + SHORT_DH
    peaks = [_peak(loud, start, end) for start, end, _ in spans]
    vowels = [peak for peak, (_, _, name) in zip(peaks, spans) if name in VOWELS]
    middling = float(np.median(vowels)) if vowels else 0.0
    out: List[Phoneme] = []
    for i, (start, end, name) in enumerate(spans):
        if end <= start:
            continue
        before = spans[i - 1][2] if i else ""
        after = spans[i + 1][2] if i + 1 < len(spans) else ""
        if name == "R" and before in VOWELS and after not in VOWELS and out:
            out[-1] = out[-1]._replace(end=end)
            continue
        if name == "L" and before in VOWELS and after not in VOWELS and out:
            middle = (start + end) / 2
            out[-1] = out[-1]._replace(end=middle)
            start = middle
        espeak = ESPEAK_NAMES.get(name, PAUSE)
        if name == "AH" and peaks[i] < middling:
            espeak = SCHWA
        out.append(Phoneme(start, end, espeak))
    return tuple(out)


def _peak(loud: np.ndarray, start: float, end: float) -> float:
    a = min(len(loud), int(round(start / FRAME)))
    b = min(len(loud), max(a + 1, int(round(end / FRAME))))
    return float(loud[a:b].max()) if b > a else 0.0


def _stops_at_their_bursts(spans: List[list], loud: np.ndarray) -> None:
    """Each stop from its burst: its first frame at BURST of its loudest, or, when all of it is
    closure (as after a pause, a burst falling in the next phone's first frame), that frame."""
    if not len(loud):
        return
    floor, high = np.percentile(loud, 5), np.percentile(loud, 90)
    audible = loud > max(3.0 * floor, 0.05 * high)
    for i in range(len(spans)):
        start, end, name = spans[i]
        if name not in STOPS:
            continue
        a, b = int(round(start / FRAME)), min(len(loud), int(round(end / FRAME)))
        if b <= a:
            continue
        if not audible[a:b].any() and i + 1 < len(spans) and spans[i + 1][1] - end > 2 * FRAME:
            spans[i][0], spans[i][1] = end, end + FRAME
            spans[i + 1][0] = end + FRAME
            if i:
                spans[i - 1][1] = end
            continue
        piece = loud[a:b]
        strong = piece >= BURST * piece.max()
        # The closure is the quiet after what is left of the sound before; the burst ends it.
        quiet = np.flatnonzero(~strong)
        if not len(quiet) or not i:
            continue
        after = np.flatnonzero(strong[quiet[0] :])
        burst = a + quiet[0] + (int(after[0]) if len(after) else len(piece) - 1 - quiet[0])
        if burst > a:
            spans[i][0] = spans[i - 1][1] = burst * FRAME
