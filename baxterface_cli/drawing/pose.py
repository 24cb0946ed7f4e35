"""Where the moving layers of a face are, in whole screen pixels: its pose.

The eyes (clamped to their ellipse), each lid (its openness, times this eye's share and size),
the drawn face's lower lids, pupil sizes, lid tilts and eye sizes. The renderer compares two
poses to find the rectangles a move changes, and draws the sprites each pose names.
"""

from __future__ import annotations

import math
from typing import NamedTuple, Tuple

from ..core.face_state import FaceState
from ..core.geometry import clamp_to_ellipse
from .artwork import LOWER_TRAVEL
from .compositing import Sprite
from .drawn_parts import EYE_STEPS
from .theme_fitting import ThemeLayers


class Pose(NamedTuple):
    """Where the moving layers are, in whole screen pixels."""

    eye_dx: int
    eye_dy: int
    lid_dy: Tuple[int, ...]  # one per lid sprite of the theme, as layers.lids
    # The drawn face's pupil sizes and lid tilts, per eye left to right (DrawnParts.eye_keys);
    # empty: the theme's own sprites.
    pupils: Tuple[int, ...] = ()
    tilts: Tuple[int, ...] = ()
    lower_dy: Tuple[int, ...] = ()  # the drawn face's lower lids, how far each has sunk
    sizes: Tuple[int, ...] = ()  # the drawn face's eye sizes, in 1/EYE_STEPS


LidPose = Tuple[Tuple[int, ...], ...]  # a pose but where the eyes look: Pose's fields from lid_dy on


def pose(layers: ThemeLayers, state: FaceState) -> Pose:
    """Screen offsets for a state: eyes clamped to their ellipse, each lid to 0..1."""
    return looking(layers, state, lid_pose(layers, state))


def looking(layers: ThemeLayers, state: FaceState, lids: LidPose) -> Pose:
    """`state`'s pose, its lids `lid_pose(layers, state)`: where the eyes look is all a look changes."""
    # A state is plain data anyone can build: a number that is not finite
    # draws as the rest position rather than failing.
    x, y = clamp_to_ellipse(*(v if math.isfinite(v) else 0.0 for v in (state.eye_x, state.eye_y)))
    return Pose(round_half_away(x * layers.scale), round_half_away(y * layers.scale), *lids)


def lid_pose(layers: ThemeLayers, state: FaceState) -> LidPose:
    """The lids of `state`'s pose, and the drawn face's pupil sizes and eye sizes: all but where
    the eyes look, from `state.eyelids` and `state.expression` alone."""
    openness = _unit(state.eyelids)
    shape = state.expression
    share = (1.0, 1.0) if shape is None else (_unit(shape.lid_right), _unit(shape.lid_left))
    middle = layers.size[0] / 2
    s = layers.scale
    drawn = layers.drawn is not None and shape is not None and len(layers.eyes) == 2 == len(layers.lids)
    pupils, tilts, sizes = layers.drawn.eye_keys(shape) if drawn else ((), (), (EYE_STEPS, EYE_STEPS))  # type: ignore[union-attr]
    # The lid left of the screen's middle is the robot's right eye's; a larger eye's travels further.
    upper = []
    for lid in layers.lids:
        i = 0 if lid.x + lid.width / 2 < middle else 1
        upper.append(-round_half_away(layers.lid_travel * openness * share[i] * sizes[i] / EYE_STEPS))
    if not drawn:
        return (tuple(upper),)
    risen = (_unit(shape.lower_lid_right, 0.0), _unit(shape.lower_lid_left, 0.0))
    lower = tuple(round_half_away((1.0 - r) * LOWER_TRAVEL * s * k / EYE_STEPS) for r, k in zip(risen, sizes))
    return (tuple(upper), pupils, tilts, lower, sizes)


def eye_sprite(layers: ThemeLayers, at: Pose, i: int) -> Sprite:
    """Eye i's pupil as `at` draws it: the theme's, or the drawn face's at another size."""
    if not at.pupils or at.pupils[i] == EYE_STEPS:
        return layers.eyes[i]
    return layers.drawn.pupil(i, at.pupils[i])  # type: ignore[union-attr]


def lid_sprite(layers: ThemeLayers, at: Pose, i: int) -> Tuple[Sprite, Tuple[int, int]]:
    """Lid i as `at` draws it, with its band of alike rows: the theme's, or a tilted or sized one."""
    if not at.tilts or (at.tilts[i] == 0 and at.sizes[i] == EYE_STEPS):
        return layers.lids[i], layers.lid_bands[i]
    return layers.drawn.lid(i, at.tilts[i], at.sizes[i])  # type: ignore[union-attr]


def lower_lid_sprite(layers: ThemeLayers, at: Pose, i: int) -> Tuple[Sprite, Tuple[int, int]]:
    """The drawn face's lower lid i, for the eye's size in `at`."""
    return layers.drawn.lower_lid(i, at.sizes[i] if at.sizes else EYE_STEPS)  # type: ignore[union-attr]


def _unit(v: float, otherwise: float = 1.0) -> float:
    return min(1.0, max(0.0, v)) if math.isfinite(v) else otherwise


def round_half_away(v: float) -> int:
    # Half away from zero, so a mirrored face gives mirrored pixels.
    return int(v + 0.5) if v >= 0 else -int(-v + 0.5)
