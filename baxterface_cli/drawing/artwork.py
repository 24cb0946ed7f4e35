"""The default theme, drawn from vector shapes at any screen size.

Every shape is given in face units: pixels of the original 1024x600 face.
A screen of another size gets the face scaled uniformly to fit and centred,
so circles stay round and eye coordinates keep their meaning. Shapes are
drawn four times larger and box-filtered down, which anti-aliases them.

`draw_theme(size)` returns the layers; `assets/draw_default_theme.py` writes
them to assets/default/ (the committed theme is exactly this at 1024x600).
"""

from __future__ import annotations

import math
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np
from PIL import Image

from ..core.expression import BROW_FIELDS, Expression
from ..core.face_constants import BROWS, MOUTHS, SKINS, VISEMES, viseme_mouth
from ..core.face_state import Parts
from ..core.presets import brow_heights, from_parts
from .mouth_drawing import CENTRE_X, INK, draw_mouth_numbers
from .vector_shapes import (
    FACE_SIZE,
    Canvas,
    Color,
    Point,
    bounds_of,
    curve,
    ellipse,
    polygon,
    ring,
    stroke,
)

# Face geometry, in face units.
EYE_Y = 255.0
EYE_DX = 200.0  # each eye's distance from the centre line
SOCKET = (110.0, 140.0)  # socket semi-axes
OUTLINE = 9.0  # the dark ring round each socket
PUPIL_R = 44.0
LID = (126.0, 152.0)  # the closed lid's half width, and its lower edge's depth below the eye centre
LID_SAG = 60.0  # how much higher the lid's edge is at its ends than in its middle
LID_TOP = 175.0  # the lid's top edge sits this far above the eye centre when closed
LID_TRAVEL = 330.0  # closed -> open, as the original's eyelid offset

# (centre colour, edge colour) of each skin's radial gradient.
SKIN_COLORS: Dict[int, Tuple[Color, Color]] = {
    0: ((255, 247, 200), (244, 220, 138)),
    1: ((255, 234, 150), (240, 198, 84)),
    2: ((255, 216, 128), (241, 163, 62)),
    3: ((255, 188, 108), (234, 122, 52)),
    4: ((250, 142, 112), (212, 66, 54)),
    5: ((216, 208, 232), (160, 150, 196)),
}
BROW_INK: Color = (84, 52, 40)
PUPIL: Color = (24, 24, 34)
WHITE: Color = (252, 252, 248)
LID_COLOR: Color = (226, 172, 126)
CHEEK: Color = (255, 110, 110)
ZZZ: Color = (92, 80, 140)


def eye_centres() -> List[Point]:
    return [(CENTRE_X - EYE_DX, EYE_Y), (CENTRE_X + EYE_DX, EYE_Y)]


# -- layers ----------------------------------------------------------------


def draw_background(
    size: Tuple[int, int], sizes: Tuple[float, float] = (1.0, 1.0), window: Optional[Sequence[float]] = None
) -> Image.Image:
    """Eye whites, shaded toward the rims (of sockets `sizes` times as large as drawn); the rest
    of the screen never shows. With `window` (face units), only that part of the screen."""
    c = Canvas(size, window)
    ys, xs = np.mgrid[c.corner[1] : c.limit[1], c.corner[0] : c.limit[0]].astype(np.float32)
    fx = (xs + 0.5 - c.origin[0]) / c.scale
    fy = (ys + 0.5 - c.origin[1]) / c.scale
    reach = np.full(fx.shape, 9.0, np.float32)
    for (cx, cy), k in zip(eye_centres(), sizes):
        reach = np.minimum(reach, np.hypot((fx - cx) / (SOCKET[0] * k), (fy - cy) / (SOCKET[1] * k)))
    shade = np.clip((reach - 0.55) / 0.45, 0.0, 1.0) ** 2
    rim = np.array((214, 214, 226), np.float32)
    rgb = np.array(WHITE, np.float32) * (1.0 - shade[..., None]) + rim * shade[..., None]
    c.paint_over(rgb / 255.0)
    return c.image()


