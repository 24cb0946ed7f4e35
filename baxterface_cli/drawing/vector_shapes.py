"""Vector shapes for drawing the face: a supersampled canvas and the shapes drawn on it.

Shapes are masks given in face units (pixels of the 1024x600 face); the
canvas maps them to the screen, draws them four times larger and
box-filters them down, which anti-aliases them.
"""

from __future__ import annotations

import math
from typing import Callable, Iterable, List, Optional, Sequence, Tuple

import numpy as np
from PIL import Image, ImageChops, ImageDraw

FACE_SIZE = (1024, 600)
SUPERSAMPLE = 4

Color = Tuple[int, int, int]
Point = Tuple[float, float]


class Canvas:
    """A layer being drawn: premultiplied RGBA floats at screen size.

    With `window` (face units: x0, y0, x1, y1), only that part of the screen is kept: a part
    drawn while the face moves costs its own size, not the screen's. `corner` is then where
    the kept part sits on the screen.
    """

    def __init__(self, size: Tuple[int, int], window: Optional[Sequence[float]] = None) -> None:
        self.width, self.height = size
        self.scale = min(self.width / FACE_SIZE[0], self.height / FACE_SIZE[1])
        self.origin = (
            (self.width - FACE_SIZE[0] * self.scale) / 2.0,
            (self.height - FACE_SIZE[1] * self.scale) / 2.0,
        )
        self.corner, self.limit = (0, 0), (self.width, self.height)
        if window is not None:
            (sx0, sy0), (sx1, sy1) = self.to_screen(*window[:2]), self.to_screen(*window[2:])
            self.corner = (max(0, int(math.floor(sx0))), max(0, int(math.floor(sy0))))
            self.limit = (min(self.width, int(math.ceil(sx1))), min(self.height, int(math.ceil(sy1))))
        w, h = max(0, self.limit[0] - self.corner[0]), max(0, self.limit[1] - self.corner[1])
        self.rgba = np.zeros((h, w, 4), np.float32)
        self._blank = True  # nothing painted yet

    def to_screen(self, x: float, y: float) -> Point:
        return self.origin[0] + x * self.scale, self.origin[1] + y * self.scale

    def paint_over(self, rgb: np.ndarray) -> None:
        """Cover the whole layer, opaque, with colours `rgb` (0..1 floats, shaped as the layer)."""
        self.rgba[..., :3] = rgb
        self.rgba[..., 3] = 1.0
        self._blank = False

    def fill(
        self, color: Color, coverage: np.ndarray, box: Tuple[int, int, int, int], opacity: float = 1.0
    ) -> None:
        """Paint `color` over the layer where `coverage` (0..1, shaped as `box`) says."""
        x0, y0, x1, y1 = box
        a = coverage[..., None] * opacity
        src = np.array([*color, 255], np.float32) / 255.0
        cx, cy = self.corner
        region = self.rgba[y0 - cy : y1 - cy, x0 - cx : x1 - cx]
        if self._blank:  # over nothing: what the general step gives, in one pass
            np.multiply(src, a, out=region)
            self._blank = False
            return
        region *= 1.0 - a
        region += src * a

    def shape(
        self,
        draw: Callable[[ImageDraw.ImageDraw, Callable[..., Point]], None],
        bounds: Sequence[float],
        color: Color,
        opacity: float = 1.0,
        clip: Optional[Callable[[ImageDraw.ImageDraw, Callable[..., Point]], None]] = None,
    ) -> None:
        """Draw with PIL at 4x inside `bounds` (face units), then filter down and paint.

        With `clip`, only where that shape is drawn too: a tongue or teeth kept inside a mouth.
        """
        drawn = self.coverage(draw, bounds, clip)
        if drawn is not None:
            small, box = drawn
            self.fill(color, np.asarray(small, np.float32) / 255.0, box, opacity)

    def coverage(
        self,
        draw: Callable[[ImageDraw.ImageDraw, Callable[..., Point]], None],
        bounds: Sequence[float],
        clip: Optional[Callable[[ImageDraw.ImageDraw, Callable[..., Point]], None]] = None,
    ) -> Optional[Tuple[np.ndarray, Tuple[int, int, int, int]]]:
        """A shape's coverage, 0..255 (uint8), and the screen box it covers inside the layer;
        None where that box is empty. Drawn with PIL at 4x, then box-filtered down."""
        fx0, fy0, fx1, fy1 = bounds
        sx0, sy0 = self.to_screen(fx0, fy0)
        sx1, sy1 = self.to_screen(fx1, fy1)
        x0 = max(self.corner[0], int(math.floor(sx0)) - 1)
        y0 = max(self.corner[1], int(math.floor(sy0)) - 1)
        x1, y1 = min(self.limit[0], int(math.ceil(sx1)) + 1), min(self.limit[1], int(math.ceil(sy1)) + 1)
        if x1 <= x0 or y1 <= y0:
            return None
        k = SUPERSAMPLE
        mask = Image.new("L", ((x1 - x0) * k, (y1 - y0) * k), 0)

        def point(x: float, y: float) -> Point:
            px, py = self.to_screen(x, y)
            return (px - x0) * k, (py - y0) * k

        draw(ImageDraw.Draw(mask), point)
        if clip is not None:
            inside = Image.new("L", mask.size, 0)
            clip(ImageDraw.Draw(inside), point)
            mask = ImageChops.multiply(mask, inside)
        small = mask.resize((x1 - x0, y1 - y0), Image.BOX)
        return np.asarray(small), (x0, y0, x1, y1)

    def pen(self, width: float) -> int:
        """A stroke width in face units, as 4x mask pixels."""
        return max(1, int(round(width * self.scale * SUPERSAMPLE)))

    def image(self) -> Image.Image:
        """The layer as a straight-alpha RGBA image (of the window, with one)."""
        out = np.zeros(self.rgba.shape, np.uint8)
        crop, x, y = self.visible()
        x, y = x - self.corner[0], y - self.corner[1]
        out[y : y + crop.shape[0], x : x + crop.shape[1]] = crop
        return Image.fromarray(out, "RGBA")

    def visible(self) -> Tuple[np.ndarray, int, int]:
        """What `image()` holds, cropped to its visible pixels, and where that crop's corner
        sits on the screen: the same numbers, for the part that shows only."""
        alpha = self.rgba[..., 3]
        shows = alpha * 255.0 + 0.5 >= 1.0  # where `_straight` gives an alpha of 1 or more
        rows, cols = np.flatnonzero(shows.any(axis=1)), np.flatnonzero(shows.any(axis=0))
        if rows.size == 0:
            return np.zeros((0, 0, 4), np.uint8), self.corner[0], self.corner[1]
        r0, r1, c0, c1 = rows[0], rows[-1] + 1, cols[0], cols[-1] + 1
        return _straight(self.rgba[r0:r1, c0:c1]), self.corner[0] + int(c0), self.corner[1] + int(r0)


