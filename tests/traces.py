"""Synthetic head-sonar traces, and the original follower written from the spec, for comparison."""

from __future__ import annotations

import math
import random
from collections import deque
from typing import List, NamedTuple, Optional, Tuple

SENSOR_AT = {0: 0.0, 1: -1.0, 2: -2.0, 3: -3.0, 9: 3.0, 10: 2.0, 11: 1.0}
RATE = 20.0  # readings a second


class Reading(NamedTuple):
    t: float
    ids: List[float]
    distances: List[float]
    truth: Optional[float]  # the eye x that looks at the person


def trace(
    path, seconds: float, seed: int, dropouts: float = 0.0, second_object: bool = False
) -> List[Reading]:
    """A person at path(t) on the sonar line [-3, 3], about a metre away, seen by noisy sensors."""
    rng = random.Random(seed)
    out = []
    for k in range(int(seconds * RATE)):
        t = k / RATE
        where = path(t)
        ids, distances = [], []
        if rng.random() >= dropouts:
            for sensor, at in SENSOR_AT.items():
                off = abs(at - where)
                if off <= 1.0 and rng.random() < 0.9:
                    ids.append(float(sensor))
                    distances.append(1.0 + 0.3 * off + rng.gauss(0, 0.06))
            if rng.random() < 0.15:  # a stray echo
                ids.append(float(rng.choice(list(SENSOR_AT))))
                distances.append(rng.uniform(0.9, 1.3))
            if second_object:  # something further off, always there
                ids.append(9.0)
                distances.append(1.8 + rng.gauss(0, 0.03))
            # Sensors behind the robot sometimes report too.
            if rng.random() < 0.3:
                ids.append(float(rng.choice([4, 5, 6, 7, 8])))
                distances.append(rng.uniform(0.3, 2.0))
        out.append(Reading(t, ids, distances, where * 80 / 3))
    return out


def walk(speed: float, start: float = -3.0):
    """Walking past along the line at `speed` line units a second, then standing at the end."""
    return lambda t: max(-3.0, min(3.0, start + speed * t))


def still(at: float):
    return lambda t: at


class OriginalFollower:
    """The original node's pipeline, as the spec describes it, faults included:
    no process noise, and outliers found but not removed."""

    def __init__(self) -> None:
        self.x: Optional[float] = None
        self.p = 1.0
        self.outputs = deque(maxlen=35)

    def update(self, ids, distances):
        readings = [
            (SENSOR_AT[int(i)], d) for i, d in zip(ids, distances) if int(i) in SENSOR_AT and d <= 2.0
        ]
        if not readings:
            return None
        nearest = min(d for _, d in readings)
        kept = [p for p, d in readings if d <= nearest * 1.3]
        z = sum(kept) / len(kept)
        if self.x is None:
            self.x = z
        else:
            k = self.p / (self.p + 0.50635561)
            self.x += k * (z - self.x)
            self.p *= 1 - k
        self.outputs.append(0.97 * self.x + 0.03 * z)
        return max(-80.0, min(80.0, sum(self.outputs) / len(self.outputs) * 80 / 3))


def run(follower, readings: List[Reading]) -> List[Tuple[float, Optional[float], Optional[float]]]:
    """(t, eye x shown, truth); the eyes hold their last place when a reading sees nobody."""
    shown, out = None, []
    for r in readings:
        value = follower.update(r.ids, r.distances)
        if value is not None:
            shown = value
        out.append((r.t, shown, r.truth))
    return out


def rms_error(results, after: float = 1.0) -> float:
    errors = [(s - truth) ** 2 for t, s, truth in results if t >= after and s is not None]
    return math.sqrt(sum(errors) / len(errors))


def lag(results, max_lag: float = 4.0) -> float:
    """The delay (s) by which the eyes best match the truth."""
    shown = [s for _, s, _ in results]
    truth = [x for _, _, x in results]
    best, best_err = 0.0, math.inf
    for shift in range(int(max_lag * RATE)):
        pairs = [(shown[i], truth[i - shift]) for i in range(shift, len(results)) if shown[i] is not None]
        err = sum((a - b) ** 2 for a, b in pairs) / len(pairs)
        if err < best_err:
            best, best_err = shift / RATE, err
    return best


def jitter(results, after: float = 3.0) -> float:
    """Mean movement of the eyes from one reading to the next, in pixels."""
    values = [s for t, s, _ in results if t >= after and s is not None]
    return sum(abs(b - a) for a, b in zip(values, values[1:])) / max(1, len(values) - 1)


def walks() -> dict:
    """The walking traces the tests check and bench/bench_follow.py reports, by name."""
    return {
        "slow walk": trace(walk(0.5), 14, seed=1),
        "walk (twice as fast)": trace(walk(1.0), 8, seed=2),
        "fast walk (four times)": trace(walk(2.0), 5, seed=3),
        "walk, 30 % dropouts": trace(walk(1.0), 8, seed=4, dropouts=0.3),
        "walk past a further object": trace(walk(1.0), 8, seed=5, second_object=True),
        "walk back": trace(walk(-1.0, start=3.0), 8, seed=7),
    }


def standing(seed: int = 6) -> List[Reading]:
    """A person standing still, slightly to the robot's left."""
    return trace(still(0.5), 20, seed=seed)
