"""The named parts and emotions as points of the continuous expression (core/expression.py).

Each legacy mouth, brow pair and skin, and each speech mouth, is a handful of numbers, found
from the shapes they were always drawn with: at these numbers the default theme draws them
as before. An emotion's preset is its skin, mouth and brows together; `nearest_parts` goes
back from any expression to the closest named parts, for themes made of pictures: the named
parts are a view of the numbers, never kept beside them.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import Any, Dict, Iterable, NamedTuple, Tuple

from .expression import BROW_FIELDS, MOUTH_FIELDS, NEUTRAL, SKIN_FIELDS, Expression, finite
from .face_constants import BROWS, EMOTIONS, MOUTHS, VISEMES, viseme_mouth


class Parts(NamedTuple):
    """The named parts a theme of pictures shows: a picture each, swapped, not moved."""

    skin: int = 2
    mouth: str = "smile"
    brows: str = "normal"


# Each mouth's numbers; the fields left out are neutral.
MOUTH_PRESETS: Dict[str, Dict[str, float]] = {
    "smile": {"mouth_curve": 1.0, "mouth_width": 130 / 92},
    "sad": {"mouth_curve": -1.0, "mouth_width": 110 / 92},
    "bored": {},
    "confused": {"mouth_skew": 1.0, "mouth_width": 110 / 92},
    "smile-open": {
        "mouth_curve": 1.0,
        "mouth_raise": 0.2,
        "mouth_lift": 0.68,
        "mouth_open": 0.48,
        "mouth_tongue": 1.0,
        "mouth_width": 128 / 92,
    },
    "teeth": {
        "mouth_curve": 1.0,
        "mouth_raise": 0.2,
        "mouth_lift": 0.68,
        "mouth_open": 0.48,
        "mouth_teeth": 0.75,
        "mouth_width": 128 / 92,
    },
    "angry": {
        "mouth_curve": -0.4,
        "mouth_raise": 1.1,
        "mouth_lift": 0.12,
        "mouth_open": 0.06,
        "mouth_gap": 0.95,
        "mouth_clench": 1.0,
        "mouth_width": 112 / 92,
    },
}

# The speech shapes (tables.VISEMES), as points of the same mouth: speech moves between them.
SPEECH_PRESETS: Dict[str, Dict[str, float]] = {
    "closed": {
        "mouth_curve": 3 / 44,
        "mouth_raise": -32 * 3 / 44 / 20,
        "mouth_width": 88 / 92,
        "mouth_press": 1.0,
    },
    "slight": {"mouth_lift": 0.14, "mouth_open": 0.14},
    "fv": {
        "mouth_raise": 0.2,
        "mouth_lift": 0.24,
        "mouth_open": 0.36,
        "mouth_round": 0.6,
        "mouth_teeth": 0.25,
        "mouth_width": 96 / 92,
    },
    "lth": {
        "mouth_raise": 0.2,
        "mouth_lift": 0.28,
        "mouth_open": 0.44,
        "mouth_round": 0.4,
        "mouth_teeth": 0.075,
        "mouth_tongue": 0.7,
        "mouth_width": 102 / 92,
    },
    "wide": {
        "mouth_raise": 0.3,
        "mouth_lift": 0.24,
        "mouth_open": 0.46,
        "mouth_round": 0.6,
        "mouth_teeth": 0.25,
        "mouth_width": 124 / 92,
    },
    "round": {
        "mouth_raise": -0.3,
        "mouth_lift": 1.0,
        "mouth_open": 0.5,
        "mouth_round": 1.0,
        "mouth_tongue": 0.45,
        "mouth_width": 44 / 92,
    },
    "open": {
        "mouth_raise": 0.7,
        "mouth_lift": 0.2,
        "mouth_open": 1.0,
        "mouth_round": 0.8,
        "mouth_teeth": 0.2,
        "mouth_tongue": 1.0,
        "mouth_width": 110 / 92,
    },
}

# Each brow as (inner end, middle, outer end) heights in face pixels from the top of the
# face, for (the robot's right brow, the robot's left): the legacy drawings.
BROW_HEIGHTS: Dict[str, Tuple[Tuple[float, float, float], Tuple[float, float, float]]] = {
    "normal": ((92, 72, 88), (92, 72, 88)),
    "raised": ((68, 34, 66), (68, 34, 66)),
    "skeptical": ((92, 74, 90), (62, 30, 56)),
    "angry": ((124, 96, 70), (124, 96, 70)),
    "worried": ((60, 66, 100), (60, 66, 100)),
}
# The neutral brow: its mean height, half its outer-minus-inner drop, and its arch.
_BROW_MEAN, _BROW_TILT, _BROW_ARCH = 84.0, -2.0, 18.0
BROW_UNITS = (40.0, 30.0, 30.0)  # face pixels per unit of height, angle and curve


def brow_numbers(inner: float, middle: float, outer: float) -> Tuple[float, float, float]:
    """(height, angle, curve) of a brow drawn through these heights."""
    mean = (inner + middle + outer) / 3
    return (
        (_BROW_MEAN - mean) / BROW_UNITS[0],
        ((outer - inner) / 2 - _BROW_TILT) / BROW_UNITS[1],
        ((inner + outer) / 2 - middle - _BROW_ARCH) / BROW_UNITS[2],
    )


def brow_heights(height: float, angle: float, curve: float) -> Tuple[float, float, float]:
    """(inner end, middle, outer end) heights of a brow: the inverse of `brow_numbers`."""
    mean = _BROW_MEAN - height * BROW_UNITS[0]
    tilt = angle * BROW_UNITS[1] + _BROW_TILT
    arch = curve * BROW_UNITS[2] + _BROW_ARCH
    middle = mean - 2 * arch / 3
    return middle + arch - tilt, middle, middle + arch + tilt


def _brows(name: str) -> Dict[str, float]:
    right, left = BROW_HEIGHTS[name]
    out: Dict[str, float] = {}
    for side, heights in (("right", right), ("left", left)):
        out.update(zip(BROW_FIELDS[side], brow_numbers(*heights)))
    return out


BROW_PRESETS: Dict[str, Dict[str, float]] = {name: _brows(name) for name in BROWS}

SLEEPING_SKIN = 5

# The expression's fields that each named part sets, and all an emotion sets (not the lids).
PART_FIELDS: Dict[str, Tuple[str, ...]] = {
    "skin": SKIN_FIELDS,
    "mouth": MOUTH_FIELDS,
    "brows": BROW_FIELDS["left"] + BROW_FIELDS["right"],
}
FACE_FIELDS = PART_FIELDS["skin"] + PART_FIELDS["mouth"] + PART_FIELDS["brows"]


def skin_numbers(index: int) -> Dict[str, float]:
    if index == SLEEPING_SKIN:
        return {"tint": 2.0, "cheeks": 0.0, "sleepy": 1.0}
    return {"tint": float(index), "cheeks": 1.0, "sleepy": 0.0}


def from_parts(parts: Parts, base: Expression = NEUTRAL) -> Expression:
    """`base` showing these named parts (its eyes kept)."""
    mouth = SPEECH_PRESETS.get(parts.mouth[len("speak-") :]) if parts.mouth.startswith("speak-") else None
    mouth = mouth if mouth is not None else MOUTH_PRESETS[parts.mouth]
    neutral_mouth = dict(zip(MOUTH_FIELDS, (getattr(NEUTRAL, f) for f in MOUTH_FIELDS)))
    return base._replace(
        **{**neutral_mouth, **mouth, **BROW_PRESETS[parts.brows], **skin_numbers(parts.skin)}
    )


DEFAULT_FACE = from_parts(Parts())  # the `default` emotion: what intensity 0 and a calm mood show


def blend(weights: Iterable[Tuple[Expression, float]], base: Expression = DEFAULT_FACE) -> Expression:
    """A weighted sum of departures from the default face.

    `happy 0.6 + confused 0.4` is DEFAULT_FACE + 0.6 (happy - DEFAULT_FACE) + 0.4 (confused -
    DEFAULT_FACE), so one emotion at weight w is that emotion at intensity w, and weight 0 the
    default face. One exception: the mouth's curve, where emotions that frown (sad, angry) take
    the base's smile away faster, so that a little of them reads as a little of them.
    """
    total = list(base)
    frowns = left = 1.0  # the share of the base not weighed out, then how much of it is not frowns
    for expression, weight in weights:
        for i, (value, origin) in enumerate(zip(expression, base)):
            total[i] += (value - origin) * weight
        left -= weight
        if expression.mouth_curve < 0.0 < base.mouth_curve:
            frowns -= weight
    if frowns < 1.0 and left > 0.0:
        # A frown takes the base's smile away faster than it adds its own: `angry 0.3` is a milder
        # anger, its mouth flat, not the default's smile bent a third of the way (a smile still).
        curve = _CURVE
        total[curve] -= base.mouth_curve * left * (1.0 - max(0.0, frowns) ** SMILE_FADE)
    return Expression(*total)


_CURVE = Expression._fields.index("mouth_curve")
SMILE_FADE = 5  # the smile a blend keeps shrinks as (1 - the frowns' weight) to this power


def speech_mouth(base: Expression, shape: str) -> Expression:
    """`base` with a speech shape's mouth."""
    neutral_mouth = {f: getattr(NEUTRAL, f) for f in MOUTH_FIELDS}
    return base._replace(**{**neutral_mouth, **SPEECH_PRESETS[shape]})


