"""Eyes of other sizes for the drawn face: each socket cut anew into the skin, and its white.

An eye's size scales its socket, its ring and its lids about the eye's centre. The lids are
drawn at that size where they are drawn (drawn_parts.py); here are the two things a size
changes in full-screen layers, each only inside a box round that eye:

- the skin: within the box, the skin without sockets (a palette of its own, skin_mixing.py, so
  it mixes as the whole skin does) with the socket and ring of that size cut and drawn in it;
- the white behind it, shaded toward the larger or smaller rim.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from typing import Any, Callable, Dict, List, Optional, Tuple

import numpy as np

from .artwork import INK, SKIN_COLORS, draw_background, draw_skin, socket_hole, socket_ring, socket_window
from .compositing import Rect, Sprite, sprite_from_rgba
from .palette_store import kept_palette
from .skin_mixing import TINTS, SkinPalette
from .vector_shapes import Canvas

Size = Tuple[int, int]
LARGEST = 1.2  # the largest eye (core/expression.py's control)
ROOM = LARGEST + 0.05  # the palette's box holds an eye this large: the largest, rounded up
KEPT = 16  # sockets and whites kept, per eye and size


class EyeSizes:
    """An eye's socket and white at any size, at one screen size; made when first asked for."""

    def __init__(self, size: Size) -> None:
        self.size = size
        self._skins: Dict[int, Tuple[Rect, SkinPalette]] = {}
        self._making = threading.Lock()  # a palette is made once, whichever thread asks first
        self._kept: OrderedDict[Tuple[str, int, float], Any] = OrderedDict()

    def box(self, index: int, size: float) -> Rect:
        """The screen rectangle that eye `index` at `size` changes: it holds the socket, its
        ring and the socket as drawn."""
        c = Canvas(self.size, socket_window(index, size))
        return (c.corner[0], c.corner[1], c.limit[0], c.limit[1])

    def cut(
        self, index: int, size: float, numbers: Tuple[float, float, float]
    ) -> Tuple[Rect, np.ndarray, np.ndarray]:
        """The skin of `numbers` (tint, cheeks, sleepy) inside eye `index`'s box, with that
        eye's socket at `size`: (the box, colour times alpha uint16, 255 - alpha uint16), both
        (h, w, 3) in B, G, R, as a sprite holds them."""
        rect, hole, ring = self._socket(index, size)
        outer, palette = self._palette(index)
        x0, y0 = rect[0] - outer[0], rect[1] - outer[1]
        assert x0 >= 0 and y0 >= 0 and rect[2] <= outer[2] and rect[3] <= outer[3], (rect, outer)
        region = (slice(y0, y0 + rect[3] - rect[1]), slice(x0, x0 + rect[2] - rect[0]))
        colour = palette.sprite(*numbers).rgb_a[region].astype(np.float32) / (255.0 * 255.0)
        keep = (1.0 - hole) * (1.0 - ring)
        # As draw_skin paints: the skin with the socket cut out, then the ring over it.
        prem = colour * keep[..., None] + np.array(INK[::-1], np.float32) / 255.0 * ring[..., None]
        alpha = keep + ring
        straight = np.where(alpha[..., None] > 0, prem / np.maximum(alpha, 1e-6)[..., None], 0.0)
        bgr = np.clip(straight * 255.0 + 0.5, 0, 255).astype(np.uint16)
        a = np.clip(alpha * 255.0 + 0.5, 0, 255).astype(np.uint16)[..., None]
        return rect, bgr * a, np.repeat(255 - a, 3, axis=2)

    def white(self, index: int, size: float) -> Tuple[Rect, np.ndarray]:
        """The eye white inside eye `index`'s box, shaded toward the rim of a socket of `size`:
        (the box, (h, w, 3) uint8 B, G, R). The other eye's rim is too far off to matter."""
        window = socket_window(index, size)
        sizes = (size, 1.0) if index == 0 else (1.0, size)

        def draw() -> Tuple[Rect, np.ndarray]:
            image = draw_background(self.size, sizes, window)
            rect = self.box(index, size)
            return rect, np.ascontiguousarray(np.asarray(image)[..., 2::-1])

        return self._keep(("white", index, size), draw)

    def _socket(self, index: int, size: float) -> Tuple[Rect, np.ndarray, np.ndarray]:
        """The socket's coverage and its ring's, each (h, w) float32 over the box."""

        def draw() -> Tuple[Rect, np.ndarray, np.ndarray]:
            window = socket_window(index, size)
            hole, ring = Canvas(self.size, window), Canvas(self.size, window)
            shape, bounds = socket_hole(index, size)
            hole.shape(shape, bounds, (255, 255, 255))
            shape, bounds = socket_ring(index, size, ring)
            ring.shape(shape, bounds, INK)
            return self.box(index, size), hole.rgba[..., 3].copy(), ring.rgba[..., 3].copy()

        return self._keep(("socket", index, size), draw)

    def _palette(self, index: int) -> Tuple[Rect, SkinPalette]:
        """The skins without sockets round eye `index`, as a palette, over its largest box."""
        with self._making:
            if index not in self._skins:
                self._skins[index] = self._make_palette(index)
        return self._skins[index]

    def _make_palette(self, index: int) -> Tuple[Rect, SkinPalette]:
        window = socket_window(index, ROOM)
        rect = self.box(index, ROOM)

        def part(skin: int, cheeks: bool) -> Sprite:
            rgba = np.asarray(draw_skin(self.size, skin, cheeks, sockets=False, window=window))
            sprite = sprite_from_rgba(rgba, rect[0], rect[1])
            assert sprite is not None and sprite.rgb_a.shape[:2] == rgba.shape[:2]  # opaque
            return sprite

        def make() -> Optional[SkinPalette]:
            plain = [part(i, False) for i in range(TINTS)]
            return SkinPalette.of(plain, [part(i, True) for i in range(len(SKIN_COLORS))])

        palette = kept_palette(f"eye{index}", self.size, make)
        assert palette is not None and (palette.x, palette.y) == rect[:2]  # one outline: no sockets
        return rect, palette

    def prepare(self) -> None:
        """Make both eyes' palettes now (most of a second each)."""
        for index in range(2):
            self._palette(index)

    def _keep(self, key: Tuple[str, int, float], draw: Callable[[], Any]) -> Any:
        found = self._kept.get(key)
        if found is None:
            found = self._kept[key] = draw()
            while len(self._kept) > KEPT:
                self._kept.popitem(last=False)
        else:
            self._kept.move_to_end(key)
        return found


def patched(base: Sprite, patches: List[Tuple[Rect, np.ndarray, np.ndarray]]) -> Sprite:
    """A full-screen sprite with boxes of it replaced."""
    rgb_a, inv = base.rgb_a.copy(), base.inv.copy()
    for (x0, y0, x1, y1), colour, clear in patches:
        region = (slice(y0 - base.y, y1 - base.y), slice(x0 - base.x, x1 - base.x))
        rgb_a[region], inv[region] = colour, clear
    return Sprite(base.x, base.y, rgb_a, inv)
