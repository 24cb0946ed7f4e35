"""`render --out x.wav`: the script's speech alone, as a WAV file."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..speech.soundtrack import SILENT_RATE, write_wav
from .sink import Export, FileSink


class WavWriter(FileSink):
    """The export's sound as a 16-bit mono WAV file; frames are not wanted."""

    def __init__(self, path: Path, export: Export) -> None:
        super().__init__(path)
        self.audio = export.audio or (np.zeros(round(export.duration * SILENT_RATE), np.int16), SILENT_RATE)

    def add(self, frame_bgr: np.ndarray, t: float) -> None:
        pass

    def finish(self) -> None:
        write_wav(self.file, *self.audio)
