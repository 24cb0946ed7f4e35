"""Sinks that write frames to image files: a PNG image, numbered PNGs, animated GIFs.

Every file is written beside its final name (see core/partial_files.py), a
folder's frames inside the folder, and renamed into place when complete, so
an interrupted render leaves no half-written file behind, and two renders to
one name leave one of them, whole.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
from contextlib import contextmanager
from pathlib import Path
from typing import Iterable, Iterator, Optional, Tuple

import numpy as np
from PIL import GifImagePlugin, Image

from ..core import partial_files as partial
from ..core.partial_files import write_atomic
from .sink import FileSink, FrameSink

TRANSPARENT = 255  # the GIF palette index meaning "as in the frame before"
LUT_BITS = 5  # colour bits per channel of the palette lookup


def write_png(path: Path, frame_bgr: np.ndarray) -> None:
    """One frame as a PNG image, written atomically."""
    data = io.BytesIO()
    Image.fromarray(np.ascontiguousarray(frame_bgr[..., ::-1]), "RGB").save(
        data, format="PNG", compress_level=6
    )
    write_atomic(path, data.getvalue())


class PngStill(FrameSink):
    """One frame as a PNG image: the last one given."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.frame: Optional[np.ndarray] = None

    def add(self, frame_bgr: np.ndarray, t: float = 0.0) -> None:
        self.frame = frame_bgr

    def close(self) -> None:
        assert self.frame is not None, "a still needs a frame"
        write_png(self.path, self.frame)

    def abort(self) -> None:
        pass  # nothing is written before close


FRAME_NAME = re.compile(r"^frame_(\d{5,})\.png$")  # what PngFolder writes, and all it replaces


class PngFolder(FrameSink):
    """Numbered PNG frames (frame_00000.png, ...) in a folder.

    Frames are written into a hidden folder inside the target first, on the target's own file
    system whatever is mounted where (a mount point, say), and move in only when the render
    finishes: each replaces the frame of the same number, and only then are the frames of a
    longer render before removed. Until the last frame is drawn, the folder's frames are the old
    ones, all of them.
    """

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self.made = not folder.is_dir()  # a folder of our making goes again if the render fails
        folder.mkdir(parents=True, exist_ok=True)
        partial.remove_stale(folder)  # what a render killed here left
        try:
            self.staging = partial.create_folder(folder / "frames")
        except BaseException:
            self._forget_folder()
            raise
        self.count = 0

    def add(self, frame_bgr: np.ndarray, t: float = 0.0) -> None:
        rgb = np.ascontiguousarray(frame_bgr[..., ::-1])
        Image.fromarray(rgb, "RGB").save(self.staging / f"frame_{self.count:05d}.png", compress_level=6)
        self.count += 1

    def close(self) -> None:
        try:
            with _locked(self.folder):  # two renders into one folder must not mix their frames
                for path in sorted(self.staging.iterdir()):
                    os.replace(path, self.folder / path.name)
                for old in os.listdir(self.folder):
                    match = FRAME_NAME.match(old)
                    if match and int(match.group(1)) >= self.count:  # a longer render's, before
                        (self.folder / old).unlink()
        finally:
            partial.remove(self.staging)

    def abort(self) -> None:
        partial.remove(self.staging)
        self._forget_folder()

    def _forget_folder(self) -> None:
        if self.made:
            with contextlib.suppress(OSError):
                self.folder.rmdir()  # only if empty: whatever else came in stays


@contextmanager
def _locked(folder: Path) -> Iterator[None]:
    """Hold an exclusive lock on `folder` (where the system has flock)."""
    try:
        import fcntl
    except ImportError:
        yield
        return
    fd = os.open(str(folder), os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)


def build_palette(frames_rgb: Iterable[np.ndarray], colours: int = 255) -> np.ndarray:
    """One palette for a whole animation, from frames that show its colours."""
    tiles = [Image.fromarray(f, "RGB").reduce(2) for f in frames_rgb]
    mosaic = Image.new("RGB", (tiles[0].width, tiles[0].height * len(tiles)))
    for i, tile in enumerate(tiles):
        mosaic.paste(tile, (0, i * tiles[0].height))
    quantized = mosaic.quantize(colors=colours, method=Image.MEDIANCUT, dither=Image.NONE)
    used = len(quantized.getcolors(colours + 1) or [])
    return np.array(quantized.getpalette()[: 3 * max(used, 1)], np.uint8).reshape(-1, 3)


def palette_lookup(palette: np.ndarray) -> np.ndarray:
    """A table from 5-bit B, G, R to the nearest palette index (the first of equals).

    The cube is a grid, so a distance is three per-channel squares added: each colour's
    squares per level are worked out once and added across the grid."""
    levels = (np.arange(1 << LUT_BITS) << (8 - LUT_BITS)) + (1 << (7 - LUT_BITS))
    side = 1 << LUT_BITS
    colours = palette.astype(np.int32)
    if len(colours) == 0:
        return np.zeros((side, side, side), np.uint8)
    squares = (levels.astype(np.int32)[None, None, :] - colours[:, :, None]) ** 2  # colour, R G B, level
    distance = squares[:, 2, :, None, None] + squares[:, 1, None, :, None]  # colour, B, G, R
    distance = distance + squares[:, 0, None, None, :]
    return distance.argmin(axis=0).astype(np.uint8)


