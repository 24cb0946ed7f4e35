"""The expression as numbers: each brow, each eye, the mouth and the skin, left and right apart.

An `Expression` is a point in a continuous space, as Vector's and Furhat's faces are: the
default theme draws any point of it, and moving from one point to another moves every number
at once, so a smile bends into a frown through the shapes in between. The ten emotions are
presets in it (`PRESETS`), each at full strength looking as its pictures always have.

Sides are the robot's, as `look left` is: `left` is the robot's left, the viewer's right.
The eyes' `lid_*` are this eye's share of the lids' openness (1 open, 0 shut: a wink); the
lids themselves stay the timeline's own track, as they always were. Units, chosen so that
the presets sit within about -1..1: brow height 40 face pixels, brow angle and curve 30, the
mouth's curve 1 the legacy smile (-1 its frown), width 1 its 92-pixel half width, openness 1
a 100-pixel drop of the lower lip. `core/presets.py` holds the presets' numbers.
"""

from __future__ import annotations

import math
from typing import Dict, Iterable, NamedTuple, Tuple


class Expression(NamedTuple):
    """One face's shape; see the module's docstring for units and sides."""

    brow_left_height: float = 0.0  # up
    brow_left_angle: float = 0.0  # the inner end up (worried); down is angry
    brow_left_curve: float = 0.0  # arched up
    brow_right_height: float = 0.0
    brow_right_angle: float = 0.0
    brow_right_curve: float = 0.0
    lid_left: float = 1.0  # this eye's share of the lids' openness: 0 shut
    lid_right: float = 1.0
    lid_left_angle: float = 0.0  # the lid's edge tilted: the inner corner down (a glare), < 0 the outer
    lid_right_angle: float = 0.0
    pupil_left: float = 1.0  # the pupil's size: 1 as drawn
    pupil_right: float = 1.0
    lower_lid_left: float = 0.0  # the lower lid risen: 0 out of sight, 1 up to just below the pupil
    lower_lid_right: float = 0.0
    eye_left: float = 1.0  # the eye's size, its socket and lids with it: 1 as drawn
    eye_right: float = 1.0
    mouth_curve: float = 0.0  # 1 the smile, -1 the frown, 0 a straight line
    mouth_width: float = 1.0
    mouth_skew: float = 0.0  # a wave that lifts one corner and drops the other (confused)
    mouth_raise: float = 0.0  # the corners up, in 20-pixel units
    mouth_open: float = 0.0  # the lower lip's drop at the middle
    mouth_lift: float = 0.0  # the upper lip's rise at the middle, in 50-pixel units
    mouth_gap: float = 0.0  # lips apart at the corners too (a grimace), in 40-pixel units
    mouth_round: float = 0.0  # 0 a parabola's lower lip, 1 half an ellipse's
    mouth_teeth: float = 0.0  # the upper teeth showing, down to 40 pixels below the corners
    mouth_clench: float = 0.0  # 1 a clenched grimace: all teeth, a line between the rows
    mouth_tongue: float = 0.0
    mouth_press: float = 0.0  # lips pressed together (p, b, m): creased corners, a mark under them
    tint: float = 2.0  # the skin's colour: 0 pale .. 4 red, as `skin 0` .. `skin 4`
    cheeks: float = 1.0  # blush: 1 as drawn, 0 none
    sleepy: float = 0.0  # 1 the sleeping skin, with its "Zzz"

    def mix(self, other: Expression, u: float) -> Expression:
        """`u` of the way from this expression to `other` (0 this, 1 other)."""
        return Expression(*(a + (b - a) * u for a, b in zip(self, other)))

    def as_record(self) -> Dict[str, float]:
        """The numbers, rounded once, for `explain --json`, `~state` and the studio."""
        return {name: round(value, 4) for name, value in zip(self._fields, self)}


NEUTRAL = Expression()  # every number at its origin: brows as `normal`, the mouth a flat line

# The fields that belong to each part, for a control that moves one part alone.
MOUTH_FIELDS: Tuple[str, ...] = tuple(f for f in Expression._fields if f.startswith("mouth_"))
BROW_FIELDS = {
    side: tuple(f for f in Expression._fields if f.startswith(f"brow_{side}_")) for side in ("left", "right")
}
SKIN_FIELDS: Tuple[str, ...] = ("tint", "cheeks", "sleepy")


def with_fields(base: Expression, source: Expression, fields: Iterable[str]) -> Expression:
    """`base` with `fields` taken from `source`."""
    return base._replace(**{f: getattr(source, f) for f in fields})


