"""Refused requests, logged so that a flood of them cannot flood the log.

A route's refusal is logged as it comes, but the same refusal again (the same route, status and
reason) within a second is only counted, and the count is told with the next one logged: five
seconds of one bad body sent as fast as it goes wrote 6,815 lines, now five. Different mistakes
are each logged at once, as a user fixing a script wants.
"""

from __future__ import annotations

import time
from typing import Callable, Dict, Tuple

EVERY = 1.0  # seconds between two log lines of one refusal
MOST_KINDS = 256  # refusals remembered; past it the memory starts over (a few lines more at most)


class RefusalLog:
    def __init__(self, log: Callable[[str], None], clock: Callable[[], float] = time.monotonic) -> None:
        self.log = log
        self.clock = clock
        self.seen: Dict[str, Tuple[float, int]] = {}  # a refusal -> (when it was logged, repeats since)

    def __call__(self, text: str) -> None:
        now = self.clock()
        logged, repeats = self.seen.get(text, (-EVERY, 0))
        if now - logged < EVERY:
            self.seen[text] = (logged, repeats + 1)
            return
        if len(self.seen) >= MOST_KINDS:
            self.seen.clear()
        self.seen[text] = (now, 0)
        self.log(text + (f" ({repeats} more like it before)" if repeats else ""))
