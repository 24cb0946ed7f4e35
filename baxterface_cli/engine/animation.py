"""The idle layer: blinks every 3-8 s and small eye darts, on top of a timeline.

It only acts where the script leaves the face alone: a blink only while the
lids are open and no lid move is under way, a dart only while the eyes hold
still and nothing is followed. It is drawn from its own seeded random
stream, so switching it on changes no emotion the script picks.

A `mood` shapes it: arousal quickens blinks and darts and widens the darts
(calm slows them), and a low valence now and then turns the gaze down and
away for a moment.
"""

from __future__ import annotations

import bisect
import random
from typing import List, NamedTuple, Optional

from ..core.face_constants import TIMING
from ..core.face_state import FaceState
from ..core.geometry import clamp_to_ellipse
from .timeline import Timeline

BLINK_EVERY = (3.0, 8.0)
DART_EVERY = (1.5, 5.0)
DART_HOLD = (0.4, 1.2)
DART_MOVE = 0.08  # seconds to dart out, and back
DART_REACH = (8.0, 6.0)  # eye pixels, x and y
AROUSAL_PACE = 0.5  # at arousal 1 the waits are half as long, at -1 one and a half times
AVERT_BELOW = -0.3  # a valence under this averts the gaze on some darts: the lower, the more
AVERT_REACH = ((15.0, 35.0), (40.0, 70.0))  # eye pixels aside, and down
AVERT_HOLD = (0.8, 1.6)


class Dart(NamedTuple):
    at: float
    hold: float
    dx: float
    dy: float

    @property
    def end(self) -> float:
        return self.at + 2 * DART_MOVE + self.hold


class Idle:
    """Blinks and darts for the first `until` seconds of a timeline."""

    def __init__(self, timeline: Timeline, seed: Optional[int] = 0, until: Optional[float] = None) -> None:
        self.timeline = timeline
        self.rng = random.Random(f"idle:{seed}")
        self.blinks: List[float] = []
        self.darts: List[Dart] = []
        self._dart_starts: List[float] = []
        self._next_blink = self.rng.uniform(*BLINK_EVERY)
        self._next_dart = self.rng.uniform(*DART_EVERY)
        self.extend(timeline.duration if until is None else until)

    def extend(self, until: float) -> None:
        """Plan blinks and darts up to `until` (a live face calls this as time goes on)."""
        lids, eyes = self.timeline.lids, self.timeline.eyes
        blink = TIMING.blink_close + TIMING.blink_open
        while self._next_blink < until:
            t = self._next_blink
            asleep = self.timeline.sample(t).skin == 5
            if not lids.busy(t, t + blink) and lids.value(t) > 0.4 and not asleep:
                self.blinks.append(t)
            self._next_blink += self.rng.uniform(*BLINK_EVERY) * self._pace(t)
        while self._next_dart < until:
            t = self._next_dart
            dart = self._dart(t)
            if not eyes.busy(t, dart.end) and self.timeline.status(t).following is None:
                self.darts.append(dart)
                self._dart_starts.append(dart.at)
            self._next_dart = dart.end + self.rng.uniform(*DART_EVERY) * self._pace(t)

    def _pace(self, t: float) -> float:
        """How much longer than usual the waits between blinks and darts are at t."""
        return 1.0 - AROUSAL_PACE * self.timeline.mood_at(t)[1]

    def _dart(self, t: float) -> Dart:
        valence, arousal = self.timeline.mood_at(t)
        reach = 1.0 + AROUSAL_PACE * arousal
        dart = Dart(t, self.rng.uniform(*DART_HOLD), *(self.rng.uniform(-r, r) * reach for r in DART_REACH))
        if valence < AVERT_BELOW and self.rng.random() < (AVERT_BELOW - valence) / (1 + AVERT_BELOW):
            aside, down = (self.rng.uniform(*span) for span in AVERT_REACH)
            dart = Dart(t, self.rng.uniform(*AVERT_HOLD), aside * self.rng.choice((-1, 1)), down)
        return dart

    def apply(self, t: float, state: FaceState, darts: bool = True) -> FaceState:
        """`state` with any blink (and dart, unless told not) under way at `t` laid over it."""
        i = bisect.bisect_right(self.blinks, t) - 1
        if i >= 0 and t - self.blinks[i] < TIMING.blink_close + TIMING.blink_open:
            u = t - self.blinks[i]
            closing = u < TIMING.blink_close
            shut = 1 - u / TIMING.blink_close if closing else (u - TIMING.blink_close) / TIMING.blink_open
            state = state.replace(eyelids=state.eyelids * shut)
        i = bisect.bisect_right(self._dart_starts, t) - 1
        if darts and i >= 0 and t < self.darts[i].end:
            dart = self.darts[i]
            u = t - dart.at
            out = min(1.0, u / DART_MOVE, (dart.end - t) / DART_MOVE)
            x, y = clamp_to_ellipse(state.eye_x + dart.dx * out, state.eye_y + dart.dy * out)
            state = state.replace(eye_x=x, eye_y=y)
        return state


class Animation:
    """What is shown: a timeline, with the idle layer on top when asked for."""

    def __init__(self, timeline: Timeline, idle: bool = False, seed: Optional[int] = 0) -> None:
        self.timeline = timeline
        self.idle = Idle(timeline, seed) if idle else None

    @property
    def duration(self) -> float:
        return self.timeline.duration

    def sample(self, t: float) -> FaceState:
        state = self.timeline.sample(t)
        return self.idle.apply(t, state) if self.idle else state
