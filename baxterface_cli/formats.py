"""What `render --out` can write, keyed by the file's extension: a table, not a switch.

Each format opens a `FrameSink` that takes the frames in order with their
times and writes a partial file beside the target (see partial.py), renamed
into place by `close` only when complete. Formats that need an optional
library name the extra that brings it.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from pathlib import Path
from typing import Callable, Dict, NamedTuple, Optional, Sequence, Tuple

import numpy as np

from .effects import Cue

Size = Tuple[int, int]


class Export(NamedTuple):
    """What a format may need besides the frames themselves."""

    size: Size  # (width, height)
    fps: float
    duration: float  # the script's length, seconds
    cues: Sequence[Cue] = ()  # robot effects at their times (bags)
    robot: str = "baxter"  # whose screen a bag's frames go to
    frame_at: Optional[Callable[[float], np.ndarray]] = None  # any frame, ahead (GIF palettes)
    palette_times: Sequence[float] = ()  # moments that between them show every colour
    audio: Optional[Tuple[np.ndarray, int]] = None  # the script's sound: mono int16 samples, rate


class FrameSink(ABC):
    """Frames in, one file (or folder) out, whole or not at all."""

    @abstractmethod
    def add(self, frame_bgr: np.ndarray, t: float) -> None:
        """The next frame (H x W x 3 uint8, B, G, R), shown from `t` seconds."""

    @abstractmethod
    def close(self) -> None:
        """Finish writing and move the file into place."""

    @abstractmethod
    def abort(self) -> None:
        """Remove everything written so far."""


class Format(NamedTuple):
    """One kind of output: what it is, and how to open a sink for it."""

    describe: str
    open: Callable[[Path, Export], FrameSink]
    one_frame: bool = False  # a still image: one frame, at --at
    # Frames 1/fps apart that last exactly the script; otherwise one more, the
    # last at the very end (GIFs and folders, as they always were).
    exact_length: bool = True
    frames: bool = True  # False: sound only, no frame is drawn


class FormatError(ValueError):
    """An --out the tool cannot write; the message says what it can."""


def _gif(path: Path, export: Export) -> FrameSink:
    from .output import GifWriter, build_palette

    assert export.frame_at is not None
    palette = build_palette(
        [np.ascontiguousarray(export.frame_at(t)[..., ::-1]) for t in export.palette_times]
    )
    return GifWriter(path, export.size, export.fps, palette)


def _video(codec: str) -> Callable[[Path, Export], FrameSink]:
    def open_video(path: Path, export: Export) -> FrameSink:
        from .video import open_video_writer

        return open_video_writer(path, export, codec)

    return open_video


def _apng(path: Path, export: Export) -> FrameSink:
    from .animated import ApngWriter

    return ApngWriter(path, export)


def _bag(path: Path, export: Export) -> FrameSink:
    from .bag import BagWriter

    return BagWriter(path, export)


def _wav(path: Path, export: Export) -> FrameSink:
    from .soundtrack import WavWriter

    return WavWriter(path, export)


def _still(path: Path, export: Export) -> FrameSink:
    from .output import PngStill

    return PngStill(path)


FORMATS: Dict[str, Format] = {
    ".png": Format("one frame as a PNG image (the last, or the one at --at)", _still, one_frame=True),
    ".gif": Format("a looping animated GIF", _gif, exact_length=False),
    ".mp4": Format("an H.264 video that plays everywhere", _video("h264")),
    ".webm": Format("a VP9 video for the web", _video("vp9")),
    ".webp": Format("a looping animated WebP, lossless", _video("webp")),
    ".apng": Format("a looping animated PNG, lossless", _apng),
    ".bag": Format("a ROS 1 bag that `rosbag play` replays on the robot", _bag),
    ".wav": Format("the speech alone, as a WAV sound file", _wav, frames=False),
}
FOLDER = Format("numbered PNG frames in a folder", lambda path, export: _folder(path), exact_length=False)


def _folder(path: Path) -> FrameSink:
    from .output import PngFolder

    return PngFolder(path)


def format_for(out: str) -> Format:
    """The format `out` asks for, from its extension (or a folder); FormatError if none."""
    if not out:
        # Path("") is the current folder: an empty variable would render there.
        raise FormatError(f"--out is empty; give DIR/ (./ for this folder) or a file ending in {_endings()}")
    if out.endswith(("/", "\\")) or Path(out).is_dir():
        return FOLDER
    suffix = Path(out).suffix.lower()
    if suffix in FORMATS:
        return FORMATS[suffix]
    raise FormatError(f"--out must end in {_choices()}, not {out!r}")


def _endings() -> str:
    names = list(FORMATS)
    return ", ".join(names[:-1]) + f" or {names[-1]}"


def _choices() -> str:
    return f"{_endings()}, or name a folder (end it with '/')"