def changed_box(a: np.ndarray, b: np.ndarray) -> Optional[Tuple[int, int, int, int]]:
    """(x0, y0, x1, y1) round the pixels where frames a and b, (h, w, 3) uint8, differ; None
    where they are the same.

    Rows are compared as machine words, a few times faster than byte by byte; then only the
    first and last differing words are looked at byte by byte, for the exact columns.
    """
    h, w, c = a.shape
    row = w * c
    size = next(k for k in (8, 4, 2, 1) if row % k == 0)
    if not (a.flags.c_contiguous and b.flags.c_contiguous):
        a, b = np.ascontiguousarray(a), np.ascontiguousarray(b)
    word = np.dtype(f"u{size}")
    bytes_a, bytes_b = a.reshape(h, row), b.reshape(h, row)
    differ = bytes_a.view(word) != bytes_b.view(word)
    rows = np.flatnonzero(differ.any(axis=1))
    if rows.size == 0:
        return None
    y0, y1 = int(rows[0]), int(rows[-1]) + 1
    words = np.flatnonzero(differ[y0:y1].any(axis=0))
    first, last = int(words[0]) * size, int(words[-1]) * size
    left = np.flatnonzero(
        (bytes_a[y0:y1, first : first + size] != bytes_b[y0:y1, first : first + size]).any(axis=0)
    )
    right = np.flatnonzero(
        (bytes_a[y0:y1, last : last + size] != bytes_b[y0:y1, last : last + size]).any(axis=0)
    )
    return (first + int(left[0])) // c, y0, (last + int(right[-1])) // c + 1, y1


class GifWriter(FileSink):
    """An animated, looping GIF, written as frames arrive.

    All frames share one palette (the face has few colours). Each frame
    stores only the rectangle that changed, and inside it pixels that did not
    change are transparent, which compresses to almost nothing. Identical
    frames merge into a longer one. Delays are in the GIF's 1/100 s, rounded
    so that they add up to the true time.
    """

    def __init__(self, path: Path, size: Tuple[int, int], fps: float, palette: np.ndarray) -> None:
        super().__init__(path)
        self.fps = fps
        self.lut = palette_lookup(palette)
        self.flat_lut = self.lut.ravel()
        self.shift = 8 - LUT_BITS
        padded = np.zeros((256, 3), np.uint8)
        padded[: len(palette)] = palette
        self.palette_bytes = padded.tobytes()
        template = Image.new("P", size)
        template.putpalette(self.palette_bytes)
        header, _ = GifImagePlugin.getheader(template, self.palette_bytes, {"loop": 0})
        try:
            for chunk in header:
                self.file.write(chunk)
        except BaseException:
            self.abort()
            raise
        self.previous_bgr: Optional[np.ndarray] = None
        self.previous_index: Optional[np.ndarray] = None
        self.pending: Optional[Tuple[Image.Image, Tuple[int, int], bool]] = None
        self.frames = 0  # frames given
        self.written_centis = 0

    def _index(self, bgr: np.ndarray) -> np.ndarray:
        """Each pixel's palette index: the table's entry at its top bits of B, G, R."""
        s = self.shift
        top = bgr >> np.uint8(s)
        at = top[..., 0].astype(np.intp)
        at <<= LUT_BITS
        at |= top[..., 1]
        at <<= LUT_BITS
        at |= top[..., 2]
        return self.flat_lut.take(at)

    def add(self, frame_bgr: np.ndarray, t: float = 0.0) -> None:
        if self.previous_bgr is None:
            index = self._index(frame_bgr)
            self.previous_bgr, self.previous_index = frame_bgr.copy(), index
            self._queue(index, (0, 0), transparent=False)
        else:
            box = changed_box(frame_bgr, self.previous_bgr)
            if box is not None:
                x0, y0, x1, y1 = box
                crop = self._index(frame_bgr[y0:y1, x0:x1])
                before = self.previous_index[y0:y1, x0:x1]
                emitted = np.where(crop == before, np.uint8(TRANSPARENT), crop)
                before[...] = crop
                self.previous_bgr[y0:y1, x0:x1] = frame_bgr[y0:y1, x0:x1]
                self._queue(emitted, (int(x0), int(y0)), transparent=True)
        self.frames += 1

    def _queue(self, index: np.ndarray, offset: Tuple[int, int], transparent: bool) -> None:
        self._flush()
        image = Image.fromarray(np.ascontiguousarray(index), "P")
        image.putpalette(self.palette_bytes)
        self.pending = (image, offset, transparent)

    def _flush(self) -> None:
        """Write the pending frame, which lasted until the current frame count."""
        if self.pending is None:
            return
        image, offset, transparent = self.pending
        until = int(round(self.frames * 100 / self.fps))
        centis = max(until - self.written_centis, 2)  # browsers treat < 2 as 10
        self.written_centis += centis
        params = {"duration": centis * 10, "disposal": 1}
        if transparent:
            params["transparency"] = TRANSPARENT
        for chunk in GifImagePlugin.getdata(image, offset, **params):
            self.file.write(chunk)
        self.pending = None

    def finish(self) -> None:
        self._flush()
        self.file.write(b";")