def _straight(rgba: np.ndarray) -> np.ndarray:
    """Premultiplied float RGBA as straight-alpha uint8."""
    alpha = rgba[..., 3:4]
    out = np.empty(rgba.shape, np.float32)
    # Where nothing was painted the colour is 0 as well as the alpha, so 0 / 1e-6 is 0 there.
    np.divide(rgba[..., :3], np.maximum(alpha, np.float32(1e-6)), out=out[..., :3])
    out[..., 3:] = alpha
    out *= np.float32(255.0)
    out += np.float32(0.5)
    np.clip(out, 0, 255, out=out)
    return out.astype(np.uint8)


def ellipse(cx: float, cy: float, rx: float, ry: float) -> Callable:
    def draw(d: ImageDraw.ImageDraw, p: Callable[..., Point]) -> None:
        d.ellipse([p(cx - rx, cy - ry), p(cx + rx, cy + ry)], fill=255)

    return draw


def ring(cx: float, cy: float, rx: float, ry: float, width: float, canvas: Canvas) -> Callable:
    def draw(d: ImageDraw.ImageDraw, p: Callable[..., Point]) -> None:
        h = width / 2.0
        d.ellipse([p(cx - rx - h, cy - ry - h), p(cx + rx + h, cy + ry + h)], fill=255)
        d.ellipse([p(cx - rx + h, cy - ry + h), p(cx + rx - h, cy + ry - h)], fill=0)

    return draw


def stroke(points: Sequence[Point], width: float, canvas: Canvas) -> Callable:
    """A polyline with round joints and caps."""

    def draw(d: ImageDraw.ImageDraw, p: Callable[..., Point]) -> None:
        pts = [p(x, y) for x, y in points]
        w = canvas.pen(width)
        d.line(pts, fill=255, width=w)
        # Round joints as discs the size of PIL's own joint="curve" pie slices, which it works
        # out in Python, point by point, at five times the cost; then the round caps.
        j = w / 2.0 - 1
        for x, y in pts[1:-1] if w > 4 else ():  # as PIL: thin lines need no joints
            d.ellipse([x - j, y - j, x + j, y + j], fill=255)
        r = w / 2.0
        for x, y in (pts[0], pts[-1]):
            d.ellipse([x - r, y - r, x + r, y + r], fill=255)

    return draw


def polygon(points: Sequence[Point]) -> Callable:
    def draw(d: ImageDraw.ImageDraw, p: Callable[..., Point]) -> None:
        d.polygon([p(x, y) for x, y in points], fill=255)

    return draw


def bounds_of(points: Iterable[Point], pad: float) -> Tuple[float, float, float, float]:
    xs, ys = zip(*points)
    return min(xs) - pad, min(ys) - pad, max(xs) + pad, max(ys) + pad


def curve(f: Callable[[float], float], x0: float, x1: float, steps: int = 48) -> List[Point]:
    """Points of y = f(x) from x0 to x1."""
    return [(x0 + (x1 - x0) * i / steps, f(x0 + (x1 - x0) * i / steps)) for i in range(steps + 1)]
