"""Animated WebP: lossless, looping, written as frames arrive.

The container is written here (RIFF 'WEBP', VP8X, ANIM, then an ANMF chunk per
frame), and each frame's picture is encoded by Pillow's libwebp: only the
rectangle that changed since the frame before, with the pixels in it that did not
change made transparent and blended over what is shown (a candidate whole and
opaque is kept when it is smaller), as libwebp's own animation encoder does. So
a full disk fails at the frame that fills it, not at the end: FFmpeg's
animation encoder (libwebp_anim) keeps every frame until its last and writes the
file only then. The RIFF size is set when the last frame is in.
"""

from __future__ import annotations

import contextlib
import io
import queue
import struct
import threading
from pathlib import Path
from typing import Any, List, Optional, Tuple

import numpy as np
from PIL import Image

from .sink import Export, FileSink

# FFmpeg's settings for libwebp_anim, as the file was written before: lossless, quality 75 (in
# lossless, the effort spent), compression level 3 (libwebp's `method`).
QUALITY = 75
METHOD = 3
ANIMATION, ALPHA = 0x02, 0x10  # VP8X flags
NO_BLEND = 0x02  # ANMF flag: the rectangle replaces what is there (else: alpha-blended over it)
LONGEST = 0xFFFFFF  # an ANMF duration is 24 bits of milliseconds


def available() -> bool:
    """Does this Pillow write WebP (its libwebp)?"""
    from PIL import features

    return bool(features.check("webp"))


def _chunk(kind: bytes, data: bytes) -> bytes:
    return kind + struct.pack("<I", len(data)) + data + (b"\0" if len(data) & 1 else b"")


def _u24(value: int) -> bytes:
    return struct.pack("<I", value)[:3]


def _bitstream(image: Image.Image) -> bytes:
    """The image's WebP chunks as Pillow encodes it (ALPH and VP8, or VP8L), without the RIFF."""
    out = io.BytesIO()
    image.save(out, format="WEBP", lossless=True, quality=QUALITY, method=METHOD)
    data, at, parts = out.getvalue(), 12, []
    while at + 8 <= len(data):
        kind, (length,) = data[at : at + 4], struct.unpack("<I", data[at + 4 : at + 8])
        end = at + 8 + length + (length & 1)
        if kind in (b"ALPH", b"VP8 ", b"VP8L"):
            parts.append(data[at:end])
        at = end
    return b"".join(parts)