def finite(expression: Expression) -> Expression:
    """Anything not a finite number drawn as the neutral face's value: a state anyone may build."""
    return Expression(*(v if math.isfinite(v) else n for v, n in zip(expression, NEUTRAL)))


class Control(NamedTuple):
    """A number a script may set on its own: `mouth curve 0.5`, `brows left angle -0.6`."""

    sides: Dict[str, Tuple[str, ...]]  # the Expression fields it sets: "" both sides, or one side
    low: float
    high: float
    meaning: str


def _sides(part: str, name: str) -> Dict[str, Tuple[str, ...]]:
    left, right = f"{part}_left_{name}", f"{part}_right_{name}"
    return {"": (left, right), "left": (left,), "right": (right,)}


def _either(part: str) -> Dict[str, Tuple[str, ...]]:
    left, right = f"{part}_left", f"{part}_right"
    return {"": (left, right), "left": (left,), "right": (right,)}


def _one(field: str) -> Dict[str, Tuple[str, ...]]:
    return {"": (field,)}


# (part, control) -> the fields it sets, its range and meaning. Tables are data: the parser,
# `explain` and the docs read this one. `eyelids left 0.3` is the control with no name.
CONTROLS: Dict[Tuple[str, str], Control] = {
    ("brows", "height"): Control(_sides("brow", "height"), -1.5, 1.5, "up; 1 is 40 face pixels"),
    ("brows", "angle"): Control(
        _sides("brow", "angle"), -1.5, 1.5, "the inner end up (worried), down (angry)"
    ),
    ("brows", "curve"): Control(_sides("brow", "curve"), -1.5, 1.5, "arched up"),
    ("mouth", "curve"): Control(_one("mouth_curve"), -1.5, 1.5, "1 the smile, -1 the frown"),
    ("mouth", "open"): Control(_one("mouth_open"), 0.0, 1.2, "the lower lip down; 1 is 100 face pixels"),
    ("mouth", "width"): Control(_one("mouth_width"), 0.3, 1.8, "1 is the bored mouth's width"),
    ("mouth", "skew"): Control(_one("mouth_skew"), -1.5, 1.5, "one corner up, the other down (confused)"),
    ("mouth", "raise"): Control(_one("mouth_raise"), -1.5, 1.5, "the corners up; 1 is 20 face pixels"),
    ("mouth", "lift"): Control(_one("mouth_lift"), -1.0, 1.2, "the upper lip up; 1 is 50 face pixels"),
    ("mouth", "gap"): Control(_one("mouth_gap"), 0.0, 1.2, "lips apart at the corners too: a grimace"),
    ("mouth", "round"): Control(_one("mouth_round"), 0.0, 1.0, "the lower lip from a parabola to an ellipse"),
    ("mouth", "teeth"): Control(_one("mouth_teeth"), 0.0, 1.0, "the upper teeth showing"),
    ("mouth", "clench"): Control(_one("mouth_clench"), 0.0, 1.0, "teeth clenched, a line between the rows"),
    ("mouth", "tongue"): Control(_one("mouth_tongue"), 0.0, 1.2, "the tongue's size"),
    ("mouth", "press"): Control(_one("mouth_press"), 0.0, 1.0, "lips pressed together, as for p, b, m"),
    ("skin", "tint"): Control(_one("tint"), 0.0, 4.0, "0 pale .. 4 red, as skin 0 .. skin 4"),
    ("skin", "cheeks"): Control(_one("cheeks"), 0.0, 3.0, "blush; 1 as drawn"),
    ("skin", "sleepy"): Control(_one("sleepy"), 0.0, 1.0, "toward the sleeping skin and its Zzz"),
    ("eyelids", ""): Control({"left": ("lid_left",), "right": ("lid_right",)}, 0.0, 1.0, "one eye's share"),
    ("eyelids", "lower"): Control(
        _either("lower_lid"),
        0.0,
        1.0,
        "the lower lids risen, as in a smile that reaches the eyes; 1 just below the pupil",
    ),
    ("eyelids", "angle"): Control(
        _sides("lid", "angle"),
        -1.0,
        1.0,
        "the edge tilted: the inner corner down (a glare), the outer down (sorrow)",
    ),
    ("eyes", ""): Control(_either("eye"), 0.8, 1.2, "the eyes' size, sockets and lids with them; 1 as drawn"),
    ("pupils", ""): Control(
        _either("pupil"),
        0.5,
        1.6,
        "the pupils' size; 1 as drawn",
    ),
}
