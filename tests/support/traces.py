"""Synthetic head-sonar traces, and the original follower written from the spec, for comparison.

Two generators: `trace`, the earlier clean one (noisy sensors, stray echoes
near the person's range, sensors behind the robot), and `faulty_trace`, with
real sonar's faults (spurious echoes at any range, each reading of the person
dropping out on its own, a further object on the other side). `walks()` and
`faulty_traces()` are the named sets the tests and bench/bench_follow.py use.
"""

from __future__ import annotations

import math
import random
from collections import deque
from typing import Dict, List, NamedTuple, Optional, Tuple

SENSOR_AT = {0: 0.0, 1: -1.0, 2: -2.0, 3: -3.0, 9: 3.0, 10: 2.0, 11: 1.0}
RATE = 20.0  # readings a second


class Reading(NamedTuple):
    t: float
    ids: List[float]
    distances: List[float]
    truth: Optional[float]  # the eye x that looks at the person
    spurious: int = 0  # how many of the distances are spurious echoes


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


def lag(results, max_lag: float = 10.0) -> float:
    """The delay (s) by which the eyes best match the truth."""
    shown = [s for _, s, _ in results]
    truth = [x for _, _, x in results]
    best, best_err = 0.0, math.inf
    for shift in range(min(int(max_lag * RATE), len(results) // 2)):
        pairs = [(shown[i], truth[i - shift]) for i in range(shift, len(results)) if shown[i] is not None]
        err = sum((a - b) ** 2 for a, b in pairs) / len(pairs)
        if err < best_err:
            best, best_err = shift / RATE, err
    return best


def walks() -> dict:
    """The earlier, clean walking traces the tests check, by name."""
    return {
        "slow walk": trace(walk(0.5), 14, seed=1),
        "walk (twice as fast)": trace(walk(1.0), 8, seed=2),
        "fast walk (four times)": trace(walk(2.0), 5, seed=3),
        "walk, 30 % dropouts": trace(walk(1.0), 8, seed=4, dropouts=0.3),
        "walk past a further object": trace(walk(1.0), 8, seed=5, second_object=True),
        "walk back": trace(walk(-1.0, start=3.0), 8, seed=7),
    }


# -- faulty traces: real sonar's faults ---------------------------------------

SPURIOUS = 0.04  # of all reported distances: a random sensor, anything from 0.3 to 3.5 m
DROPOUT = 0.15  # of the person's in-cone readings, each missing on its own
OBJECT_AT = 2.5  # a still object, further off than the person, on the other side


def faulty_trace(
    path,
    seconds: float,
    seed: int,
    second_object: bool = False,
    person_range: float = 1.0,
    object_range: float = 1.7,
    object_at: Optional[float] = None,
) -> List[Reading]:
    """A person at path(t) about `person_range` metres away, seen as real sonar sees them.

    Every front sensor within one spacing of the person reports, unless it
    drops out (DROPOUT), their range plus 0.3 m a spacing off its axis and
    6 cm of noise; behind the robot a sensor answers in 30 % of readings. On
    top, SPURIOUS of everything reported is spurious: a random sensor (0-11)
    at a range anywhere from 0.3 to 3.5 m, so often nearer than the person.
    With `second_object`, a still object stands `object_range` metres off at
    `object_at` (by default OBJECT_AT on the side away from where the person
    starts), seen the same way.
    """
    rng = random.Random(seed)
    if object_at is None:
        object_at = -OBJECT_AT if path(0.0) > 0 else OBJECT_AT
    out = []
    for k in range(int(seconds * RATE)):
        t = k / RATE
        where = path(t)
        seen: List[Tuple[float, float]] = []
        things = [(where, person_range, 0.06)]
        if second_object:
            things.append((object_at, object_range, 0.03))
        for at_x, distance, noise in things:
            for sensor, at in SENSOR_AT.items():
                off = abs(at - at_x)
                if off <= 1.0 and rng.random() >= DROPOUT:
                    seen.append((float(sensor), distance + 0.3 * off + rng.gauss(0, noise)))
        if rng.random() < 0.3:  # sensors behind the robot answer too
            seen.append((float(rng.choice([4, 5, 6, 7, 8])), rng.uniform(0.3, 2.0)))
        # Spurious echoes: SPURIOUS of all the distances reported, on average.
        spurious = sum(rng.random() < SPURIOUS / (1.0 - SPURIOUS) for _ in seen)
        for _ in range(spurious):
            seen.insert(rng.randrange(len(seen) + 1), (float(rng.randrange(12)), rng.uniform(0.3, 3.5)))
        ids = [sensor for sensor, _ in seen]
        distances = [d for _, d in seen]
        out.append(Reading(t, ids, distances, where * 80 / 3, spurious))
    return out


def back_and_forth(speed: float, low: float = -3.0, high: float = 3.0):
    """Walking from `low` to `high` and back, again and again, at `speed` spacings a second."""
    span = high - low

    def at(t: float) -> float:
        u = (speed * t) % (2 * span)
        return low + (u if u <= span else 2 * span - u)

    return at


def spread(results, after: float = 2.0) -> float:
    """The standard deviation of where the eyes look (pixels): a still person's jitter."""
    values = [s for t, s, _ in results if t >= after and s is not None]
    mean = sum(values) / len(values)
    return math.sqrt(sum((v - mean) ** 2 for v in values) / len(values))


WALK_SPEEDS = ((0.3, 40.0), (1.0, 24.0))  # (spacings a second, seconds): along the line and back, once, twice
STILL_AT = (0.5, -1.0)  # between two sensors, and in front of one
SEEDS = (1, 2, 3)


def faulty_traces() -> Dict[str, List[Reading]]:
    """The faulty traces the tests check and bench/bench_follow.py reports, by name: a person
    walking back and forth along the whole line, or standing, with and without a further object."""
    out = {}
    for second_object in (False, True):
        also = " + object" if second_object else ""
        for speed, seconds in WALK_SPEEDS:
            for seed in SEEDS:
                path = back_and_forth(speed)
                out[f"walk {speed:.1f}/s{also}, seed {seed}"] = faulty_trace(
                    path, seconds, seed, second_object
                )
        for at in STILL_AT:
            for seed in SEEDS:
                out[f"still at {at:.1f}{also}, seed {seed}"] = faulty_trace(
                    still(at), 30.0, seed, second_object
                )
    return out


def walk_past(seconds: float = 8.0, seed: int = 1) -> List[Reading]:
    """scripts_examples/walk-past.jsonl: a person walking past from the robot's right to its
    left at 0.75 spacings a second, with real sonar's faults and a further object."""
    return faulty_trace(walk(0.75), seconds, seed, second_object=True)


def as_jsonl(readings: List[Reading]) -> str:
    """A trace as `play --follow-from` reads it: one sonar reading a line."""
    import json

    return "".join(
        json.dumps({"t": round(r.t, 3), "sonar": [r.ids, [round(d, 3) for d in r.distances]]}) + "\n"
        for r in readings
    )


if __name__ == "__main__":  # python tests/support/traces.py > scripts_examples/walk-past.jsonl
    import sys

    sys.stdout.write(as_jsonl(walk_past()))