def draw_pupil(c: Canvas, cx: float, cy: float, scale: float = 1.0) -> None:
    """A pupil with its catch-lights, `scale` times its drawn size."""
    r = PUPIL_R * scale
    c.shape(ellipse(cx, cy, r, r), (cx - r - 2, cy - r - 2, cx + r + 2, cy + r + 2), PUPIL)
    hx, hy, h = cx - 15 * scale, cy - 17 * scale, 11 * scale
    c.shape(ellipse(hx, hy, h, h), (hx - h - 2, hy - h - 2, hx + h + 2, hy + h + 2), WHITE)
    lx, ly, lr = cx + 14 * scale, cy + 16 * scale, 5 * scale
    c.shape(ellipse(lx, ly, lr, lr), (lx - lr - 2, ly - lr - 2, lx + lr + 2, ly + lr + 2), WHITE, 0.8)


def pupil_window(index: int, scale: float) -> Tuple[float, float, float, float]:
    cx, cy = eye_centres()[index]
    r = PUPIL_R * scale + 6
    return (cx - r, cy - r, cx + r, cy + r)


def draw_eyes(size: Tuple[int, int]) -> Image.Image:
    """Both pupils, with a catch-light each, at rest (looking ahead)."""
    c = Canvas(size)
    for cx, cy in eye_centres():
        draw_pupil(c, cx, cy)
    return c.image()


# A tilted lid's edge comes down across the eye in a wedge even when the lid is open, where it
# rests above the socket: at tilt 1 it drops LID_LOWER face pixels at its pivoting corner and
# LID_LOWER + LID_TILT at the corner it tilts toward (a glare, or sorrow); a closed lid's edge
# only goes further below the socket, so a shut eye stays shut. Part of the way grows as a
# power under 1, so that a small tilt already shows.
LID_LOWER, LID_TILT, LID_TILT_POWER = 50.0, 170.0, 0.6


def lid_edge(x: float, cx: float, cy: float, tilt: float = 0.0, size: float = 1.0) -> float:
    """The closed lid's lower edge: a gentle arc, lowest under the eye's centre. `tilt` above 0
    drops its inner corner (the one toward the face's centre line), below 0 its outer one, the
    edge pivoting about the other corner; `size` scales it with its eye, about the eye's centre."""
    rx, depth = LID[0] * size, LID[1] * size
    inward = 1.0 if cx < CENTRE_X else -1.0  # which way x runs toward the centre line
    toward_inner = min(1.0, max(0.0, (1.0 + inward * (x - cx) / rx) / 2))  # 0 outer corner .. 1 inner
    reach = toward_inner if tilt > 0 else 1.0 - toward_inner
    drop = _tilt_share(tilt) * (LID_LOWER + LID_TILT * reach) * size
    return cy + depth - LID_SAG * size * (1 - math.sqrt(max(0.0, 1 - ((x - cx) / rx) ** 2))) + drop


def _tilt_share(tilt: float) -> float:
    return min(1.0, abs(tilt)) ** LID_TILT_POWER


def draw_lid(c: Canvas, cx: float, cy: float, tilt: float = 0.0, size: float = 1.0) -> None:
    rx = LID[0] * size
    lower = curve(lambda x: lid_edge(x, cx, cy, tilt, size), cx + rx, cx - rx)
    outline = [(cx - rx, cy - LID_TOP * size), (cx + rx, cy - LID_TOP * size)] + lower
    c.shape(polygon(outline), bounds_of(outline, 2), LID_COLOR)
    lash = curve(lambda x: lid_edge(x, cx, cy, tilt, size) - 3, cx - rx + 6, cx + rx - 6)
    c.shape(stroke(lash, 8, c), bounds_of(lash, 8), INK)


def lid_window(index: int, tilt: float, size: float = 1.0) -> Tuple[float, float, float, float]:
    cx, cy = eye_centres()[index]
    rx, depth = LID[0] * size, LID[1] * size
    low = cy + depth + _tilt_share(tilt) * (LID_LOWER + LID_TILT) * size + 8
    return (cx - rx - 8, cy - LID_TOP * size - 4, cx + rx + 8, low)


# The lower lid, risen all the way: its edge an arc bulging up, LOWER_TOP below the eye's centre
# in its middle and LOWER_SAG lower at its ends; it sinks LOWER_TRAVEL to go out of sight.
LOWER_TOP, LOWER_SAG, LOWER_TRAVEL = 52.0, 44.0, 110.0
LOWER_DEPTH = 175.0  # its flat lower part reaches this far below the eye's centre


