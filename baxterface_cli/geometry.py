"""Eye and head geometry in the original's coordinates (1024x600 pixels)."""

from __future__ import annotations

import math
from typing import Tuple

from .tables import EYE_RADIUS_X, EYE_RADIUS_Y, HEAD_PAN_LIMIT


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
