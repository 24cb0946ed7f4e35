"""A phrase spoken by espeak-ng into a WAV file, for the tests that hear it: where its last word
ends is read from the sound (its last sample above 5 % of the loudest)."""

from __future__ import annotations

import subprocess
import wave
from pathlib import Path
from typing import Tuple

import numpy as np


def spoken(path: Path, text: str, quiet: float = 0.0) -> Tuple[np.ndarray, int, float]:
    """`text` (en-us) written to `path` after `quiet` seconds of silence: its samples (as floats,
    the silence left out), their rate, and when its last word ends in the file, in seconds."""
    subprocess.run(["espeak-ng", "-v", "en-us", "-w", str(path), text], check=True)
    with wave.open(str(path), "rb") as w:
        rate, frames = w.getframerate(), w.readframes(w.getnframes())
    if quiet:
        with wave.open(str(path), "wb") as w:
            w.setnchannels(1), w.setsampwidth(2), w.setframerate(rate)
            w.writeframes(b"\0\0" * int(quiet * rate) + frames)
    samples = np.frombuffer(frames, "<i2").astype(float)
    last_loud = int(np.nonzero(np.abs(samples) > 0.05 * np.abs(samples).max())[0][-1])
    return samples, rate, quiet + last_loud / rate
