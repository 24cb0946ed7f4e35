"""Where the eyes should look to follow a person (head sonar) or a hand (its pose).

Pure functions of their inputs: the face node feeds them ROS messages, the
tests feed them generated traces. The sonar follower's constants are a small
frozen table, `SonarSettings`: baxterface's by default, the original node's
in `ORIGINAL_SONAR`.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, replace
from typing import Any, Deque, Iterable, List, Optional, Tuple

from ..core.face_constants import EYE_RADIUS_X
from ..core.geometry import clamp_to_ellipse

# Front sonar sensors and where each sits on a line from -3 (the robot's
# right) to 3 (its left): ids 0..3 -> 0, -1, -2, -3; 9, 10, 11 -> 3, 2, 1.
# One unit on this line, a "spacing", is the 30 degrees between two sensors.
FRONT_SENSORS = {0: 0.0, 1: -1.0, 2: -2.0, 3: -3.0, 9: 3.0, 10: 2.0, 11: 1.0}
LINE_HALF = 3.0

Sighting = Tuple[float, float]  # (position on the line, distance in metres)


@dataclass(frozen=True)
class SonarSettings:
    """The constants of `HumanFollower`: positions in spacings on the sensor
    line, variances in spacings squared, times in seconds, distances in metres.

    The defaults are baxterface's, measured on the faulty traces of
    tests/traces.py (bench/bench_follow.py); `ORIGINAL_SONAR` is the original
    node's. A stage whose setting is None is left out.
    """

    rate: float = 20.0  # readings a second: the follower's only clock
    max_distance: float = 2.0  # further readings are ignored
    near_share: float = 0.30  # a sighting: the nearest reading and those within 30 % of it
    position_gate: Optional[float] = 2.0  # the person's readings lie this near the track (None: all do)
    range_gate: float = 0.4  # ... and this near the range they are tracked at
    range_share: float = 0.2  # of each sighting's distance taken into that range
    reacquire_after: Optional[float] = 0.5  # with nothing in the gates this long, start afresh
    first_sightings: int = 3  # sightings in that time a track starts from, at their median
    measurement_noise: float = 0.15  # variance of a sighting's position
    initial_variance: float = 0.15  # of the position a track starts at
    still_memory: Optional[float] = 20.0  # a standing person is the mean of at most this long
    start_walking: Optional[float] = 1.0  # mean innovation (standard deviations) that starts a walk
    drift_share: float = 0.1  # of each innovation, or walking speed, taken into its running mean
    walk_noise: float = 0.3  # a walker's random acceleration, spacings^2/s^3
    walk_speed: float = 1.0  # spacings/s: the spread of the speed when a walk starts
    stop_speed: float = 0.15  # spacings/s: a walker whose mean speed stays under this...
    stop_after: float = 1.0  # ... this long is standing
    raw_share: float = 0.0  # of the sighting's own position blended into the estimate
    window: int = 1  # outputs averaged
    deadband: float = 3.0  # eye pixels a standing person's estimate must pull before the eyes move


# The original node's pipeline, as its spec describes it: every reading's
# sighting, a Kalman filter with no process noise, 97 % of it blended with
# 3 % of the sighting, the last 35 outputs averaged.
ORIGINAL_SONAR = SonarSettings(
    position_gate=None,
    reacquire_after=None,
    first_sightings=1,
    measurement_noise=0.50635561,
    initial_variance=1.0,
    still_memory=None,
    start_walking=None,
    raw_share=0.03,
    window=35,
    deadband=0.0,
)


class HumanFollower:
    """Sonar readings in, the eye x to look at out (None when nobody is in front).

    One `update` a reading; the readings are the clock, `rate` a second.
    Each reading, in turn (the names are `SonarSettings`'):

    1. Front sensors only (ids 0-3 and 9-11, on the line from -3 to 3), within
       `max_distance`; none left: nobody is in front, None.
    2. The person's sighting: of the readings within `position_gate` of where
       they are tracked and `range_gate` of their range, the nearest and those
       within `near_share` of it; their mean position is the measurement. So a
       spurious echo elsewhere, however near, or a further object is not taken
       for them. With nothing in the gates for `reacquire_after`, the track is
       dropped and started afresh, as at first, at the median of the sightings
       of all the readings meanwhile (if `first_sightings` of them; else nobody).
    3. A Kalman filter in two modes. Standing: the position alone, without
       process noise, so a still person is the mean of their sightings (over
       at most `still_memory`). When the running mean of the innovations, in
       standard deviations, passes `start_walking`, they walk: a
       constant-velocity filter with `walk_noise`, following a walker with
       little lag, until its running mean speed has stayed under `stop_speed`
       for `stop_after`.
    4. [-3, 3] scaled to [-80, 80] eye pixels. While the person stands, the
       eyes move only when the estimate pulls them more than `deadband` pixels,
       and then stay that far behind it, so a still person's noise does not
       make them tremble; while they walk, the eyes follow the estimate.

    `HumanFollower.original()` is the original node's pipeline, number for
    number (`ORIGINAL_SONAR`: no gates, standing only, its blend and its
    35-reading average); `HumanFollower(deadband=0)` changes one setting.
    Unlike the original node, either skips what is not a reading (non-finite
    values, ids that are not whole numbers, distances not above 0), and has
    no outlier step: the original's found outliers and removed none, so
    leaving it out changes no number.
    """

    def __init__(self, settings: Optional[SonarSettings] = None, **changes: Any) -> None:
        settings = settings if settings is not None else SonarSettings()
        self.settings = replace(settings, **changes) if changes else settings
        self.dt = 1.0 / self.settings.rate
        self.x: Optional[float] = None  # where the person is on the line; None: nobody tracked
        self.v = 0.0  # spacings/s, 0 while they stand
        self.p = [[0.0, 0.0], [0.0, 0.0]]  # covariance of (x, v)
        self.range = 0.0  # metres
        self.walking = False
        self.drift = 0.0  # running mean of the innovations, in standard deviations
        self.speed = 0.0  # running mean of v while walking
        self.slow = 0  # readings that mean speed has been under stop_speed
        self.misses = 0  # readings since the last one in the gates
        held = round((self.settings.reacquire_after or 0.0) * self.settings.rate)
        self.fresh: Deque[Optional[Sighting]] = deque(maxlen=max(self.settings.first_sightings, held))
        self.outputs: Deque[float] = deque(maxlen=self.settings.window)
        self.eye_x: Optional[float] = None  # where the eyes look; None: nobody

    @classmethod
    def original(cls) -> HumanFollower:
        """The original node's pipeline, number for number."""
        return cls(ORIGINAL_SONAR)

    def readings(self, sensor_ids: Iterable[float], distances: Iterable[float]) -> List[Sighting]:
        """(position on the line, distance) of each front reading near enough to count."""
        out = []
        for sensor, distance in zip(sensor_ids, distances):
            if not (math.isfinite(sensor) and math.isfinite(distance)):
                continue
            position = FRONT_SENSORS.get(int(sensor)) if float(sensor).is_integer() else None
            if position is not None and 0.0 < distance <= self.settings.max_distance:
                out.append((position, distance))
        return out

    def nearest(self, readings: List[Sighting]) -> Sighting:
        """The original's sighting: the mean position of the readings within
        `near_share` of the nearest, and that nearest distance."""
        near = min(d for _, d in readings)
        kept = [p for p, d in readings if d <= near * (1.0 + self.settings.near_share)]
        return sum(kept) / len(kept), near

    def update(self, sensor_ids: Iterable[float], distances: Iterable[float]) -> Optional[float]:
        """Take one sonar reading; return the eye x to look at, or None if nobody is in front."""
        seen = self.readings(sensor_ids, distances)
        if self.x is not None:
            self._predict()
        sighting = self._claim(seen) if seen and self.x is not None else None
        if sighting is not None:
            self._correct(*sighting)
        else:
            self._miss(self.nearest(seen) if seen else None)
        if not seen or self.x is None:
            return None
        return self._look(sighting[0] if sighting is not None else self.x)

    def _claim(self, seen: List[Sighting]) -> Optional[Sighting]:
        """The person's readings in this one: their mean position and nearest distance, or None."""
        s = self.settings
        if s.position_gate is None:
            return self.nearest(seen)
        mine = [
            (p, d)
            for p, d in seen
            if abs(p - self.x) <= s.position_gate and abs(d - self.range) <= s.range_gate
        ]
        return self.nearest(mine) if mine else None

    def _miss(self, fresh: Optional[Sighting]) -> None:
        """A reading with nothing in the gates. With nobody tracked, or after `reacquire_after`
        seconds of these, take up the median of the fresh sightings meanwhile, if there are
        `first_sightings` of them; with fewer, nobody is there."""
        s = self.settings
        self.fresh.append(fresh)
        self.misses += 1
        if self.x is not None and (s.reacquire_after is None or self.misses < s.reacquire_after * s.rate):
            return
        sightings = sorted(f for f in self.fresh if f is not None)
        if len(sightings) < s.first_sightings:
            self.x = self.eye_x = None
            return
        self.x, self.range = sightings[len(sightings) // 2]
        self.v, self.walking, self.drift, self.slow, self.misses = 0.0, False, 0.0, 0, 0
        self.p = [[s.initial_variance, 0.0], [0.0, 0.0]]
        self.fresh.clear()
        self.outputs.clear()

    def _predict(self) -> None:
        s = self.settings
        (p00, p01), (_, p11) = self.p
        if self.walking:
            dt, q = self.dt, s.walk_noise
            self.x += self.v * dt
            self.p = [
                [p00 + 2 * dt * p01 + dt * dt * p11 + q * dt**3 / 3, p01 + dt * p11 + q * dt * dt / 2],
                [p01 + dt * p11 + q * dt * dt / 2, p11 + q * dt],
            ]
            if abs(self.x) > LINE_HALF:  # nobody is seen beyond the end sensors
                self.x = math.copysign(LINE_HALF, self.x)
                self.v = 0.0 if self.x * self.v > 0 else self.v
        elif s.still_memory is not None:  # the mean of at most still_memory seconds
            self.p[0][0] = max(p00, s.measurement_noise / (s.still_memory * s.rate))

    def _correct(self, z: float, near: float) -> None:
        s = self.settings
        (p00, p01), (_, p11) = self.p
        innovation = z - self.x
        variance = p00 + s.measurement_noise  # the innovation's
        k0, k1 = p00 / variance, p01 / variance
        self.x += k0 * innovation
        self.v += k1 * innovation
        self.p = [[(1 - k0) * p00, (1 - k0) * p01], [(1 - k0) * p01, p11 - k1 * p01]]
        self.range += s.range_share * (near - self.range)
        self.misses = 0
        self.fresh.clear()
        if s.start_walking is None:
            return
        self.drift += s.drift_share * (innovation / math.sqrt(variance) - self.drift)
        if not self.walking and abs(self.drift) > s.start_walking:
            self.walking, self.speed = True, 0.0
            self.p[1][1] = s.walk_speed**2
        elif self.walking:
            self.speed += s.drift_share * (self.v - self.speed)
            self.slow = self.slow + 1 if abs(self.speed) < s.stop_speed else 0
            if self.slow >= s.stop_after * s.rate:
                self.walking, self.v, self.drift, self.slow = False, 0.0, 0.0, 0
                self.p = [[self.p[0][0], 0.0], [0.0, 0.0]]

    def _look(self, raw: float) -> float:
        s = self.settings
        self.outputs.append((1.0 - s.raw_share) * self.x + s.raw_share * raw)
        average = sum(self.outputs) / len(self.outputs)
        target = max(-EYE_RADIUS_X, min(EYE_RADIUS_X, average * EYE_RADIUS_X / LINE_HALF))
        if self.eye_x is None or self.walking:
            self.eye_x = target
        else:  # held until the target pulls further than the deadband, then dragged behind it
            self.eye_x = min(max(self.eye_x, target - s.deadband), target + s.deadband)
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
