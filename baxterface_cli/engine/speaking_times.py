"""When the face speaks, for a word spotter that must not hear the face itself (`play --listen`,
the node's ears).

A live session's face begins a new timeline at each step; the speech of the newest is what the
face says from its start on, and what an older one said was cut short where the new one began.
The spotter asks from its own thread; the caller follows the face from another.
"""

from __future__ import annotations

import threading
from typing import Any, List, Tuple

KEPT = 50  # spans of speech remembered from earlier timelines: enough for the spotter's echo


class SpeakingTimes:
    """The (start, end) spans the face speaks in, on the caller's clock."""

    def __init__(self) -> None:
        self.timeline: Any = None  # the timeline whose speech was read last
        self._spans: List[Tuple[float, float, str]] = []  # (start, end, what was said)
        self._lock = threading.Lock()

    def follow(self, timeline: Any, started: float, now: float) -> bool:
        """Read `timeline` (begun at `started`) if it is new; True if it was."""
        if timeline is self.timeline:
            return False
        self.timeline = timeline
        spans = [(started + s.at, started + s.end, s.utterance.text) for s in timeline.speech]
        with self._lock:  # what was cut short was said until now
            self._spans = [(a, min(b, now), text) for a, b, text in self._spans if a < now][-KEPT:] + spans
        return True

    def speaking(self, at: float) -> bool:
        """Was the face speaking at `at`?"""
        with self._lock:
            return any(start <= at <= end for start, end, _ in self._spans)

    def saying(self, start: float, end: float) -> str:
        """The words of what the face said at some time between `start` and `end`."""
        with self._lock:
            return " ".join(text for a, b, text in self._spans if a <= end and start <= b)
