"""Integer alpha compositing, the one arithmetic every frame is made with.

Layers are premultiplied once when a theme loads: `rgb_a` = colour x alpha
and `inv` = 255 - alpha (repeated per channel), both uint16. Laying a layer over an opaque (or
premultiplied) destination is then `div255(rgb_a + dst * inv)`, exact to the
nearest integer and small enough for uint16 throughout.
"""

from __future__ import annotations

from typing import NamedTuple, Optional, Tuple

import numpy as np

Rect = Tuple[int, int, int, int]  # x0, y0, x1, y1: half-open, in screen pixels


def div255(x: np.ndarray) -> np.ndarray:
    """round(x / 255) for uint16 x <= 255 * 255, without a division."""
    x = x + 128
    return (x + (x >> 8)) >> 8


def div255_inplace(x: np.ndarray) -> None:
    """`x[...] = div255(x)`, without temporaries the size of x but one."""
    x += 128
    x += x >> 8
    x >>= 8


class Sprite(NamedTuple):
    """A layer cropped to what it draws, premultiplied for compositing."""

    x: int  # where its top-left corner sits, at rest
    y: int
    rgb_a: np.ndarray  # (h, w, 3) uint16: colour (B, G, R) times alpha
    inv: np.ndarray  # (h, w, 3) uint16: 255 - alpha, once per channel

    @property
    def height(self) -> int:
        return self.rgb_a.shape[0]

    @property
    def width(self) -> int:
        return self.rgb_a.shape[1]

    def rect(self, dx: int = 0, dy: int = 0) -> Rect:
        h, w = self.rgb_a.shape[:2]  # asked for every layer of every frame: no properties
        x, y = self.x + dx, self.y + dy
        return (x, y, x + w, y + h)


def sprite_from_rgba(rgba: np.ndarray, x: int = 0, y: int = 0) -> Optional[Sprite]:
    """Crop an (h, w, 4) RGBA uint8 array to its visible pixels; None if it has none."""
    return sprite_of(rgba[..., 3], rgba[..., 2::-1], x, y)


def sprite_of(alpha: np.ndarray, bgr: np.ndarray, x: int = 0, y: int = 0) -> Optional[Sprite]:
    """A sprite of `alpha` (h, w) and straight colour `bgr`, uint8: (h, w, 3), or one (3,)
    colour throughout; cropped to its visible pixels, None if it has none."""
    rows = np.flatnonzero(alpha.any(axis=1))
    cols = np.flatnonzero(alpha.any(axis=0))
    if rows.size == 0:
        return None
    r0, r1, c0, c1 = rows[0], rows[-1] + 1, cols[0], cols[-1] + 1
    a = alpha[r0:r1, c0:c1, None].astype(np.uint16)
    colour = (bgr[r0:r1, c0:c1] if bgr.ndim == 3 else bgr).astype(np.uint16)
    # 255 - alpha is stored per channel: numpy multiplies (h, w, 3) by
    # (h, w, 3) many times faster than by a broadcast (h, w, 1).
    return Sprite(x + int(c0), y + int(r0), colour * a, np.repeat(255 - a, 3, axis=2))


def split_columns(sprite: Sprite) -> list:
    """Split a sprite at fully transparent columns: one sprite per eye, say.

    Redrawing what moved then touches each eye's own box, not the span
    between them.
    """
    visible = (sprite.inv[..., 0] < 255).any(axis=0)
    parts, start = [], None
    for i, on in enumerate(list(visible) + [False]):
        if on and start is None:
            start = i
        elif not on and start is not None:
            rows = np.flatnonzero((sprite.inv[:, start:i, 0] < 255).any(axis=1))
            r0, r1 = int(rows[0]), int(rows[-1]) + 1
            parts.append(
                Sprite(
                    sprite.x + start, sprite.y + r0, sprite.rgb_a[r0:r1, start:i], sprite.inv[r0:r1, start:i]
                )
            )
            start = None
    return parts


def intersect(a: Rect, b: Rect) -> Optional[Rect]:
    x0, y0 = max(a[0], b[0]), max(a[1], b[1])
    x1, y1 = min(a[2], b[2]), min(a[3], b[3])
    return (x0, y0, x1, y1) if x0 < x1 and y0 < y1 else None


def lay(dst: np.ndarray, rect: Rect, sprite: Sprite, dx: int = 0, dy: int = 0) -> None:
    """Lay `sprite`, moved by (dx, dy), over the part of `dst` (covering `rect`) it reaches."""
    hit = intersect(rect, sprite.rect(dx, dy))
    if hit is None:
        return
    x0, y0, x1, y1 = hit
    sx, sy = sprite.x + dx, sprite.y + dy
    src = (slice(y0 - sy, y1 - sy), slice(x0 - sx, x1 - sx))
    out = (slice(y0 - rect[1], y1 - rect[1]), slice(x0 - rect[0], x1 - rect[0]))
    view = dst[out]
    # numpy runs one loop per row over a part of rows, many times slower than one over a whole
    # block: the arithmetic is done in a block of its own, then copied back.
    work = view if view.flags.c_contiguous else view.copy()
    work *= sprite.inv[src]
    work += sprite.rgb_a[src]
    div255_inplace(work)
    if work is not view:
        view[...] = work


def finish(
    prem: np.ndarray, inv: np.ndarray, under: np.ndarray, out: Optional[np.ndarray] = None
) -> np.ndarray:
    """The premultiplied top stack over the opaque bottom stack, as uint8.

    Works in place on `under`; writes into `out` (uint8) when given.
    """
    under *= inv
    div255_inplace(under)
    under += prem
    # numpy's uint16 minimum against one number is many times slower than against an array of it.
    np.minimum(under, np.full(under.shape, 255, np.uint16), out=under)
    if out is None:
        return under.astype(np.uint8)
    np.copyto(out, under, casting="unsafe")
    return out


def alike_rows(sprite: Sprite) -> Tuple[int, int]:
    """The longest run of identical rows: a lid's flat upper part."""
    same = np.all(sprite.rgb_a[1:] == sprite.rgb_a[:-1], axis=(1, 2)) & np.all(
        sprite.inv[1:] == sprite.inv[:-1], axis=(1, 2)
    )
    best, start = (0, 1), None
    for i, alike in enumerate(list(same) + [False]):
        if alike and start is None:
            start = i
        elif not alike and start is not None:
            if i + 1 - start > best[1] - best[0]:
                best = (start, i + 1)
            start = None
    return best
