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
from typing import Dict, List, NamedTuple, Sequence, Tuple

import numpy as np
from PIL import Image

from ..core.tables import BROWS, MOUTHS, SKINS, VISEMES, viseme_mouth
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
CENTRE_X = 512.0
EYE_Y = 255.0
EYE_DX = 200.0  # each eye's distance from the centre line
SOCKET = (110.0, 140.0)  # socket semi-axes
OUTLINE = 9.0  # the dark ring round each socket
PUPIL_R = 44.0
LID = (126.0, 152.0)  # the closed lid's half width, and its lower edge's depth below the eye centre
LID_SAG = 60.0  # how much higher the lid's edge is at its ends than in its middle
LID_TOP = 175.0  # the lid's top edge sits this far above the eye centre when closed
LID_TRAVEL = 330.0  # closed -> open, as the original's eyelid offset
MOUTH_Y = 470.0

# (centre colour, edge colour) of each skin's radial gradient.
SKIN_COLORS: Dict[int, Tuple[Color, Color]] = {
    0: ((255, 247, 200), (244, 220, 138)),
    1: ((255, 234, 150), (240, 198, 84)),
    2: ((255, 216, 128), (241, 163, 62)),
    3: ((255, 188, 108), (234, 122, 52)),
    4: ((250, 142, 112), (212, 66, 54)),
    5: ((216, 208, 232), (160, 150, 196)),
}
INK: Color = (62, 36, 38)  # outlines, mouth lines
BROW_INK: Color = (84, 52, 40)
PUPIL: Color = (24, 24, 34)
WHITE: Color = (252, 252, 248)
LID_COLOR: Color = (226, 172, 126)
MOUTH_INSIDE: Color = (128, 32, 44)
TONGUE: Color = (232, 110, 120)
TEETH: Color = (250, 250, 244)
CHEEK: Color = (255, 110, 110)
ZZZ: Color = (92, 80, 140)


def eye_centres() -> List[Point]:
    return [(CENTRE_X - EYE_DX, EYE_Y), (CENTRE_X + EYE_DX, EYE_Y)]


# -- layers ----------------------------------------------------------------


def draw_background(size: Tuple[int, int]) -> Image.Image:
    """Eye whites, shaded toward the rims; the rest of the screen never shows."""
    c = Canvas(size)
    ys, xs = np.mgrid[0 : c.height, 0 : c.width].astype(np.float32)
    fx = (xs + 0.5 - c.origin[0]) / c.scale
    fy = (ys + 0.5 - c.origin[1]) / c.scale
    reach = np.full(fx.shape, 9.0, np.float32)
    for cx, cy in eye_centres():
        reach = np.minimum(reach, np.hypot((fx - cx) / SOCKET[0], (fy - cy) / SOCKET[1]))
    shade = np.clip((reach - 0.55) / 0.45, 0.0, 1.0) ** 2
    rim = np.array((214, 214, 226), np.float32)
    rgb = np.array(WHITE, np.float32) * (1.0 - shade[..., None]) + rim * shade[..., None]
    c.rgba[..., :3] = rgb / 255.0
    c.rgba[..., 3] = 1.0
    return c.image()


def draw_eyes(size: Tuple[int, int]) -> Image.Image:
    """Both pupils, with a catch-light each, at rest (looking ahead)."""
    c = Canvas(size)
    for cx, cy in eye_centres():
        box = (cx - PUPIL_R - 2, cy - PUPIL_R - 2, cx + PUPIL_R + 2, cy + PUPIL_R + 2)
        c.shape(ellipse(cx, cy, PUPIL_R, PUPIL_R), box, PUPIL)
        hx, hy = cx - 15, cy - 17
        c.shape(ellipse(hx, hy, 11, 11), (hx - 13, hy - 13, hx + 13, hy + 13), WHITE)
        c.shape(ellipse(cx + 14, cy + 16, 5, 5), (cx + 7, cy + 9, cx + 21, cy + 23), WHITE, 0.8)
    return c.image()


def lid_edge(x: float, cx: float, cy: float) -> float:
    """The closed lid's lower edge: a gentle arc, lowest under the eye's centre."""
    rx, depth = LID
    return cy + depth - LID_SAG * (1 - math.sqrt(max(0.0, 1 - ((x - cx) / rx) ** 2)))


def draw_eyelids(size: Tuple[int, int]) -> Image.Image:
    """Both lids, closed. All but their lowest rows are one flat colour, so
    those rows are identical and a moving lid changes pixels near its edge only."""
    c = Canvas(size)
    rx = LID[0]
    for cx, cy in eye_centres():
        lower = curve(lambda x, cx=cx, cy=cy: lid_edge(x, cx, cy), cx + rx, cx - rx)
        outline = [(cx - rx, cy - LID_TOP), (cx + rx, cy - LID_TOP)] + lower
        c.shape(polygon(outline), bounds_of(outline, 2), LID_COLOR)
        lash = curve(lambda x, cx=cx, cy=cy: lid_edge(x, cx, cy) - 3, cx - rx + 6, cx + rx - 6)
        c.shape(stroke(lash, 8, c), bounds_of(lash, 8), INK)
    return c.image()


