"""What `render --out` can write, keyed by the file's extension: a table, not a switch.

Each format opens a `FrameSink` (sink.py) that takes the frames in order with
their times and writes a partial file beside the target (core/partial_files.py),
renamed into place by `close` only when complete. Writers are imported when
their format is asked for; formats that need an optional library name the
extra that brings it.
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable, Dict, NamedTuple

import numpy as np

from .sink import Export, FormatError, FrameSink


class Format(NamedTuple):
    """One kind of output: what it is, and how to open a sink for it."""

    describe: str
    open: Callable[[Path, Export], FrameSink]
    one_frame: bool = False  # a still image: one frame, at --at
    frames: bool = True  # False: sound only, no frame is drawn
    folder: bool = False  # a folder of files, written inside itself, not a file beside others


def _gif(path: Path, export: Export) -> FrameSink:
    from .png_gif import GifWriter, build_palette

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


def _webp(path: Path, export: Export) -> FrameSink:
    from .webp import WebpWriter, available

    if not available():  # a Pillow built without libwebp: FFmpeg's encoder, whole at the end
        return _video("webp")(path, export)
    return WebpWriter(path, export)


def _apng(path: Path, export: Export) -> FrameSink:
    from .apng import ApngWriter

    return ApngWriter(path, export)


def _bag(path: Path, export: Export) -> FrameSink:
    from .bag import BagWriter

    return BagWriter(path, export)


def _wav(path: Path, export: Export) -> FrameSink:
    from .wav import WavWriter

    return WavWriter(path, export)


def _still(path: Path, export: Export) -> FrameSink:
    from .png_gif import PngStill

    return PngStill(path)


FORMATS: Dict[str, Format] = {
    ".png": Format("one frame as a PNG image (the last, or the one at --at)", _still, one_frame=True),
    ".gif": Format("a looping animated GIF", _gif),
    ".mp4": Format("an H.264 video that plays everywhere", _video("h264")),
    ".webm": Format("a VP9 video for the web", _video("vp9")),
    ".webp": Format("a looping animated WebP, lossless", _webp),
    ".apng": Format("a looping animated PNG, lossless", _apng),
    ".bag": Format("a ROS 1 bag that `rosbag play` replays on the robot", _bag),
    ".wav": Format("the speech alone, as a WAV sound file", _wav, frames=False),
}
FOLDER = Format("numbered PNG frames in a folder", lambda path, export: _folder(path), folder=True)


def _folder(path: Path) -> FrameSink:
    from .png_gif import PngFolder

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