def lower_lid_edge(x: float, cx: float, cy: float, size: float = 1.0) -> float:
    rx = LID[0] * size
    return cy + (LOWER_TOP + LOWER_SAG * (1 - math.sqrt(max(0.0, 1 - ((x - cx) / rx) ** 2)))) * size


def draw_lower_lid(c: Canvas, cx: float, cy: float, size: float = 1.0) -> None:
    """The lower lid, risen: skin-coloured below an upward arc, its edge lined in ink."""
    rx = LID[0] * size
    upper = curve(lambda x: lower_lid_edge(x, cx, cy, size), cx - rx, cx + rx)
    outline = upper + [(cx + rx, cy + LOWER_DEPTH * size), (cx - rx, cy + LOWER_DEPTH * size)]
    c.shape(polygon(outline), bounds_of(outline, 2), LID_COLOR)
    line = curve(lambda x: lower_lid_edge(x, cx, cy, size) + 2, cx - rx + 10, cx + rx - 10)
    c.shape(stroke(line, 6, c), bounds_of(line, 6), INK)


def lower_lid_window(index: int, size: float = 1.0) -> Tuple[float, float, float, float]:
    cx, cy = eye_centres()[index]
    rx = LID[0] * size
    return (cx - rx - 8, cy + LOWER_TOP * size - 8, cx + rx + 8, cy + LOWER_DEPTH * size + 4)


def draw_eyelids(size: Tuple[int, int]) -> Image.Image:
    """Both lids, closed. All but their lowest rows are one flat colour, so
    those rows are identical and a moving lid changes pixels near its edge only."""
    c = Canvas(size)
    for cx, cy in eye_centres():
        draw_lid(c, cx, cy)
    return c.image()


def draw_skin(
    size: Tuple[int, int],
    index: int,
    cheeks: bool = True,
    sockets: bool = True,
    window: Optional[Sequence[float]] = None,
) -> Image.Image:
    """The face: a radial gradient with see-through sockets ringed in ink (and, unless told
    not, the cheeks of a waking skin). Without `sockets`, the skin where they would be, for
    cutting sockets of other sizes into; with `window` (face units), that part of it only."""
    c = Canvas(size, window)
    centre, edge = (np.array(col, np.float32) for col in SKIN_COLORS[index])
    ys, xs = np.mgrid[c.corner[1] : c.limit[1], c.corner[0] : c.limit[0]].astype(np.float32)
    fx = (xs + 0.5 - c.origin[0]) / c.scale - CENTRE_X
    fy = (ys + 0.5 - c.origin[1]) / c.scale - 300.0
    t = np.clip(np.hypot(fx / 620.0, fy / 420.0), 0.0, 1.0) ** 1.6
    c.paint_over((centre * (1.0 - t[..., None]) + edge * t[..., None]) / 255.0)
    if sockets:
        holes = Canvas(size, window)  # the sockets' coverage, to cut out of the skin
        for index_of_eye in range(2):
            holes.shape(*socket_hole(index_of_eye, 1.0), WHITE)
        c.rgba *= 1.0 - holes.rgba[..., 3:4]
        for index_of_eye in range(2):
            c.shape(*socket_ring(index_of_eye, 1.0, c), INK)
    if index != 5:
        if cheeks:
            for cx in (CENTRE_X - 300, CENTRE_X + 300):
                c.shape(ellipse(cx, 440, 62, 34), (cx - 64, 404, cx + 64, 476), CHEEK, 0.22)
    else:
        for x, y, h in ((842, 120, 34), (888, 70, 46), (944, 12, 58)):
            z = [(x, y), (x + h * 0.8, y), (x, y + h), (x + h * 0.8, y + h)]
            c.shape(stroke(z, 7, c), bounds_of(z, 7), ZZZ)
    return c.image()


def socket_hole(index: int, size: float) -> Tuple[Any, Tuple[float, float, float, float]]:
    """Eye `index`'s socket, `size` times as large as drawn: the shape cut out of the skin, and
    its bounds."""
    cx, cy = eye_centres()[index]
    rx, ry = SOCKET[0] * size, SOCKET[1] * size
    return ellipse(cx, cy, rx, ry), (cx - rx - 2, cy - ry - 2, cx + rx + 2, cy + ry + 2)


