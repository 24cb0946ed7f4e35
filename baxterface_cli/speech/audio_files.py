"""Sound files read with PyAV (FFmpeg): WAV, FLAC, OGG, MP3 and whatever else FFmpeg reads.

Reading is bounded: a regular file (opened without waiting, see wav_header.py)
of at most `MAX_BYTES`, whose sound lasts at most `MAX_SECONDS`, read within
`READ_SECONDS`, so a recording named by mistake (a device, a film of an hour,
a file of junk) is refused rather than read. A WAV file's header is checked
without FFmpeg, the same way for `check` and for `render`. PyAV is in the
`[lipsync]` extra.
"""

from __future__ import annotations

import os
import time
from typing import Any, BinaryIO, List, NamedTuple, Optional

import numpy as np

from ..extras import MissingTool, need
from .wav_header import HeaderError, open_recording, wav_header

EXTRA = "lipsync"
MAX_SECONDS = 600.0  # one recording: ten minutes
MAX_BYTES = 200 * 1024 * 1024
MAX_RATE = 48000  # what is kept to play; higher rates are brought down to it
# Rates every sound encoder we write takes (AAC's); a recording at another is brought to MAX_RATE.
RATES = frozenset((8000, 11025, 12000, 16000, 22050, 24000, 32000, 44100, 48000))
ANALYSIS_RATE = 16000  # what the phonemes are found at: the acoustic model's
READ_SECONDS = 60.0  # the longest reading one recording may take: ten minutes decode in a few seconds


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


def check_file(path: str) -> BinaryIO:
    """`path` opened, a regular file of a size we read (AudioError otherwise); the caller closes it."""
    try:
        file = open_recording(path)
    except HeaderError as e:
        raise AudioError(str(e)) from None
    size = os.fstat(file.fileno()).st_size
    if size > MAX_BYTES:
        file.close()
        raise AudioError(f"too large ({size // 2**20} MB; the limit is {MAX_BYTES // 2**20} MB)")
    return file


def _header_seconds(file: BinaryIO) -> Optional[float]:
    """A WAV file's length from its checked header; None for another kind of file."""
    try:
        header = wav_header(file)
        file.seek(0)
    except HeaderError as e:
        raise AudioError(str(e)) from None
    except OSError as e:  # a file that is not one to read (/proc/self/mem: an I/O error)
        raise AudioError(f"it cannot be read ({(e.strerror or str(e)).lower()})") from None
    if header is not None and header.seconds > MAX_SECONDS:
        raise AudioError(f"too long ({header.seconds:.0f} s; the limit is {MAX_SECONDS:.0f} s)")
    return None if header is None else header.seconds


def probe(path: str) -> float:
    """The sound's length in seconds, from its header; AudioError if it has none we can read.

    Without PyAV, AudioError too, naming the extra: `render` could not read it either.
    """
    with check_file(path) as file:
        seconds = _header_seconds(file)
        try:
            av = _av()
        except MissingTool as e:
            raise AudioError(str(e)) from None
        if seconds is not None:
            return seconds
        try:
            with av.open(file, "r") as container:
                streams = container.streams.audio
                if not streams:
                    raise AudioError("it holds no sound")
                stream = streams[0]
                if not stream.codec_context.channels or not stream.codec_context.sample_rate:
                    raise AudioError("its sound has no channels or no sample rate")
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


def read_sound(path: str, seconds: float = READ_SECONDS) -> Sound:
    """The file's first sound stream, mixed to mono; AudioError if it cannot be read, or if
    reading it takes longer than `seconds` (FFmpeg's time on a file of junk is not bounded)."""
    deadline = time.monotonic() + seconds
    with check_file(path) as file:
        _header_seconds(file)
        av = _av()
        try:
            with av.open(file, "r") as container:
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
                    if time.monotonic() > deadline:
                        raise AudioError(f"it took more than {seconds:.0f} s to read")
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


def analysis_sound(samples: np.ndarray, rate: int) -> np.ndarray:
    """int16 mono `samples` at `rate` brought to ANALYSIS_RATE, read-only (PyAV resamples)."""
    return _joined(_resampled(_av(), samples, rate, ANALYSIS_RATE))


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
