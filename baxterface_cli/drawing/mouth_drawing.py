"""The mouth drawn from the expression's numbers: one shape family for every mouth.

Across the mouth, u runs from -1 (the viewer's left corner) to 1, and x = CENTRE_X + u * half.
A centre line bends (curve) and waves (skew); the upper lip's edge rises above it and the lower
lip's sinks below it toward the middle (lift, open), apart at the corners by the gap. Every
legacy mouth and speech shape is one point of this family (core/presets.py), so moving the
numbers morphs one into another through the shapes in between.
"""

from __future__ import annotations

import math
from typing import List, NamedTuple, Tuple

from ..core.expression import Expression
from .vector_shapes import Canvas, Point, bounds_of, ellipse, polygon, stroke

CENTRE_X = 512.0
MOUTH_Y = 470.0
INK = (62, 36, 38)
MOUTH_INSIDE = (128, 32, 44)
TONGUE = (232, 110, 120)
TEETH = (250, 250, 244)


class MouthGeometry(NamedTuple):
    """The mouth in face pixels: what the numbers mean on the screen."""

    corners: float  # the corners' height
    half: float  # half the width
    bend: float  # the centre line's middle, below the corners (up if negative)
    wave: float  # the skew's amplitude
    lift: float  # the upper lip's edge above the centre line, at the middle
    drop: float  # the lower lip's edge below it, at the middle
    gap: float  # the lips apart at the corners
    power: float  # the lips' profile: 1 parabolas, 0.5 half ellipses
    teeth: float  # the upper teeth's lower edge, below the corners (0: no teeth)
    clench: float
    tongue: float
    press: float

    @property
    def opening(self) -> float:
        return max(0.0, self.gap + self.lift + self.drop)

    def line(self, u: float) -> float:
        return self.corners + self.bend * (1 - u * u) + self.wave * math.sin(1.43 * math.pi * u)

    def upper(self, u: float) -> float:
        return self.line(u) - self.lift * max(0.0, 1 - u * u) ** self.power

    def lower(self, u: float) -> float:
        # Never above the upper lip: a mouth closes, it does not turn inside out.
        depth = self.gap + self.drop * max(0.0, 1 - u * u) ** self.power
        return self.line(u) + max(depth, -self.lift * max(0.0, 1 - u * u) ** self.power)


def geometry(e: Expression) -> MouthGeometry:
    c = e.mouth_curve
    corners = MOUTH_Y + 20 - (32 * c if c > 0 else 20 * c) - 20 * e.mouth_raise
    return MouthGeometry(
        corners=corners,
        half=92 * max(0.1, e.mouth_width),
        bend=(44 if c > 0 else 40) * c,
        wave=13 * e.mouth_skew,
        lift=50 * e.mouth_lift,
        drop=100 * max(0.0, e.mouth_open),
        gap=40 * max(0.0, e.mouth_gap),
        power=1 - 0.5 * min(1.0, max(0.0, e.mouth_round)),
        teeth=40 * max(0.0, e.mouth_teeth),
        clench=min(1.0, max(0.0, e.mouth_clench)),
        tongue=max(0.0, e.mouth_tongue),
        press=min(1.0, max(0.0, e.mouth_press)),
    )


def _along(g: MouthGeometry, f, forward: bool = True, half: float = 0.0, steps: int = 48) -> List[Point]:
    us = [-1 + 2 * i / steps for i in range(steps + 1)]
    if not forward:
        us.reverse()
    half = half or g.half
    return [(CENTRE_X + u * half, f(u)) for u in us]


def mouth_window(e: Expression) -> Tuple[float, float, float, float]:
    """A box, in face units, that holds everything `draw_mouth_numbers` draws for `e`."""
    g = geometry(e)
    ys = [f(u) for f in (g.upper, g.lower) for u in (-1 + i / 12 for i in range(25))]
    margin = 16.0  # more than half the widest pen, and the antialiasing
    low = max(ys) + (30 if g.press > 0 else 0)  # the pressed lips' mark sits below
    side = g.half + margin + (12 if g.press > 0 else 0)  # and their creases outside the corners
    return (CENTRE_X - side, min(ys) - margin, CENTRE_X + side, low + margin)


