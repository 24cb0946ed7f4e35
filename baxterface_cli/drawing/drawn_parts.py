"""The default theme's mouth, brows and skin for any expression: drawn when first asked for, kept.

A theme of pictures has one sprite per named part. The default theme draws its parts from
the expression's numbers instead, so `PartBook` stands where the renderer looks up a part:
a name gives the theme's own sprite, a key of numbers (`DrawnParts.keys`) the part drawn at
those numbers. Keys round the numbers to steps of well under a screen pixel, so that a slow
change redraws only when something would show, and a still face draws nothing at all.
"""

from __future__ import annotations

import math
import threading
from collections import OrderedDict
from functools import lru_cache
from typing import Any, Callable, Dict, Hashable, List, NamedTuple, Optional, Tuple

import numpy as np

from ..core.expression import BROW_FIELDS, MOUTH_FIELDS, SKIN_FIELDS, Expression, finite
from ..core.face_state import Parts
from ..core.presets import from_parts
from .artwork import (
    BROW_INK,
    brow_strokes,
    brows_window,
    draw_lid,
    draw_lower_lid,
    draw_pupil,
    draw_skin,
    eye_centres,
    lid_window,
    lower_lid_window,
    pupil_window,
)
from .compositing import Rect, Sprite, alike_rows, div255, sprite_from_rgba, sprite_of
from .eye_sizes import LARGEST, EyeSizes, patched
from .mouth_drawing import draw_mouth_numbers, mouth_window
from .palette_store import kept_palette
from .skin_mixing import TINTS, SkinPalette, mixed_colour, skin_weights
from .vector_shapes import Canvas, Color

KEPT = 48  # drawn parts kept per kind: a morph's worth, and every speech shape
STEPS = 256  # mouth and brow numbers are rounded to 1/STEPS: under half a face pixel
EYE_STEPS = 64  # pupil sizes and lid tilts to 1/64: under a face pixel
SKIN_STEPS = 32  # skin numbers to 1/32: colour steps too small to see

Size = Tuple[int, int]


class DrawnMouthKey(NamedTuple):
    numbers: Tuple[int, ...]  # MOUTH_FIELDS, in 1/STEPS


class DrawnBrowsKey(NamedTuple):
    numbers: Tuple[int, ...]  # both brows' fields, in 1/STEPS


class DrawnSkinKey(NamedTuple):
    numbers: Tuple[int, ...]  # SKIN_FIELDS, in 1/SKIN_STEPS
    eyes: Tuple[int, ...] = (EYE_STEPS, EYE_STEPS)  # the eyes' sizes left to right, in 1/EYE_STEPS


_BROWS = BROW_FIELDS["left"] + BROW_FIELDS["right"]


def _round(e: Expression, fields: Tuple[str, ...], steps: int) -> Tuple[int, ...]:
    return tuple(int(math.floor(getattr(e, f) * steps + 0.5)) for f in fields)


def _expression(fields: Tuple[str, ...], numbers: Tuple[int, ...], steps: int) -> Expression:
    return Expression()._replace(**{f: n / steps for f, n in zip(fields, numbers)})


# Every frame asks for the keys of its expression, mostly the same one as the frame before:
# kept, so a face that only moves its eyes pays a lookup, not 31 roundings.
@lru_cache(maxsize=64)
def _keys(e: Expression) -> Parts:
    e = finite(e)
    return Parts(
        DrawnSkinKey(_round(e, SKIN_FIELDS, SKIN_STEPS), _eye_keys(e)[2]),
        DrawnMouthKey(_round(e, MOUTH_FIELDS, STEPS)),
        DrawnBrowsKey(_round(e, _BROWS, STEPS)),
    )


@lru_cache(maxsize=64)
def _eye_keys(e: Expression) -> Tuple[Tuple[int, ...], Tuple[int, ...], Tuple[int, ...]]:
    e = finite(e)

    def steps(values: Tuple[float, float], low: float, high: float) -> Tuple[int, ...]:
        return tuple(int(math.floor(min(high, max(low, v)) * EYE_STEPS + 0.5)) for v in values)

    return (
        steps((e.pupil_right, e.pupil_left), 0.5, 1.6),
        steps((e.lid_right_angle, e.lid_left_angle), -1.0, 1.0),
        steps((e.eye_right, e.eye_left), 0.8, LARGEST),
    )


class PartBook:
    """A kind of part by name (the theme's sprites) or by key (drawn, and the last KEPT kept)."""

    def __init__(
        self,
        named: Dict[Hashable, Sprite],
        draw: Callable[[Hashable], Sprite],
        key: Callable[[Hashable], Hashable],
    ) -> None:
        self.named = named
        self._draw = draw
        self._drawn: OrderedDict[Hashable, Sprite] = OrderedDict()
        # A key that a name's preset gives is that name's sprite: a still emotion draws nothing.
        self._aliases = {key(name): name for name in named}

    def __getitem__(self, key: Hashable) -> Sprite:
        if key in self.named:
            return self.named[key]
        if key in self._aliases:
            return self.named[self._aliases[key]]
        sprite = self._drawn.get(key)
        if sprite is None:
            sprite = self._drawn[key] = self._draw(key)
            while len(self._drawn) > KEPT:
                self._drawn.popitem(last=False)
        else:
            self._drawn.move_to_end(key)
        return sprite

    def __contains__(self, key: object) -> bool:
        return key in self.named

    def __iter__(self):
        return iter(self.named)

    def __len__(self) -> int:
        return len(self.named)

    def get(self, key: Hashable, default=None):
        return self.named.get(key, default)

    def items(self):
        return self.named.items()

    def keys(self):
        return self.named.keys()

    def values(self):
        return self.named.values()