def emotion_preset(name: str, variant: int = 0) -> Expression:
    """An emotion at full strength, with its `variant`-th (mouth, brows) pair."""
    spec = EMOTIONS[name]
    mouth, brows = spec.variants[variant]
    return from_parts(Parts(spec.skin, mouth, brows))


def expression_of(state: Any) -> Expression:
    """The expression a `FaceState` shows: its numbers (kept for the benchmarks' sake)."""
    return state.expression


_MOUTH = tuple(Expression._fields.index(f) for f in MOUTH_FIELDS)
# A speech shape's mouth, exactly as `speech_mouth` sets it: what speech shows in pictures.
_SPEECH_MOUTHS = {
    tuple(speech_mouth(NEUTRAL, shape)[i] for i in _MOUTH): viseme_mouth(shape) for shape in SPEECH_PRESETS
}


@lru_cache(maxsize=512)  # by the numbers: a theme of pictures asks for every frame's
def nearest_parts(expression: Expression) -> Parts:
    """The named skin, mouth and brows closest to an expression: what a theme of pictures shows.
    A mouth exactly at a speech shape is that shape's picture (`speak-open`)."""
    expression = finite(expression)  # a state anyone may build
    skin = (
        SLEEPING_SKIN if expression.sleepy >= 0.5 else min(4, max(0, int(math.floor(expression.tint + 0.5))))
    )

    def distance(preset: Dict[str, float], fields: Tuple[str, ...]) -> float:
        return sum((getattr(expression, f) - preset.get(f, getattr(NEUTRAL, f))) ** 2 for f in fields)

    mouth = _SPEECH_MOUTHS.get(tuple(expression[i] for i in _MOUTH))
    if mouth is None:
        mouth = min(MOUTHS, key=lambda m: distance(MOUTH_PRESETS[m], MOUTH_FIELDS))
    brow_fields = BROW_FIELDS["left"] + BROW_FIELDS["right"]
    brows = min(BROWS, key=lambda b: distance(BROW_PRESETS[b], brow_fields))
    return Parts(skin, mouth, brows)


