"""The fallback mouth: shapes from a recording's loudness and spectrum, for any language.

Without pocketsphinx, or for a recording in a language it does not know,
each 10 ms of the sound is put in a class that the speech mouths tell apart,
by what a spectrum shows of the mouth that made it, and named as an
espeak-ng phoneme of that shape, so that the same rules as `say`'s tidy it
(visemes.py):

- silence (quieter than `quiet` of the way from the noise floor to the
  voice's loud level): a pause;
- a hiss (most of the energy above 3.5 kHz: s, sh, z, f, th): "wide";
- a quiet, low hum between louder sounds (m, n, the closure of a b): "closed";
- a voiced sound by its balance of low (F1, an open jaw) and middle (F2, spread
  lips) energy: "open" when loud and low, "wide" when bright, "round" when
  dark, "slight" otherwise.

It cannot tell p from t, or hear a word, so it is rougher than pocketsphinx's
phonemes; docs/speech.md gives its figures beside theirs.
"""

from __future__ import annotations

from typing import List, NamedTuple, Tuple

import numpy as np

from .synthesis import Phoneme


class SpectrumRules(NamedTuple):
    frame: float = 0.01  # seconds a class covers
    window: float = 0.025  # seconds of sound each spectrum is taken over
    quiet: float = 0.25  # under this share of the floor-to-loud range (in dB): silence
    hiss: float = 0.3  # energy above 3.5 kHz over this share of all: a hiss
    faint: float = 0.35  # a hiss under this share: f, th (lips to teeth); over it, s, sh
    hum: float = 0.6  # energy under 400 Hz over this share of all under 4 kHz...
    hum_centre: float = 450.0  # ...its centre of mass (Hz) under this, and not loud: a closed hum
    loud: float = 0.7  # a voice over this share...
    dark: float = 700.0  # ...with its centre of mass under this: rounded lips
    bright: float = 900.0  # ...over this: an open jaw
    spread: float = 0.3  # 1.2-3 kHz energy over this share of 0.2-3 kHz: spread lips


SPECTRUM_RULES = SpectrumRules()
# The phoneme each class is named as (any of the shape's would do).
NAMES = {
    "pause": "_", "faint": "f", "hiss": "s", "hum": "m",
    "open": "a", "wide": "i:", "round": "u:", "slight": "@",
}  # fmt: skip


def spectrum_phonemes(
    sound: np.ndarray, rate: int, rules: SpectrumRules = SPECTRUM_RULES
) -> Tuple[Phoneme, ...]:
    """int16 mono `sound` as a phoneme per run of 10 ms pieces of one class, end to end."""
    classes = frame_classes(sound, rate, rules)
    duration = len(sound) / rate
    out: List[Phoneme] = []
    for i, name in enumerate(classes):
        start, end = i * rules.frame, min(duration, (i + 1) * rules.frame)
        if out and out[-1].name == NAMES[name]:
            out[-1] = out[-1]._replace(end=end)
        else:
            out.append(Phoneme(start, end, NAMES[name]))
    if out and out[-1].end < duration:
        out[-1] = out[-1]._replace(end=duration)
    return tuple(out)


def frame_classes(sound: np.ndarray, rate: int, rules: SpectrumRules = SPECTRUM_RULES) -> List[str]:
    step = max(1, round(rate * rules.frame))
    width = max(step, round(rate * rules.window))
    count = len(sound) // step
    if count == 0:
        return []
    padded = np.concatenate([np.asarray(sound, np.float64), np.zeros(width)])
    index = np.arange(count)[:, None] * step + np.arange(width)[None, :] - (width - step) // 2
    frames = padded[np.clip(index, 0, len(padded) - 1)] * np.hanning(width)
    power = np.abs(np.fft.rfft(frames, axis=1)) ** 2
    freqs = np.fft.rfftfreq(width, 1.0 / rate)

    def band(low: float, high: float) -> np.ndarray:
        return power[:, (freqs >= low) & (freqs < high)].sum(axis=1) + 1e-9

    level = 10 * np.log10(power.sum(axis=1) + 1e-9)
    floor, top = np.percentile(level, 5), np.percentile(level, 97)
    share = np.clip((level - floor) / max(1e-9, top - floor), 0.0, 1.0)
    hiss = band(3500, rate / 2) / band(100, rate / 2)
    below = freqs < 4000
    centre = (power[:, below] * freqs[below]).sum(axis=1) / (power[:, below].sum(axis=1) + 1e-9)
    hum = band(80, 400) / band(80, 4000)
    spread = band(1200, 3000) / band(200, 3000)
    out = []
    for i in range(count):
        if share[i] < rules.quiet:
            out.append("pause")
        elif hiss[i] > rules.hiss:
            out.append("faint" if share[i] < rules.faint else "hiss")
        elif hum[i] > rules.hum and centre[i] < rules.hum_centre and share[i] < rules.loud:
            out.append("hum")
        elif share[i] > rules.loud and centre[i] < rules.dark:
            out.append("round")
        elif share[i] > rules.loud and centre[i] > rules.bright:
            out.append("open")
        elif spread[i] > rules.spread:
            out.append("wide")
        else:
            out.append("slight")
    return out
