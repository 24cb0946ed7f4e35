"""A script's sound: its utterances mixed at their times, and WAV files of it.

Video writers take the track through `Export.audio`; `render --out x.wav`
writes it alone (export/wav.py). Utterances are mixed, not queued, so two `say`s in a
`together` block speak over each other, as written.
"""

from __future__ import annotations

import wave
from typing import BinaryIO, Optional, Sequence, Tuple, Union

import numpy as np

Audio = Tuple[np.ndarray, int]  # mono int16 samples, samples a second
SILENT_RATE = 22050  # a script that says nothing: espeak-ng's own rate


Placed = Tuple[float, np.ndarray, int]  # when a sound starts, its int16 samples, samples a second


def soundtrack(speech: Sequence, duration: float, heard: Sequence[Placed] = ()) -> Optional[Audio]:
    """The utterances of `speech` (timeline `Said`s), and the sounds `heard` (a visitor's voice,
    `render --hear`), mixed over `duration` seconds; None if silent."""
    sounds = [(said.at, said.utterance.samples, said.utterance.sample_rate) for said in speech]
    sounds += list(heard)
    if not sounds:
        return None
    rate = sounds[0][2]
    mix = np.zeros(max(1, round(duration * rate)), np.int32)
    for at, sound, sound_rate in sounds:
        samples = resample(sound, sound_rate, rate)
        start = round(at * rate)
        piece = samples[: max(0, len(mix) - start)]
        mix[start : start + len(piece)] += piece
    return np.clip(mix, -32768, 32767).astype(np.int16), rate


def resample(samples: np.ndarray, rate: int, wanted: int) -> np.ndarray:
    """int16 samples from `rate` to `wanted` a second (0 or equal: as they are); linear, as speech needs."""
    if not wanted or rate == wanted or not len(samples):
        return samples
    times = np.arange(round(len(samples) * wanted / rate)) * (rate / wanted)
    return np.interp(times, np.arange(len(samples)), samples).astype(np.int16)


def write_wav(out: Union[str, BinaryIO], samples: np.ndarray, rate: int) -> None:
    """Mono 16-bit samples as a WAV file, to a path or an open binary file (left open)."""
    with wave.open(out, "wb") as w:
        w.setnchannels(1)
        w.setsampwidth(2)
        w.setframerate(rate)
        w.writeframes(np.asarray(samples).astype("<i2").tobytes())
