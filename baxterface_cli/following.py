"""Where the eyes should look to follow a person (head sonar) or a hand (its pose).

Pure functions of their inputs: the face node feeds them ROS messages, the
tests feed them generated traces. Constants are the original node's.
"""

from __future__ import annotations

import math
from collections import deque
from typing import Deque, Iterable, Optional, Tuple

from .geometry import clamp_to_ellipse
from .tables import EYE_RADIUS_X

# Front sonar sensors and where each sits on a line from -3 (the robot's
# right) to 3 (its left): ids 0..3 -> 0, -1, -2, -3; 9, 10, 11 -> 3, 2, 1.
FRONT_SENSORS = {0: 0.0, 1: -1.0, 2: -2.0, 3: -3.0, 9: 3.0, 10: 2.0, 11: 1.0}
LINE_HALF = 3.0


class HumanFollower:
    """Sonar readings in, the eye x to look at out (None when nobody is in front).

    The original pipeline, step by step: front sensors only; readings beyond
    `max_distance` dropped; only those within `gate` (30 %) of the nearest
    kept; outliers beyond `outlier_z` standard deviations removed (the
    original meant to and did not); a Kalman filter on their mean; 97 % of
    its output blended with 3 % of the measurement; the last `window`
    outputs averaged; [-3, 3] scaled to [-80, 80].

    The original filter had no process noise, so its gain fell toward zero
    and it stopped following anyone who walked. Here process noise is
    `process_noise` times how far recent innovations exceed what the
    measurement noise explains: a person standing still lets the gain fall
    as before, a person walking keeps it up (0 gives the original filter).
    `deadband` holds the eyes until the estimate has moved that many pixels,
    so a still person's noise does not make them tremble.
    """

    def __init__(
        self,
        max_distance: float = 2.0,
        gate: float = 0.30,
        outlier_z: float = 1.3,
        measurement_noise: float = 0.50635561,
        initial_variance: float = 1.0,
        process_noise: float = 0.5,
        blend: float = 0.97,
        window: int = 35,
        deadband: float = 1.5,
    ) -> None:
        self.max_distance = max_distance
        self.gate = gate
        self.outlier_z = outlier_z
        self.r = measurement_noise
        self.q = process_noise
        self.blend = blend
        self.deadband = deadband
        self.estimate: Optional[float] = None
        self.variance = initial_variance
        self.surprise = 1.0  # recent innovations over what the noise explains
        self.outputs: Deque[float] = deque(maxlen=window)
        self.eye_x: Optional[float] = None

    def measure(self, sensor_ids: Iterable[float], distances: Iterable[float]) -> Optional[float]:
        """Steps 1 to 4: one position on the [-3, 3] line from one reading, or None."""
        readings = []
        for sensor, distance in zip(sensor_ids, distances):
            if not (math.isfinite(sensor) and math.isfinite(distance)):
                continue
            position = FRONT_SENSORS.get(int(sensor)) if float(sensor).is_integer() else None
            if position is not None and 0.0 < distance <= self.max_distance:
                readings.append((position, distance))
        if not readings:
            return None
        nearest = min(d for _, d in readings)
        kept = [p for p, d in readings if d <= nearest * (1.0 + self.gate)]
        if len(kept) > 2:
            mean = sum(kept) / len(kept)
            spread = math.sqrt(sum((p - mean) ** 2 for p in kept) / len(kept))
            if spread > 0:
                kept = [p for p in kept if abs(p - mean) / spread <= self.outlier_z] or kept
        return sum(kept) / len(kept)

    def update(self, sensor_ids: Iterable[float], distances: Iterable[float]) -> Optional[float]:
        """Take one sonar reading; return the eye x to look at, or None if nobody is in front."""
        z = self.measure(sensor_ids, distances)
        if z is None:
            return None
        if self.estimate is None:
            self.estimate = z
        else:
            # Process noise in proportion to how much the person seems to
            # move: none for someone standing still (innovations the size
            # the measurement noise explains), more the more they walk.
            innovation = z - self.estimate
            self.surprise += 0.1 * (innovation**2 / (self.variance + self.r) - self.surprise)
            self.variance += self.q * max(0.0, self.surprise - 1.0)
            gain = self.variance / (self.variance + self.r)
            self.estimate += gain * (z - self.estimate)
            self.variance *= 1.0 - gain
        self.outputs.append(self.blend * self.estimate + (1.0 - self.blend) * z)
        average = sum(self.outputs) / len(self.outputs)
        target = max(-EYE_RADIUS_X, min(EYE_RADIUS_X, average * EYE_RADIUS_X / LINE_HALF))
        if self.eye_x is None or abs(target - self.eye_x) >= self.deadband:
            self.eye_x = target
        return self.eye_x


# The face's origin, taken to be this far above the robot's base origin (m).
FACE_HEIGHT = 0.75
DEGREES_PER_RADIAN = 57.294
PIXELS_PER_ELEVATION = 76.394  # pi/2 rad up -> 120 pixels up


class ArmFollower:
    """A hand's position (metres, base frame) in, eye (x, y) out.

    Azimuth atan2(y, |x|) in degrees is the eye x (the robot's left is
    positive, as in eye coordinates); elevation atan2(z - c, |x|) scaled so a
    quarter turn is 120 pixels is the eye y, up negative. atan2 has no
    division, so a hand straight above or at face height is no trouble; a
    hand behind the robot (x < 0) is looked at as if mirrored in front, the
    nearest the eyes can get.
    """

    def __init__(self, face_height: float = FACE_HEIGHT) -> None:
        self.face_height = face_height

    def eye_target(self, x: float, y: float, z: float) -> Tuple[float, float]:
        if not all(math.isfinite(v) for v in (x, y, z)):
            raise ValueError(f"hand position must be finite, not ({x}, {y}, {z})")
        reach = abs(x)
        azimuth = math.atan2(y, reach)
        elevation = math.atan2(z - self.face_height, reach)
        return clamp_to_ellipse(azimuth * DEGREES_PER_RADIAN, -PIXELS_PER_ELEVATION * elevation)