assert set(MOUTH_PRESETS) == set(MOUTHS) and set(SPEECH_PRESETS) == set(VISEMES)


# Where each emotion sits on the valence (x) / arousal (y) circle, in degrees from pleasant:
# a mood between two of them is a blend of the two, stronger toward the edge, as Kismet's
# expressions were. The calm, pleasant quarter is the neutral face.
MOOD_CIRCLE: Tuple[Tuple[str, float], ...] = (
    ("happy", 0.0),
    ("wake up", 55.0),
    ("panic", 100.0),
    ("confused", 125.0),
    ("angry", 150.0),
    ("sad", 200.0),
    ("bored", 235.0),
    ("sleep", 270.0),
    ("default", 320.0),
)


def mood_weights(valence: float, arousal: float) -> Tuple[Tuple[str, float], ...]:
    """The emotions a mood blends, with their weights: the two neighbours on MOOD_CIRCLE."""
    strength = min(1.0, math.hypot(valence, arousal))
    if strength == 0.0:
        return ()
    angle = math.degrees(math.atan2(arousal, valence)) % 360.0
    ring = list(MOOD_CIRCLE) + [(MOOD_CIRCLE[0][0], MOOD_CIRCLE[0][1] + 360.0)]
    if angle < ring[0][1]:
        angle += 360.0
    for (a, at_a), (b, at_b) in zip(ring, ring[1:]):
        if at_a <= angle <= at_b:
            u = (angle - at_a) / (at_b - at_a)
            return tuple((name, w) for name, w in ((a, strength * (1 - u)), (b, strength * u)) if w > 0)
    raise AssertionError("MOOD_CIRCLE covers the circle")  # pragma: no cover


def blend_lids(weights: Tuple[Tuple[str, float], ...]) -> float:
    """The lids' openness of a blend: each emotion's lids, weighted, from open."""
    return 1.0 + sum(w * (EMOTIONS[name].eyelids - 1.0) for name, w in weights)
