"""`render --out x.wav`: the script's speech alone, as a WAV file."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..core import partial_files as partial
from ..speech.soundtrack import SILENT_RATE, write_wav
from .sink import Export, FrameSink


class WavWriter(FrameSink):
    """The export's sound as a 16-bit mono WAV file; frames are not wanted."""

    def __init__(self, path: Path, export: Export) -> None:
        self.path = path
        self.audio = export.audio or (np.zeros(round(export.duration * SILENT_RATE), np.int16), SILENT_RATE)
        self.tmp, self.file = partial.create_file(path)

    def add(self, frame_bgr: np.ndarray, t: float) -> None:
        pass

    def close(self) -> None:
        write_wav(self.file, *self.audio)
        self.file.close()
        os.replace(self.tmp, self.path)

    def abort(self) -> None:
        self.file.close()
        partial.remove(self.tmp)
