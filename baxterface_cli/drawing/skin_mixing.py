"""Skins between the named ones, mixed once per distinct pixel rather than once per pixel.

Every skin of the default theme has the same outline; only colours differ (the gradient's,
the cheeks' blush, the sleeping skin's "Zzz"). A skin between them is, at every pixel, the same
weighted mix of the named skins' colours at that pixel, so two pixels that agree in every named
skin agree in every mix. `SkinPalette` finds those classes once (a gradient has a few thousand
shades, the cheeks and outlines some thousands more), mixes one row per class, and looks the
rows up for the whole screen: a new skin costs a lookup, not a dozen full-screen passes.

The mix is `mixed_colour`'s arithmetic, the same elementwise float32 steps on a row as on a
pixel, so the palette's skin and the plain per-pixel mix are the same to the last bit
(tests/drawing/test_skin_mixing.py holds them to it).
"""

from __future__ import annotations

import math
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np
from PIL import Image

from .compositing import Sprite, div255

TINTS = 5  # named waking skins, 0 (pale) .. 4 (red); skin 5 is the sleeping one
SLEEPING = 5


def skin_weights(tint: float, cheeks: float, sleepy: float) -> Tuple[int, float, float, float]:
    """(the named tint below, the way to the next, the cheeks, the sleepiness), each clamped."""
    tint = min(float(TINTS - 1), max(0.0, tint))
    low = min(TINTS - 2, int(math.floor(tint)))
    return low, tint - low, max(0.0, cheeks), min(1.0, max(0.0, sleepy))


def mixed_colour(
    plain: Sequence[np.ndarray], cheeky: Sequence[np.ndarray], tint: float, cheeks: float, sleepy: float
) -> np.ndarray:
    """A skin's colour times alpha (uint16) from the named skins' (uint16, any shape alike):
    `plain[i]` skin i without its cheeks, `cheeky[i]` with them (and the sleeping skin last).

    The tint runs between the two nearest named skins, the cheeks between none and as drawn
    (and past it: more blush), and sleepiness toward the sleeping skin.
    """
    low, f, cheeks, sleepy = skin_weights(tint, cheeks, sleepy)
    colour = plain[low].astype(np.float32) * (1 - f) + plain[low + 1].astype(np.float32) * f
    with_cheeks = cheeky[low].astype(np.float32) * (1 - f) + cheeky[low + 1].astype(np.float32) * f
    colour += (with_cheeks - colour) * cheeks
    colour += (cheeky[SLEEPING].astype(np.float32) - colour) * sleepy
    return np.clip(colour + 0.5, 0, 255 * 255).astype(np.uint16)


