"""Which of the faces the camera sees the eyes follow: the people seen, and the policy that chooses.

Each face the follower tracks is a `Person`: where it is (filtered), since when
it has been seen, when it last passed the check. The `PersonChoice` picks one of
the confirmed people by a policy, with hysteresis so that two faces that are
about as good never swap the eyes between them:

- `nearest` (the default): the largest face, which is the nearest person; another
  takes over once its area has been more than 1.3 times the followed one's for
  0.1 s (a person about 15 % nearer);
- `central`: the face nearest the middle of the image, where the head points;
  another takes over once it has been nearer the middle by more than a face's
  width for 0.1 s;
- `longest`: the face seen the longest; the eyes stay on it until it is gone.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import List, Optional, Sequence, Tuple

from .haar_detector import Box, same_face

FACE_POLICIES = ("nearest", "central", "longest")
DEFAULT_FACE_POLICY = "nearest"
FACE_POLICY_CHOICES = "nearest, central or longest"  # as errors say them


def check_face_policy(policy: str) -> str:
    """`policy` if it is one of FACE_POLICIES; ValueError saying which there are otherwise."""
    if policy not in FACE_POLICIES:
        raise ValueError(f"the face policy must be {FACE_POLICY_CHOICES}, not {str(policy)[:40]!r}")
    return policy


@dataclass
class Person:
    """A face the follower tracks: its box (filtered) and speed (pixels a second), when it was
    first and last found, when it last passed the check and how often it has."""

    box: Box
    first: float
    seen: float
    checked: float
    tried: float = -math.inf  # when it was last checked, passing or not
    checks: int = 1  # strict checks passed, while not yet confirmed ...
    fails: int = 0  # ... and failed
    sure: bool = False  # confirmed: followed now or later
    speed: Tuple[float, float] = (0.0, 0.0)
    found_now: bool = True  # found in the latest image

    ALPHA, BETA = 0.6, 0.1  # the alpha-beta filter on the face's centre

    @property
    def confirmed(self) -> bool:
        """Passed the strict check at least twice, and as often as it failed, before it is
        followed: one mistake never moves the eyes, and a thing that looks like a face only now
        and then never does."""
        return self.sure

    def checked_now(self, passed: bool, sure: bool, t: float) -> None:
        """The outcome of a check at `t`: `passed` (the cascades found it) and `sure` (strictly)."""
        self.tried = t
        if passed:
            self.checked = t
        if self.sure:
            return
        self.checks += sure
        self.fails += not sure
        self.sure = self.checks >= 2 and self.checks >= self.fails

    @property
    def doubtful(self) -> bool:
        """Not confirmed, and failed the strict check too often to be."""
        return not self.sure and self.fails >= 4 and self.fails >= 3 * self.checks

    def expected(self, t: float) -> Tuple[float, float]:
        """Where its centre should be at `t`, going on as it moved (0.2 s ahead at most)."""
        ahead = max(0.0, min(t - self.seen, 0.2))
        return self.box.x + self.speed[0] * ahead, self.box.y + self.speed[1] * ahead

    def follow(self, box: Box, t: float) -> None:
        """Take `box` as its position at `t`, through the alpha-beta filter."""
        face, dt = self.box, t - self.seen
        if dt <= 0.0 or not same_face(face, box, 1.0):
            self.box, self.speed = box, (0.0, 0.0)
        else:
            px, py = face.x + self.speed[0] * dt, face.y + self.speed[1] * dt
            rx, ry = box.x - px, box.y - py
            size = face.size + 0.5 * (box.size - face.size)
            self.box = Box(px + self.ALPHA * rx, py + self.ALPHA * ry, size, box.turn)
            self.speed = (self.speed[0] + self.BETA * rx / dt, self.speed[1] + self.BETA * ry / dt)
        self.seen = t
        self.found_now = True


class PersonChoice:
    """The policy (one of FACE_POLICIES) and its hysteresis: which person the eyes follow."""

    SWITCH_AREA = 1.3  # for `nearest`: another face's area must be this much larger ...
    SWITCH_AFTER = 0.1  # ... (or, for `central`, nearer the middle) for this long, to take over
    PATIENCE = 0.3  # seconds a first choice waits for a better face to be confirmed

    def __init__(self, policy: str = DEFAULT_FACE_POLICY) -> None:
        self.policy = check_face_policy(policy)
        self.followed: Optional[Person] = None
        self._rival: Optional[Person] = None
        self._rival_since = 0.0

    def reset(self) -> None:
        self.followed, self._rival = None, None

    def choose(self, people: Sequence[Person], t: float, width: int, height: int) -> Optional[Person]:
        """The person to follow now among `people` (only confirmed ones count), or None."""
        confirmed: List[Person] = [p for p in people if p.confirmed]
        middle = (width / 2.0, height / 2.0)
        if self.followed not in confirmed:
            # A better face seen at the same time may be a few images from confirmed: wait for it.
            best = self._best(people, middle)
            if best is not None and not best.confirmed and t - best.first < self.PATIENCE:
                self.followed = None
            else:
                self.followed = self._best(confirmed, middle)
            self._rival = None
            return self.followed
        followed = self.followed
        assert followed is not None
        rival = self._best([p for p in confirmed if p is not followed], middle)
        if rival is None or not self._better(rival, followed, middle):
            self._rival = None
        elif rival is not self._rival:
            self._rival, self._rival_since = rival, t
        elif t - self._rival_since >= self.SWITCH_AFTER - 1e-9:
            self.followed, self._rival = rival, None
        return self.followed

    def _best(self, people: Sequence[Person], middle: Tuple[float, float]) -> Optional[Person]:
        if not people:
            return None
        if self.policy == "nearest":
            return max(people, key=lambda p: p.box.size)
        if self.policy == "central":
            return min(people, key=lambda p: _off_middle(p, middle))
        return min(people, key=lambda p: p.first)

    def _better(self, rival: Person, followed: Person, middle: Tuple[float, float]) -> bool:
        """Whether `rival` is clearly better than the followed person, by the policy."""
        if self.policy == "nearest":
            return rival.box.size**2 > self.SWITCH_AREA * followed.box.size**2
        if self.policy == "central":
            margin = max(rival.box.size, followed.box.size)
            return _off_middle(rival, middle) + margin < _off_middle(followed, middle)
        return False  # longest: the followed face stays followed while it is seen


def _off_middle(person: Person, middle: Tuple[float, float]) -> float:
    return math.hypot(person.box.x - middle[0], person.box.y - middle[1])