def _drawn_sprite(size: Size, window: Tuple[float, ...], draw: Callable[[Canvas], None]) -> Sprite:
    canvas = Canvas(size, window)
    draw(canvas)
    sprite = sprite_from_rgba(*canvas.visible()) if canvas.rgba.size else None
    return _NOTHING if sprite is None else sprite


def _transparent_pixel() -> Sprite:
    sprite = Sprite(0, 0, np.zeros((1, 1, 3), np.uint16), np.full((1, 1, 3), 255, np.uint16))
    sprite.rgb_a.flags.writeable = sprite.inv.flags.writeable = False  # one, shared
    return sprite


_NOTHING = _transparent_pixel()  # nothing drawn: as an empty layer of a theme


def _ink_sprite(canvas: Canvas, color: Color, shapes: List[Tuple[Callable, Tuple[float, ...]]]) -> Sprite:
    """Shapes of one opaque colour that never overlap, as a sprite: what drawing them on
    `canvas` (`_drawn_sprite`) gives, without the float layer. Their coverage is the alpha."""
    alpha = np.zeros(canvas.rgba.shape[:2], np.uint8)
    cx, cy = canvas.corner
    for shape, bounds in shapes:
        drawn = canvas.coverage(shape, bounds)
        if drawn is not None:
            small, (x0, y0, x1, y1) = drawn
            region = alpha[y0 - cy : y1 - cy, x0 - cx : x1 - cx]
            np.maximum(region, small, out=region)  # apart, so the same as laying one over another
    sprite = sprite_of(alpha, np.array(color[::-1], np.uint8), cx, cy)
    return _NOTHING if sprite is None else sprite