class SkinPalette:
    """The named skins as a palette of distinct pixels and, per screen pixel, its row."""

    def __init__(self, plain: List[Sprite], cheeky: List[Sprite]) -> None:
        first = cheeky[0]
        self.x, self.y, self.inv = first.x, first.y, first.inv
        h, w = first.rgb_a.shape[:2]
        # One row per pixel: every named skin's colour there, side by side.
        layers = [s.rgb_a for s in plain] + [s.rgb_a for s in cheeky]
        table = np.concatenate(layers, axis=2).reshape(h * w, -1)
        first_seen, self.index = _distinct_rows(table)
        rows = table[first_seen]
        n = len(plain)
        self._plain = [rows[:, 3 * i : 3 * i + 3] for i in range(n)]
        self._cheeky = [rows[:, 3 * (n + i) : 3 * (n + i) + 3] for i in range(len(cheeky))]
        self.index = self.index.reshape(h, w)
        self.shape = (h, w)

    @classmethod
    def of(cls, plain: List[Sprite], cheeky: List[Sprite]) -> Optional[SkinPalette]:
        """A palette, or None where the skins do not share one outline (a mix per pixel then)."""
        first = cheeky[0]
        for s in plain + cheeky:
            if (s.x, s.y, s.rgb_a.shape) != (first.x, first.y, first.rgb_a.shape):
                return None
            if not np.array_equal(s.inv, first.inv):
                return None
        return cls(plain, cheeky)

    def arrays(self) -> Dict[str, np.ndarray]:
        """The palette as named arrays, what `from_arrays` takes back (palette_store.py)."""
        return {
            "origin": np.array([self.x, self.y], np.int64),
            "inv": self.inv,
            "index": self.index,
            "plain": np.stack(self._plain),
            "cheeky": np.stack(self._cheeky),
        }

    @classmethod
    def from_arrays(cls, arrays: Dict[str, np.ndarray]) -> SkinPalette:
        """A palette from `arrays()`; ValueError where they do not make one."""
        index, inv, plain, cheeky = arrays["index"], arrays["inv"], arrays["plain"], arrays["cheeky"]
        rows = plain.shape[1] if plain.ndim == 3 else 0
        if not (
            index.ndim == 2
            and index.dtype == np.int32
            and inv.shape[:2] == index.shape
            and plain.shape == (TINTS, rows, 3)
            and cheeky.shape == (TINTS + 1, rows, 3)
            and plain.dtype == cheeky.dtype
            and rows > 0
            and index.min() >= 0
            and index.max() < rows
        ):
            raise ValueError("not a skin palette")
        palette = cls.__new__(cls)
        palette.x, palette.y = (int(n) for n in arrays["origin"])
        palette.inv, palette.index, palette.shape = inv, index, index.shape
        palette._plain, palette._cheeky = list(plain), list(cheeky)
        return palette

    def colours(self, tint: float, cheeks: float, sleepy: float) -> np.ndarray:
        """The mixed skin's rows: (rows, 3) uint16 colour times alpha."""
        return mixed_colour(self._plain, self._cheeky, tint, cheeks, sleepy)

    def sprite(self, tint: float, cheeks: float, sleepy: float) -> Sprite:
        """The mixed skin as a sprite, as a theme's skin layer is."""
        rgb_a = _look_up(self.colours(tint, cheeks, sleepy), self.index)
        return Sprite(self.x, self.y, rgb_a, self.inv)

    def stacked(self, tint: float, cheeks: float, sleepy: float) -> np.ndarray:
        """The mixed skin laid alone on nothing: its premultiplied colour, (h, w, 3) uint8,
        what compositing the sprite gives (div255 of colour times alpha), without the sprite.
        Read-only."""
        rows = div255(self.colours(tint, cheeks, sleepy)).astype(np.uint8)
        return _look_up_bytes(rows, self.index)


def _look_up(rows: np.ndarray, index: np.ndarray) -> np.ndarray:
    """`rows[index]` as an (h, w, 3) array, copying each pixel's three values as one item."""
    rows = np.ascontiguousarray(rows)
    item = np.dtype((np.void, rows.dtype.itemsize * 3))
    out = np.empty(index.shape + (3,), rows.dtype)
    np.take(rows.view(item).ravel(), index, out=out.view(item).reshape(index.shape))
    return out


def _look_up_bytes(rows: np.ndarray, index: np.ndarray) -> np.ndarray:
    """`_look_up` for uint8 rows: numpy picks 4-byte words several times faster than 3-byte
    items, so each row is padded to a word, picked, and Pillow drops the padding as it packs
    the pixels. Read-only: the packed bytes, not copied again."""
    words = np.zeros((len(rows), 4), np.uint8)
    words[:, :3] = rows
    picked = np.take(words.view(np.uint32).ravel(), index, mode="clip")  # index is in range
    h, w = index.shape
    packed = Image.frombuffer("RGBX", (w, h), picked, "raw", "RGBX", 0, 1).tobytes("raw", "RGB")
    return np.frombuffer(packed, np.uint8).reshape(h, w, 3)


def _distinct_rows(table: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """(the first pixel of each distinct row, each pixel's row number), by a 64-bit hash of
    the row, checked: a collision, however unlikely, falls back to comparing whole rows."""
    h = np.zeros(table.shape[0], np.uint64)
    for column in table.T:
        h *= np.uint64(1099511628211)  # FNV's prime: every column shifts the hash before it
        h ^= column.astype(np.uint64)
    _, first, inverse = np.unique(h, return_index=True, return_inverse=True)
    if np.array_equal(table[first][inverse.ravel()], table):
        return first, inverse.ravel().astype(np.int32)
    rows = np.ascontiguousarray(table).view(np.dtype((np.void, table.dtype.itemsize * table.shape[1])))
    _, first, inverse = np.unique(rows.ravel(), return_index=True, return_inverse=True)
    return first, inverse.ravel().astype(np.int32)