def draw_skin(size: Tuple[int, int], index: int) -> Image.Image:
    """The face: a radial gradient with see-through sockets ringed in ink."""
    c = Canvas(size)
    centre, edge = (np.array(col, np.float32) for col in SKIN_COLORS[index])
    ys, xs = np.mgrid[0 : c.height, 0 : c.width].astype(np.float32)
    fx = (xs + 0.5 - c.origin[0]) / c.scale - CENTRE_X
    fy = (ys + 0.5 - c.origin[1]) / c.scale - 300.0
    t = np.clip(np.hypot(fx / 620.0, fy / 420.0), 0.0, 1.0) ** 1.6
    c.rgba[..., :3] = (centre * (1.0 - t[..., None]) + edge * t[..., None]) / 255.0
    c.rgba[..., 3] = 1.0
    holes = Canvas(size)  # the sockets' coverage, to cut out of the skin
    for cx, cy in eye_centres():
        rx, ry = SOCKET
        holes.shape(ellipse(cx, cy, rx, ry), (cx - rx - 2, cy - ry - 2, cx + rx + 2, cy + ry + 2), WHITE)
    c.rgba *= 1.0 - holes.rgba[..., 3:4]
    for cx, cy in eye_centres():
        rx, ry = SOCKET
        box = (cx - rx - OUTLINE, cy - ry - OUTLINE, cx + rx + OUTLINE, cy + ry + OUTLINE)
        c.shape(ring(cx, cy, rx, ry, OUTLINE, c), box, INK)
    if index != 5:
        for cx in (CENTRE_X - 300, CENTRE_X + 300):
            c.shape(ellipse(cx, 440, 62, 34), (cx - 64, 404, cx + 64, 476), CHEEK, 0.22)
    else:
        for x, y, h in ((842, 120, 34), (888, 70, 46), (944, 12, 58)):
            z = [(x, y), (x + h * 0.8, y), (x, y + h), (x + h * 0.8, y + h)]
            c.shape(stroke(z, 7, c), bounds_of(z, 7), ZZZ)
    return c.image()


def _mouth_opening(top: float, depth: float, half: float) -> List[Point]:
    """An open mouth: a gently curved top and a deep U below it."""
    upper = curve(lambda x: top + 10 * (1 - ((x - CENTRE_X) / half) ** 2), CENTRE_X - half, CENTRE_X + half)
    lower = curve(
        lambda x: top + depth * (1 - ((x - CENTRE_X) / half) ** 2), CENTRE_X + half, CENTRE_X - half
    )
    return upper + lower