class DrawnParts:
    """Keys for an expression's parts, and the books that draw them, at one screen size."""

    def __init__(
        self, size: Size, skins: Dict[int, Sprite], mouths: Dict[str, Sprite], brows: Dict[str, Sprite]
    ):
        self.size = size
        self.skins = PartBook(skins, self._skin, lambda i: self.keys(from_parts(Parts(skin=i))).skin)
        self.mouths = PartBook(mouths, self._mouth, lambda m: self.keys(from_parts(Parts(mouth=m))).mouth)
        self.brows = PartBook(brows, self._brows, lambda b: self.keys(from_parts(Parts(brows=b))).brows)
        self._basis: Dict[int, Sprite] = {}
        self._palette: Any = None  # a SkinPalette, False where there is none, None not yet
        self._making_palette = threading.Lock()
        self._eyes: OrderedDict[Tuple[Any, ...], Any] = OrderedDict()
        self.eye_sizes = EyeSizes(size)

    @staticmethod
    def eye_keys(e: Expression) -> Tuple[Tuple[int, ...], Tuple[int, ...], Tuple[int, ...]]:
        """(pupil sizes, lid tilts, eye sizes) of the eyes left to right on the screen (the
        robot's right eye first), in 1/EYE_STEPS."""
        return _eye_keys(e)

    def pupil(self, index: int, size: int) -> Sprite:
        """Eye `index`'s pupil at `size` (1/EYE_STEPS), at rest."""
        cx, cy = eye_centres()[index]
        scale = size / EYE_STEPS
        return self._kept(
            ("pupil", index, size, 0),
            lambda: _drawn_sprite(
                self.size, pupil_window(index, scale), lambda c: draw_pupil(c, cx, cy, scale)
            ),
        )

    def lid(self, index: int, tilt: int, size: int = EYE_STEPS) -> Tuple[Sprite, Tuple[int, int]]:
        """Eye `index`'s lid, closed, tilted by `tilt` and as large as an eye of `size` (both in
        1/EYE_STEPS), with its band of alike rows."""
        cx, cy = eye_centres()[index]
        angle, k = tilt / EYE_STEPS, size / EYE_STEPS

        def draw() -> Tuple[Sprite, Tuple[int, int]]:
            window = lid_window(index, angle, k)
            sprite = _drawn_sprite(self.size, window, lambda c: draw_lid(c, cx, cy, angle, k))
            return sprite, alike_rows(sprite)

        return self._kept(("lid", index, tilt, size), draw)

    def lower_lid(self, index: int, size: int = EYE_STEPS) -> Tuple[Sprite, Tuple[int, int]]:
        """Eye `index`'s lower lid, risen all the way, for an eye of `size` (1/EYE_STEPS), with
        its band of alike rows."""
        cx, cy = eye_centres()[index]
        k = size / EYE_STEPS

        def draw() -> Tuple[Sprite, Tuple[int, int]]:
            window = lower_lid_window(index, k)
            sprite = _drawn_sprite(self.size, window, lambda c: draw_lower_lid(c, cx, cy, k))
            return sprite, alike_rows(sprite)

        return self._kept(("lower lid", index, size, 0), draw)

    def white(self, index: int, size: int) -> Tuple[Rect, np.ndarray]:
        """The eye white round eye `index` with the socket of an eye of `size` (1/EYE_STEPS)."""
        return self.eye_sizes.white(index, size / EYE_STEPS)

    def _kept(self, key: Tuple[Any, ...], draw: Callable[[], Any]) -> Any:
        found = self._eyes.get(key)
        if found is None:
            found = self._eyes[key] = draw()
            while len(self._eyes) > KEPT:
                self._eyes.popitem(last=False)
        else:
            self._eyes.move_to_end(key)
        return found

    @staticmethod
    def keys(e: Expression) -> Parts:
        """The drawn parts that show expression `e`."""
        return _keys(e)

    def _mouth(self, key: Hashable) -> Sprite:
        e = _expression(MOUTH_FIELDS, key.numbers, STEPS)  # type: ignore[attr-defined]
        return _drawn_sprite(self.size, mouth_window(e), lambda c: draw_mouth_numbers(c, e))

    def _brows(self, key: Hashable) -> Sprite:
        e = _expression(_BROWS, key.numbers, STEPS)  # type: ignore[attr-defined]
        canvas = Canvas(self.size, brows_window(e))  # its float layer unused: zeros cost nothing
        return _ink_sprite(canvas, BROW_INK, brow_strokes(canvas, e))

    def _skin(self, key: Hashable) -> Sprite:
        """A skin between the named ones (drawing/skin_mixing.py), its sockets cut for eyes of
        other sizes (drawing/eye_sizes.py)."""
        numbers = _skin_numbers(key)
        palette = self.palette()
        if palette is not None:
            sprite = palette.sprite(*numbers)
        else:
            base = self.skins[skin_weights(*numbers)[0]]
            plain = [self._plain(i).rgb_a for i in range(TINTS)]
            cheeky = [self.skins[i].rgb_a for i in range(TINTS + 1)]
            sprite = Sprite(base.x, base.y, mixed_colour(plain, cheeky, *numbers), base.inv)
        return patched(sprite, self._cuts(key))

    def _cuts(self, key: Hashable) -> List[Tuple[Rect, np.ndarray, np.ndarray]]:
        """The skin of `key` round each eye of another size, with its socket."""
        numbers = _skin_numbers(key)
        eyes = key.eyes  # type: ignore[attr-defined]
        return [self.eye_sizes.cut(i, k / EYE_STEPS, numbers) for i, k in enumerate(eyes) if k != EYE_STEPS]

    def named(self, parts: Parts) -> bool:
        """Whether every part of `parts` is one of the theme's own (a preset's): a still
        emotion, whose frame the renderer keeps."""
        return all(
            key in book or key in book._aliases
            for book, key in ((self.skins, parts.skin), (self.mouths, parts.mouth), (self.brows, parts.brows))
        )

    def skin_stacked(self, key: Hashable) -> Optional[Tuple[np.ndarray, Optional[np.ndarray]]]:
        """The skin of `key` laid alone, as the renderer stacks it: premultiplied colour,
        (h, w, 3) uint8, and 255 - alpha, (h, w, 1) uint8, or None where it is the named skins'
        own (eyes as drawn). None for a named skin (the renderer keeps those) or without a
        palette."""
        if key in self.skins or key in self.skins._aliases:
            return None
        palette = self.palette()
        if palette is None:
            return None
        prem = palette.stacked(*_skin_numbers(key))
        cuts = self._cuts(key)
        if not cuts:
            return prem, None
        prem = prem.copy()  # the palette's is read-only
        inv = palette.inv[..., :1].astype(np.uint8)
        for (x0, y0, x1, y1), colour, clear in cuts:
            region = (slice(y0 - palette.y, y1 - palette.y), slice(x0 - palette.x, x1 - palette.x))
            prem[region] = div255(colour)
            inv[region] = clear[..., :1]
        return prem, inv

    def palette(self) -> Optional[SkinPalette]:
        """The named skins as a palette, made when a skin between them is first asked for."""
        with self._making_palette:  # made once, whichever thread asks first
            if self._palette is None:

                def make() -> Optional[SkinPalette]:
                    plain = [self._plain(i) for i in range(TINTS)]
                    return SkinPalette.of(plain, [self.skins[i] for i in range(TINTS + 1)])

                self._palette = kept_palette("skin", self.size, make) or False
        return self._palette or None

    def _plain(self, index: int) -> Sprite:
        """Skin `index` without its cheeks, drawn once."""
        if index not in self._basis:
            self._basis[index] = sprite_from_rgba(np.asarray(draw_skin(self.size, index, cheeks=False)))
        return self._basis[index]


def _skin_numbers(key: Hashable) -> Tuple[float, float, float]:
    tint, cheeks, sleepy = (n / SKIN_STEPS for n in key.numbers)  # type: ignore[attr-defined]
    return tint, cheeks, sleepy
