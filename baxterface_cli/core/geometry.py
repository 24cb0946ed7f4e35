"""Eye and head geometry in the original's coordinates (1024x600 pixels)."""

from __future__ import annotations

import math
from typing import Optional, Tuple

from .face_constants import EYE_RADIUS_X, EYE_RADIUS_Y, HEAD_PAN_LIMIT


def clamp_to_ellipse(
    x: float, y: float, rx: float = EYE_RADIUS_X, ry: float = EYE_RADIUS_Y
) -> Tuple[float, float]:
    """Pull (x, y) onto the eye ellipse if it lies outside, keeping its direction.

    Scaling by the ellipse's polar radius over the point's distance is the
    same as dividing by sqrt((x/rx)^2 + (y/ry)^2), which avoids the angle.
    """
    reach = math.hypot(x / rx, y / ry)
    if reach <= 1.0:
        return x, y
    return x / reach, y / reach


def inside_ellipse(x: float, y: float, rx: float = EYE_RADIUS_X, ry: float = EYE_RADIUS_Y) -> bool:
    return math.hypot(x / rx, y / ry) <= 1.0


def clamp_pan(radians: float) -> float:
    """A head pan within the +-1.5 rad the original allowed (Rethink's limit is +-1.3963)."""
    return max(-HEAD_PAN_LIMIT, min(HEAD_PAN_LIMIT, radians))


EYE_SPAN_RAD = 0.25  # the eyes alone cover this much either side of where the head points
RAD_PER_PIXEL = 3.0 / 160.0  # eye x 80 <-> head 1.5 rad


def to_radians(x: float) -> float:
    """An eye x (pixels) as a head angle (radians)."""
    return x * RAD_PER_PIXEL


def to_pixels(rad: float) -> float:
    """A head angle (radians) as an eye x (pixels)."""
    return rad / RAD_PER_PIXEL


def dynamic_look(want: float, head: float) -> Tuple[Optional[float], float]:
    """The dynamic-look rule: (where the head pans, or None to stay; the eye x).

    `want` is the direction to look in and `head` where the head points, both
    radians in the robot's frame. Within the eyes' reach (EYE_SPAN_RAD either
    side of the head) only the eyes move; beyond it the head pans to `want`,
    clamped to its limit, and the eyes take what the head could not (nothing,
    unless the head hit its limit). Used by `dynamic look` and by following.
    """
    pan = None
    if abs(want - head) > EYE_SPAN_RAD:
        pan = clamp_pan(want)
        head = pan
    eye_x = max(-EYE_RADIUS_X, min(EYE_RADIUS_X, to_pixels(want - head)))
    return pan, eye_x