def draw_mouth(size: Tuple[int, int], name: str) -> Image.Image:
    c = Canvas(size)
    y = MOUTH_Y
    if name == "smile":
        line = curve(
            lambda x: y - 12 + 44 * (1 - ((x - CENTRE_X) / 130) ** 2), CENTRE_X - 130, CENTRE_X + 130
        )
        c.shape(stroke(line, 12, c), bounds_of(line, 12), INK)
    elif name in ("smile-open", "teeth"):
        shape = _mouth_opening(y - 16, 92, 128)
        c.shape(polygon(shape), bounds_of(shape, 2), MOUTH_INSIDE)
        if name == "teeth":
            # The teeth fill the top of the opening, never past its outline.
            band = _mouth_opening(y - 16, 92, 128)[:49] + curve(
                lambda x: min(
                    y + 14 + 12 * (1 - ((x - CENTRE_X) / 128) ** 2),
                    y - 16 + 92 * (1 - ((x - CENTRE_X) / 128) ** 2),
                ),
                CENTRE_X + 128,
                CENTRE_X - 128,
            )
            c.shape(polygon(band), bounds_of(band, 2), TEETH)
            for k in (-72, -24, 24, 72):
                gap = [(CENTRE_X + k, y - 4), (CENTRE_X + k * 1.02, y + 22)]
                c.shape(stroke(gap, 3, c), bounds_of(gap, 4), INK, 0.55)
        else:
            c.shape(ellipse(CENTRE_X, y + 58, 62, 24), (CENTRE_X - 64, y + 32, CENTRE_X + 64, y + 84), TONGUE)
        c.shape(stroke(shape + shape[:1], 9, c), bounds_of(shape, 9), INK)
    elif name == "sad":
        line = curve(
            lambda x: y + 40 - 40 * (1 - ((x - CENTRE_X) / 110) ** 2), CENTRE_X - 110, CENTRE_X + 110
        )
        c.shape(stroke(line, 12, c), bounds_of(line, 12), INK)
    elif name == "bored":
        line = [(CENTRE_X - 92, y + 20), (CENTRE_X + 92, y + 20)]
        c.shape(stroke(line, 12, c), bounds_of(line, 12), INK)
    elif name == "confused":
        line = curve(
            lambda x: y + 20 + 13 * math.sin((x - CENTRE_X) / 100 * 2.6 * math.pi / 2),
            CENTRE_X - 110,
            CENTRE_X + 110,
        )
        c.shape(stroke(line, 11, c), bounds_of(line, 11), INK)
    elif name == "angry":
        top = curve(lambda x: y + 6 - 22 * (1 - ((x - CENTRE_X) / 112) ** 2), CENTRE_X - 112, CENTRE_X + 112)
        bottom = curve(
            lambda x: y + 44 - 10 * (1 - ((x - CENTRE_X) / 104) ** 2), CENTRE_X + 104, CENTRE_X - 104
        )
        shape = top + bottom
        c.shape(polygon(shape), bounds_of(shape, 2), TEETH)
        mid = curve(lambda x: y + 24 - 16 * (1 - ((x - CENTRE_X) / 108) ** 2), CENTRE_X - 106, CENTRE_X + 106)
        c.shape(stroke(mid, 3, c), bounds_of(mid, 4), INK, 0.7)
        for k in (-60, -20, 20, 60):
            gap = [(CENTRE_X + k, y - 12 + abs(k) * 0.08), (CENTRE_X + k, y + 38)]
            c.shape(stroke(gap, 3, c), bounds_of(gap, 4), INK, 0.55)
        c.shape(stroke(shape + shape[:1], 9, c), bounds_of(shape, 9), INK)
    elif name in SPEECH_MOUTHS:
        draw_speech_mouth(c, SPEECH_MOUTHS[name])
    else:  # pragma: no cover - MOUTHS and this function are kept in step by a test
        raise ValueError(f"no drawing for mouth {name!r}")
    return c.image()


# -- speech mouths ---------------------------------------------------------

# The mouth layer of each speech shape ("speak-open": "open"), in the order of tables.VISEMES.
SPEECH_MOUTHS: Dict[str, str] = {viseme_mouth(shape): shape for shape in VISEMES}
SPEAK_Y = MOUTH_Y + 20  # the speech mouths' corners: the height of the bored mouth's line


class Opening(NamedTuple):
    """A mouth opening with its corners at (CENTRE_X +- half, y): the upper lip's edge rises
    `up` above them in the middle, the lower lip's sinks `down` below. Roundness 1 makes the
    lower edge a parabola, 0.5 half an ellipse, and between, a jaw-like U."""

    y: float
    half: float
    up: float
    down: float
    roundness: float = 1.0

    def upper(self, x: float) -> float:
        return self.y - self.up * (1 - ((x - CENTRE_X) / self.half) ** 2)

    def lower(self, x: float) -> float:
        return self.y + self.down * max(0.0, 1 - ((x - CENTRE_X) / self.half) ** 2) ** self.roundness

    def outline(self) -> List[Point]:
        left, right = CENTRE_X - self.half, CENTRE_X + self.half
        return curve(self.upper, left, right) + curve(self.lower, right, left)

    def draw(
        self, c: Canvas, teeth: float = 0.0, gaps: Sequence[float] = (), tongue: Sequence[float] = ()
    ) -> None:
        """The dark inside, a tongue (centre x, y and semi-axes), the upper teeth down to
        `teeth` below the corners with lines between them at `gaps` from the centre line,
        and the outline."""
        shape = self.outline()
        c.shape(polygon(shape), bounds_of(shape, 2), MOUTH_INSIDE)
        if tongue:
            tx, ty, rx, ry = tongue
            box = (tx - rx - 2, ty - ry - 2, tx + rx + 2, ty + ry + 2)
            c.shape(ellipse(tx, ty, rx, ry), box, TONGUE, clip=polygon(shape))
        if teeth:
            # The upper edge, then a gentle smile back, never below the lower edge.
            left, right = CENTRE_X - self.half, CENTRE_X + self.half
            band = curve(self.upper, left, right) + curve(
                lambda x: min(self.y + teeth - 4 * ((x - CENTRE_X) / self.half) ** 2, self.lower(x)),
                right,
                left,
            )
            c.shape(polygon(band), bounds_of(band, 2), TEETH)
            for k in gaps:
                gap = [(CENTRE_X + k, self.y - self.up - 4), (CENTRE_X + k * 1.02, self.y + teeth + 4)]
                c.shape(stroke(gap, 3, c), bounds_of(gap, 4), INK, 0.55, clip=polygon(band))
        c.shape(stroke(shape + shape[:1], 9, c), bounds_of(shape, 9), INK)