class WebpWriter(FileSink):
    """Each frame is the rectangle that changed, over the frame before; identical frames merge.

    Frames are compared here and encoded and written in a thread of their own (Pillow lets go of
    the GIL while libwebp encodes), so the next frame is drawn meanwhile; a failure there (a full
    disk) is raised at the next frame given.
    """

    QUEUED = 4  # rectangles waiting for the encoder

    def __init__(self, path: Path, export: Export) -> None:
        super().__init__(path)
        self.fps = export.fps
        width, height = export.size
        try:
            vp8x = bytes([ANIMATION | ALPHA, 0, 0, 0]) + _u24(width - 1) + _u24(height - 1)
            anim = struct.pack("<IH", 0xFFFFFFFF, 0)  # white behind the first frame; loop forever
            self.file.write(b"RIFF\0\0\0\0WEBP" + _chunk(b"VP8X", vp8x) + _chunk(b"ANIM", anim))
        except BaseException:
            self.abort()
            raise
        self.previous: Optional[np.ndarray] = None
        self.frames = 0  # frames given
        self.written = 0  # ANMF chunks written
        # The encoder's: the frame written when the next one starts, as (chunk header, bitstream).
        self._pending: Optional[Tuple[bytes, int, bytes, bytes]] = None
        self._rectangles: queue.Queue = queue.Queue(maxsize=self.QUEUED)
        self._failure: Optional[BaseException] = None
        # A daemon: whatever stops the render (Ctrl-C) never waits on it to end the program.
        self._encoder = threading.Thread(target=self._encode, name="baxterface-webp", daemon=True)
        self._encoder.start()

    def add(self, frame_bgr: np.ndarray, t: float = 0.0) -> None:
        frame = np.array(frame_bgr, np.uint8)  # kept: the renderer reuses its buffer
        height = frame.shape[0]
        if self.previous is None:
            self._hand_over((_picture(frame, None), False, 0, 0, self.frames))
        else:
            # Rows and columns first, over bytes (a pixel's channels apart is 25 times slower).
            rows = np.flatnonzero(
                (frame.reshape(height, -1) != self.previous.reshape(height, -1)).any(axis=1)
            )
            if rows.size:  # unchanged frames only lengthen the one before
                # A frame's offset is stored halved: it starts on even pixels.
                y0, y1 = int(rows[0]) & ~1, int(rows[-1]) + 1
                band, before = frame[y0:y1], self.previous[y0:y1]
                cols = np.flatnonzero((band != before).any(axis=0).any(axis=1))
                x0, x1 = int(cols[0]) & ~1, int(cols[-1]) + 1
                crop, differs = band[:, x0:x1], band[:, x0:x1] != before[:, x0:x1]
                changed = differs[..., 0] | differs[..., 1] | differs[..., 2]
                self._hand_over((_picture(crop, changed), True, x0, y0, self.frames))
        self.previous = frame
        self.frames += 1

    def _hand_over(self, item: Any) -> None:
        while True:
            self._raise_failure()
            try:
                self._rectangles.put(item, timeout=0.1)
                return
            except queue.Full:
                if not self._encoder.is_alive():
                    self._raise_failure()
                    raise OSError("the WebP encoder stopped") from None

    def _raise_failure(self) -> None:
        if self._failure is not None:
            raise self._failure

    def _encode(self) -> None:
        try:
            while True:
                item = self._rectangles.get()
                if item is None:
                    return
                image, blend, x, y, starts = item
                if isinstance(image, int):  # the end: the last frame lasts until then
                    self._write(starts)
                    continue
                width, height = image.size
                place = _u24(x // 2) + _u24(y // 2) + _u24(width - 1) + _u24(height - 1)
                flags = bytes([0 if blend else NO_BLEND])
                bitstream = _bitstream(image)
                self._write(starts)
                self._pending = (place, starts, flags, bitstream)
        except BaseException as error:  # a full disk: said where the frames come from
            self._failure = error

    def _write(self, ends: int) -> None:
        """Write the pending frame, shown until frame number `ends`."""
        if self._pending is None:
            return
        place, starts, flags, bitstream = self._pending
        chunks: List[bytes] = []
        # A frame too long for one chunk (4.6 hours) goes on in the same rectangle again.
        for duration in _durations(starts, ends, self.fps):
            chunks.append(_chunk(b"ANMF", place + _u24(duration) + flags + bitstream))
        self.file.write(b"".join(chunks))
        self.written += len(chunks)
        self._pending = None

    def finish(self) -> None:
        self._hand_over((0, False, 0, 0, self.frames))
        self._hand_over(None)
        self._encoder.join()
        self._raise_failure()
        size = self.file.tell()
        self.file.seek(4)
        self.file.write(struct.pack("<I", size - 8))

    def release(self) -> None:
        encoder = getattr(self, "_encoder", None)
        if encoder is not None and encoder.is_alive():
            # Rectangles still waiting are dropped; the one being encoded finishes first.
            with contextlib.suppress(queue.Empty):
                while True:
                    self._rectangles.get_nowait()
            with contextlib.suppress(queue.Full):
                self._rectangles.put_nowait(None)
            encoder.join(timeout=10)


def _picture(crop_bgr: np.ndarray, changed: Optional[np.ndarray]) -> Image.Image:
    """The rectangle as a picture; its unchanged pixels transparent, to blend over the frame before."""
    height, width = crop_bgr.shape[:2]
    if changed is None:
        return Image.fromarray(np.ascontiguousarray(crop_bgr[..., ::-1]), "RGB")
    rgba = np.empty((height, width, 4), np.uint8)
    rgba[..., :3] = crop_bgr[..., ::-1]
    rgba[..., 3] = changed
    rgba[..., 3] *= 255
    return Image.fromarray(rgba, "RGBA")


def _durations(start: int, end: int, fps: float) -> List[int]:
    """Frames `start` to `end` as milliseconds, rounded where each frame starts (so they add up)."""
    total = round(end * 1000 / fps) - round(start * 1000 / fps)
    parts = [LONGEST] * (total // LONGEST)
    if total % LONGEST or not parts:
        parts.append(total % LONGEST)
    return parts