def socket_ring(index: int, size: float, c: Canvas) -> Tuple[Any, Tuple[float, float, float, float]]:
    """The ink ring round that socket, and its bounds."""
    cx, cy = eye_centres()[index]
    rx, ry = SOCKET[0] * size, SOCKET[1] * size
    box = (cx - rx - OUTLINE, cy - ry - OUTLINE, cx + rx + OUTLINE, cy + ry + OUTLINE)
    return ring(cx, cy, rx, ry, OUTLINE, c), box


def socket_window(index: int, size: float) -> Tuple[float, float, float, float]:
    """A box, in face units, holding eye `index`'s socket and ring at `size` and as drawn."""
    cx, cy = eye_centres()[index]
    grow = max(1.0, size)
    rx, ry = SOCKET[0] * grow + OUTLINE + 3, SOCKET[1] * grow + OUTLINE + 3
    return (cx - rx, cy - ry, cx + rx, cy + ry)


def draw_mouth(size: Tuple[int, int], name: str) -> Image.Image:
    """A named mouth (an emotion's or a speech shape's): its preset's numbers, drawn."""
    c = Canvas(size)
    draw_mouth_numbers(c, from_parts(Parts(mouth=name)))
    return c.image()


# The mouth layer of each speech shape ("speak-open": "open"), in the order of face_constants.VISEMES.
SPEECH_MOUTHS: Dict[str, str] = {viseme_mouth(shape): shape for shape in VISEMES}


BROW_PEN = 15


def brow_strokes(c: Canvas, e: Expression) -> List[Tuple[Callable, Tuple[float, float, float, float]]]:
    """Both brows of expression `e`, left to right on the screen, as (shape, bounds): each a
    stroke of BROW_INK through its inner end, middle and outer end. They never overlap."""
    strokes = []
    for side, robot_side in ((-1, "right"), (1, "left")):
        inner, middle, outer = brow_heights(*(getattr(e, f) for f in BROW_FIELDS[robot_side]))
        cx = CENTRE_X + side * EYE_DX
        x_inner, x_outer = cx - side * 100, cx + side * 100

        def y_at(t: float, inner: float = inner, middle: float = middle, outer: float = outer) -> float:
            return (1 - t) ** 2 * inner + 2 * (1 - t) * t * (2 * middle - (inner + outer) / 2) + t**2 * outer

        line = [(x_inner + (x_outer - x_inner) * i / 40, y_at(i / 40)) for i in range(41)]
        strokes.append((stroke(line, BROW_PEN, c), bounds_of(line, BROW_PEN)))
    return strokes


def draw_brows_numbers(c: Canvas, e: Expression) -> None:
    """Both brows of expression `e` on canvas `c`."""
    for shape, bounds in brow_strokes(c, e):
        c.shape(shape, bounds, BROW_INK)


def brows_window(e: Expression) -> Tuple[float, float, float, float]:
    """A box, in face units, that holds both brows of `e`."""
    heights = [
        h for side in ("left", "right") for h in brow_heights(*(getattr(e, f) for f in BROW_FIELDS[side]))
    ]
    return (CENTRE_X - EYE_DX - 120, min(heights) - 40, CENTRE_X + EYE_DX + 120, max(heights) + 40)


def draw_brows(size: Tuple[int, int], name: str) -> Image.Image:
    c = Canvas(size)
    draw_brows_numbers(c, from_parts(Parts(brows=name)))
    return c.image()


def layer_names() -> List[Tuple[str, str]]:
    """(kind, name) of every layer of a complete theme, back to front by kind."""
    names = [("background", "background"), ("eyes", "eyes"), ("eyelids", "eyelids")]
    names += [("skin", str(i)) for i in SKINS]
    names += [("mouth", m) for m in MOUTHS]
    names += [("mouth", m) for m in SPEECH_MOUTHS]
    names += [("brows", b) for b in BROWS]
    return names


def draw_layer(size: Tuple[int, int], kind: str, name: str) -> Image.Image:
    if kind == "background":
        return draw_background(size)
    if kind == "eyes":
        return draw_eyes(size)
    if kind == "eyelids":
        return draw_eyelids(size)
    if kind == "skin":
        return draw_skin(size, int(name))
    if kind == "mouth":
        return draw_mouth(size, name)
    return draw_brows(size, name)


def draw_theme(size: Tuple[int, int] = FACE_SIZE) -> Dict[Tuple[str, str], Image.Image]:
    """Every layer of the default theme at `size`, keyed by (kind, name)."""
    return {key: draw_layer(size, *key) for key in layer_names()}