def draw_speech_mouth(c: Canvas, shape: str) -> None:
    """A mouth shape of speech (a viseme), as tables.VISEMES names them.

    They sit where the emotions' mouths do and are about as wide, so that a crossfade between
    any two looks like one mouth moving. How open each is, the dark inside, goes closed < slight
    < fv, lth < wide, round < open.
    """
    y = SPEAK_Y
    if shape == "closed":  # p, b, m: lips pressed together, creased at the corners
        line = curve(lambda x: y + 3 * (1 - ((x - CENTRE_X) / 88) ** 2), CENTRE_X - 88, CENTRE_X + 88)
        c.shape(stroke(line, 12, c), bounds_of(line, 12), INK)
        for side in (-1, 1):
            crease = [
                (CENTRE_X + side * (93 + 3 * math.cos(a)), y + 1 + 12 * math.sin(a))
                for a in (math.pi * (i / 12 - 0.5) for i in range(13))
            ]
            c.shape(stroke(crease, 6, c), bounds_of(crease, 6), INK)
        lip = curve(lambda x: y + 24 - 3 * (1 - ((x - CENTRE_X) / 34) ** 2), CENTRE_X - 34, CENTRE_X + 34)
        c.shape(stroke(lip, 6, c), bounds_of(lip, 6), INK, 0.45)
    elif shape == "slight":  # lips a little apart
        Opening(y, 92, 7, 14).draw(c)
    elif shape == "fv":  # f, v: the upper teeth on the lower lip
        Opening(y - 4, 96, 12, 36, 0.7).draw(c, teeth=12, gaps=(-56, -18, 18, 56))
    elif shape == "lth":  # l, th: the tongue's tip up at the upper teeth
        Opening(y - 4, 102, 14, 44, 0.8).draw(
            c, teeth=3, gaps=(-48, -16, 16, 48), tongue=(CENTRE_X, y + 30, 42, 30)
        )
    elif shape == "wide":  # e, i: lips spread, the teeth showing
        Opening(y - 6, 124, 12, 46, 0.7).draw(c, teeth=12, gaps=(-72, -24, 24, 72))
    elif shape == "round":  # o, u, w: a small rounded O
        cx, cy, rx, ry = CENTRE_X, y + 6, 44, 50
        c.shape(ellipse(cx, cy, rx, ry), (cx - rx - 2, cy - ry - 2, cx + rx + 2, cy + ry + 2), MOUTH_INSIDE)
        tongue = (cx - 30, cy + 20, cx + 30, cy + ry + 2)
        c.shape(ellipse(cx, cy + 42, 28, 16), tongue, TONGUE, clip=ellipse(cx, cy, rx, ry))
        c.shape(ring(cx, cy, rx, ry, 9, c), (cx - rx - 9, cy - ry - 9, cx + rx + 9, cy + ry + 9), INK)
    elif shape == "open":  # a as in "father": the jaw dropped
        Opening(y - 14, 110, 10, 100, 0.6).draw(
            c, teeth=8, gaps=(-64, -22, 22, 64), tongue=(CENTRE_X, y + 78, 60, 28)
        )
    else:  # pragma: no cover - VISEMES and this function are kept in step by a test
        raise ValueError(f"no drawing for speech mouth {shape!r}")


# Each brow as (inner end, middle, outer end) heights; inner is toward the
# centre line. Per side: (viewer's left brow, viewer's right brow).
BROW_SHAPES: Dict[str, Tuple[Tuple[float, float, float], Tuple[float, float, float]]] = {
    "normal": ((92, 72, 88), (92, 72, 88)),
    "raised": ((68, 34, 66), (68, 34, 66)),
    "skeptical": ((92, 74, 90), (62, 30, 56)),
    "angry": ((124, 96, 70), (124, 96, 70)),
    "worried": ((60, 66, 100), (60, 66, 100)),
}


def draw_brows(size: Tuple[int, int], name: str) -> Image.Image:
    c = Canvas(size)
    for side, heights in zip((-1, 1), BROW_SHAPES[name]):
        inner, middle, outer = heights
        cx = CENTRE_X + side * EYE_DX
        x_inner, x_outer = cx - side * 100, cx + side * 100

        def y_at(t: float, inner: float = inner, middle: float = middle, outer: float = outer) -> float:
            return (1 - t) ** 2 * inner + 2 * (1 - t) * t * (2 * middle - (inner + outer) / 2) + t**2 * outer

        line = [(x_inner + (x_outer - x_inner) * i / 40, y_at(i / 40)) for i in range(41)]
        c.shape(stroke(line, 15, c), bounds_of(line, 15), BROW_INK)
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
