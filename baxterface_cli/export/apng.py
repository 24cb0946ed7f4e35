"""Animated PNG (APNG): lossless, looping, written as frames arrive.

Pillow encodes each frame (only the rectangle that changed since the one
before); this module wraps its image data in APNG's frame chunks. Pillow's
own APNG writer keeps every frame in memory until the end (over a gigabyte
for a 20-second show at 1024x600): this one keeps one.
"""

from __future__ import annotations

import io
import struct
import zlib
from pathlib import Path
from typing import List, Optional, Tuple

import numpy as np
from PIL import Image

from .sink import Export, FileSink

SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def _image_data(rgb: np.ndarray) -> bytes:
    """The zlib stream of `rgb` as Pillow encodes it in a PNG (its IDAT chunks joined)."""
    out = io.BytesIO()
    Image.fromarray(rgb, "RGB").save(out, format="PNG", compress_level=6)
    png, at, parts = out.getvalue(), len(SIGNATURE), []
    while at < len(png):
        (length,), kind = struct.unpack(">I", png[at : at + 4]), png[at + 4 : at + 8]
        if kind == b"IDAT":
            parts.append(png[at + 8 : at + 8 + length])
        at += 12 + length
    return b"".join(parts)


class ApngWriter(FileSink):
    """Each frame is the rectangle that changed, over the frame before; identical frames merge."""

    def __init__(self, path: Path, export: Export) -> None:
        super().__init__(path)
        self.fps = export.fps
        self.width, self.height = export.size
        try:
            header = struct.pack(">IIBBBBB", self.width, self.height, 8, 2, 0, 0, 0)  # 8-bit RGB
            self.file.write(SIGNATURE + _chunk(b"IHDR", header))
            self.actl_at = self.file.tell()
            self.file.write(_chunk(b"acTL", struct.pack(">II", 1, 0)))  # counted at close; 0: loop
        except BaseException:
            self.abort()
            raise
        self.previous: Optional[np.ndarray] = None
        self.pending: Optional[Tuple[np.ndarray, Tuple[int, int]]] = None  # (crop, (x, y))
        self.pending_from = 0  # the frame number the pending one is shown from
        self.frames = 0  # frames given
        self.written = 0  # APNG frames written
        self.sequence = 0

    def add(self, frame_bgr: np.ndarray, t: float = 0.0) -> None:
        rgb = np.ascontiguousarray(frame_bgr[..., ::-1])
        if self.previous is None:
            self._queue(rgb, (0, 0))
        else:
            changed = (rgb != self.previous).any(axis=2)
            rows = np.flatnonzero(changed.any(axis=1))
            if rows.size:  # unchanged frames only lengthen the one before
                cols = np.flatnonzero(changed[rows[0] : rows[-1] + 1].any(axis=0))
                y0, y1, x0, x1 = int(rows[0]), int(rows[-1]) + 1, int(cols[0]), int(cols[-1]) + 1
                self._queue(np.ascontiguousarray(rgb[y0:y1, x0:x1]), (x0, y0))
        self.previous = rgb
        self.frames += 1

    def _queue(self, crop: np.ndarray, at: Tuple[int, int]) -> None:
        self._flush()
        self.pending, self.pending_from = (crop, at), self.frames

    def _flush(self) -> None:
        """Write the pending frame, which lasts until the current frame count."""
        if self.pending is None:
            return
        crop, (x, y) = self.pending
        height, width = crop.shape[:2]
        frames = max(1, self.frames - self.pending_from)
        delay = _delay(frames, self.fps)
        # dispose NONE, blend SOURCE: the rectangle replaces what was there
        control = struct.pack(">IIIIIHHBB", self.sequence, width, height, x, y, *delay, 0, 0)
        self.sequence += 1
        chunks: List[bytes] = [_chunk(b"fcTL", control)]
        data = _image_data(crop)
        if self.written == 0:
            chunks.append(_chunk(b"IDAT", data))  # the first frame is also the still image
        else:
            chunks.append(_chunk(b"fdAT", struct.pack(">I", self.sequence) + data))
            self.sequence += 1
        self.file.write(b"".join(chunks))
        self.written += 1
        self.pending = None

    def finish(self) -> None:
        self._flush()
        self.file.write(_chunk(b"IEND", b""))
        self.file.seek(self.actl_at)
        self.file.write(_chunk(b"acTL", struct.pack(">II", self.written, 0)))


def _delay(frames: int, fps: float) -> Tuple[int, int]:
    """`frames` frame times as an APNG delay fraction (numerator, denominator), both 16-bit."""
    if float(fps).is_integer() and frames < 65536:
        return frames, int(fps)
    return min(65535, round(frames * 1000 / fps)), 1000
