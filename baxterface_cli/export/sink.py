"""The writers' interface: frames in, one file (or folder) out, whole or not at all.

Every format's writer is a `FrameSink`; the registry (registry.py) lists them by
extension and imports them only when asked, so nothing here imports a writer.
A sink is a context manager, as files are: leaving the block closes it, and an
exception aborts it, so no partial file outlives a failure.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from pathlib import Path
from typing import Any, Callable, NamedTuple, Optional, Sequence, Tuple

import numpy as np

from ..core.partial_files import PartialFile
from ..engine.effects import Cue

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

    def __enter__(self) -> FrameSink:
        return self

    def __exit__(self, kind: Any, error: Any, trace: Any) -> None:
        if kind is None:
            self.close()
        else:
            self.abort()


class FileSink(FrameSink):
    """A sink that writes one file, unseen until it is whole (a `PartialFile`).

    A writer writes into `self.file` as frames come, says in `finish` what
    ends the file, and in `release` how to let go of an encoder after a
    failure; closing, aborting and the partial file are all here.
    """

    named = False  # True for a writer whose encoder opens the file by its name (`partial.path`)

    def __init__(self, path: Path) -> None:
        self.path = path
        self.partial = PartialFile(path, named=self.named)
        self.file = self.partial.file

    def finish(self) -> None:
        """Write what ends the file (trailers, an index): every frame is in."""

    def release(self) -> None:
        """Let go of whatever writes into the file, after a failure."""

    def close(self) -> None:
        try:
            self.finish()
            self.partial.commit()
        except BaseException:
            self.abort()
            raise

    def abort(self) -> None:
        try:
            self.release()
        finally:
            self.partial.discard()


class FormatError(ValueError):
    """An --out the tool cannot write; the message says what it can."""