def _mix(a, b, u: float):
    return tuple(int(round(x + (y - x) * u)) for x, y in zip(a, b))


def draw_mouth_numbers(c: Canvas, e: Expression) -> None:
    """The mouth of expression `e` on canvas `c`."""
    g = geometry(e)
    upper = _along(g, g.upper)
    # Lips apart at the corners draw in toward the bottom, as clenched teeth do.
    lower_half = g.half * (1 - 0.075 * min(1.0, g.gap / 40))
    outline = upper + _along(g, g.lower, forward=False, half=lower_half)
    # A line mouth is a 12-pixel stroke, an open one a 9-pixel outline round its inside.
    pen = 9 + 3 * max(0.0, 1 - g.opening / 8)
    if g.opening > 0.5:
        inside = polygon(outline)
        c.shape(inside, bounds_of(outline, 2), _mix(MOUTH_INSIDE, TEETH, g.clench))
        if g.tongue > 0:
            rx, ry = 62 * g.tongue, 24 * g.tongue
            tx, ty = CENTRE_X, g.lower(0) - 0.75 * ry
            box = (tx - rx - 2, ty - ry - 2, tx + rx + 2, ty + ry + 2)
            c.shape(ellipse(tx, ty, rx, ry), box, TONGUE, clip=inside)
        if g.teeth > 0:
            band = upper + _along(
                g,
                lambda u: max(g.upper(u), min(g.corners + g.teeth * (1 + 0.4 * (1 - u * u)), g.lower(u))),
                forward=False,
            )
            c.shape(polygon(band), bounds_of(band, 2), TEETH, clip=inside)
            _gaps(c, g, g.upper(0) + 2, g.corners + g.teeth * 1.27, polygon(band))
        if g.clench > 0:
            middle = _along(g, lambda u: (g.upper(u) + g.lower(u)) / 2)
            c.shape(stroke(middle, 3, c), bounds_of(middle, 4), INK, 0.7 * g.clench, clip=inside)
            _gaps(c, g, g.upper(0) + 4, g.lower(0) + 4, inside, g.clench, lower_half)
    c.shape(stroke(outline + outline[:1], pen, c), bounds_of(outline, pen), INK)
    if g.press > 0:
        _pressed(c, g)


def _pressed(c: Canvas, g: MouthGeometry) -> None:
    """Lips pressed together: a crease round each corner and the lower lip's mark below."""
    for side in (-1, 1):
        y = g.line(side)
        crease = [
            (CENTRE_X + side * (g.half + 5 + 3 * math.cos(a)), y + 1 + 12 * math.sin(a))
            for a in (math.pi * (i / 12 - 0.5) for i in range(13))
        ]
        c.shape(stroke(crease, 6, c), bounds_of(crease, 6), INK, g.press)
    y = g.lower(0) + 24
    lip = [(CENTRE_X + x, y - 3 * (1 - (x / 34) ** 2)) for x in range(-34, 35, 4)]
    c.shape(stroke(lip, 6, c), bounds_of(lip, 6), INK, 0.45 * g.press)


def _gaps(
    c: Canvas, g: MouthGeometry, top: float, bottom: float, clip, opacity: float = 1.0, half: float = 0.0
) -> None:
    """The lines between the teeth, at the same fractions of the width in every mouth."""
    half = half or g.half
    for k in (-0.57, -0.19, 0.19, 0.57):
        x = CENTRE_X + k * half
        gap = [(x, top), (x + k * half * 0.02, bottom)]
        c.shape(stroke(gap, 3, c), bounds_of(gap, 4), INK, 0.55 * opacity, clip=clip)
