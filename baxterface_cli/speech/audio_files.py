"""Sound files read with PyAV (FFmpeg): WAV, FLAC, OGG, MP3 and whatever else FFmpeg reads.

Reading is bounded: a regular file of at most `MAX_BYTES`, whose sound lasts
at most `MAX_SECONDS`, so a recording named by mistake (a device, a film of an
hour) is refused rather than read. PyAV is in the `[lipsync]` extra.
"""

from __future__ import annotations

import os
from typing import Any, List, NamedTuple

import numpy as np

from ..extras import need

EXTRA = "lipsync"
MAX_SECONDS = 600.0  # one recording: ten minutes
MAX_BYTES = 200 * 1024 * 1024
MAX_RATE = 48000  # what is kept to play; higher rates are brought down to it
# Rates every sound encoder we write takes (AAC's); a recording at another is brought to MAX_RATE.
RATES = frozenset((8000, 11025, 12000, 16000, 22050, 24000, 32000, 44100, 48000))
ANALYSIS_RATE = 16000  # what the phonemes are found at: the acoustic model's


class AudioError(ValueError):
    """A sound file that cannot be read; the message says why, without the file's name."""


class Sound(NamedTuple):
    """A recording, mono: int16 `samples` at `rate` to play, and the same at ANALYSIS_RATE."""

    samples: np.ndarray
    rate: int
    analysis: np.ndarray

    @property
    def duration(self) -> float:
        return len(self.samples) / self.rate


def _av() -> Any:
    return need("av", EXTRA, "reading a recording")


def check_file(path: str) -> None:
    """AudioError unless `path` is a regular file of a size we read (no sound is decoded)."""
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise AudioError("no such file") from None
    except OSError as e:
        raise AudioError(e.strerror or str(e)) from None
    if not os.path.isfile(path):
        raise AudioError("not a file")
    if info.st_size > MAX_BYTES:
        raise AudioError(f"too large ({info.st_size // 2**20} MB; the limit is {MAX_BYTES // 2**20} MB)")
    if not os.access(path, os.R_OK):
        raise AudioError("permission denied")


def probe(path: str) -> float:
    """The sound's length in seconds, from its header; AudioError if it has none we can read."""
    check_file(path)
    av = _av()
    try:
        with av.open(path, "r") as container:
            streams = container.streams.audio
            if not streams:
                raise AudioError("it holds no sound")
            stream = streams[0]
            if stream.duration is not None and stream.time_base is not None:
                seconds = float(stream.duration * stream.time_base)
            elif container.duration is not None:
                seconds = container.duration / 1_000_000
            else:
                seconds = 0.0
    except AudioError:
        raise
    except Exception as e:  # FFmpeg's many errors for a file that is not sound
        raise AudioError(_reason(e)) from None
    if seconds > MAX_SECONDS:
        raise AudioError(f"too long ({seconds:.0f} s; the limit is {MAX_SECONDS:.0f} s)")
    return seconds


def read_sound(path: str) -> Sound:
    """The file's first sound stream, mixed to mono; AudioError if it cannot be read."""
    check_file(path)
    av = _av()
    try:
        with av.open(path, "r") as container:
            if not container.streams.audio:
                raise AudioError("it holds no sound")
            stream = container.streams.audio[0]
            rate = int(stream.codec_context.sample_rate or stream.rate or ANALYSIS_RATE)
            rate = rate if rate in RATES else MAX_RATE
            to_play = av.AudioResampler(format="s16", layout="mono", rate=rate)
            played: List[np.ndarray] = []
            count = 0
            for frame in container.decode(stream):
                frame.pts = None  # resample by the samples alone: some files' times jump
                played.extend(piece.to_ndarray().reshape(-1) for piece in to_play.resample(frame))
                count += frame.samples
                if count > MAX_SECONDS * frame.sample_rate:
                    raise AudioError(f"too long (more than {MAX_SECONDS:.0f} s)")
            played.extend(piece.to_ndarray().reshape(-1) for piece in to_play.resample(None))
            samples = _joined(played)
            heard = _joined(_resampled(av, samples, rate, ANALYSIS_RATE))
    except AudioError:
        raise
    except Exception as e:  # FFmpeg's many errors for a file that is not sound
        raise AudioError(_reason(e)) from None
    if not len(samples):
        raise AudioError("it holds no sound")
    return Sound(samples, rate, heard)


def _resampled(av: Any, samples: np.ndarray, rate: int, wanted: int) -> List[np.ndarray]:
    """int16 mono `samples` at `wanted` a second, by FFmpeg's resampler (filtered, unlike a line's)."""
    out = av.AudioResampler(format="s16", layout="mono", rate=wanted)
    pieces: List[np.ndarray] = []
    step = rate  # a second a frame
    for start in range(0, len(samples), step):
        frame = av.AudioFrame.from_ndarray(
            np.ascontiguousarray(samples[start : start + step]).reshape(1, -1), format="s16", layout="mono"
        )
        frame.sample_rate = rate
        pieces.extend(piece.to_ndarray().reshape(-1) for piece in out.resample(frame))
    pieces.extend(piece.to_ndarray().reshape(-1) for piece in out.resample(None))
    return pieces


def _joined(pieces: List[np.ndarray]) -> np.ndarray:
    out = np.concatenate(pieces).astype(np.int16) if pieces else np.zeros(0, np.int16)
    out.flags.writeable = False
    return out


def _reason(error: Exception) -> str:
    """FFmpeg's words for what is wrong, without the file name it repeats."""
    text = getattr(error, "strerror", None) or str(error) or type(error).__name__
    text = text.split(":")[0].strip() if ": '" in text else text.strip()
    return f"not a sound file FFmpeg reads ({text.lower()})"
