"""Refused requests, logged so that a flood of them cannot flood the log.

A route's refusal is logged as it comes, but the same refusal again (the same route, status and
reason) within a second is only counted, and the count is told with the next one logged: five
seconds of one bad body sent as fast as it goes wrote 6,815 lines, now five. Different mistakes
are each logged at once, as a user fixing a script wants.

What a refusal repeats of the request (its path, method, headers) is cut to ECHOED characters
with the length it had (`echoed`), and a whole line to LONGEST: a 16 KB path, or a token of
any size, once went into the log whole.
"""

from __future__ import annotations

import time
from typing import Callable, Dict, Tuple

EVERY = 1.0  # seconds between two log lines of one refusal
MOST_KINDS = 256  # refusals remembered; past it the memory starts over (a few lines more at most)
ECHOED = 80  # characters of a request's path, method or header a refusal repeats
LONGEST = 500  # characters of a refusal's line, whatever it says


def echoed(text: str, most: int = ECHOED) -> str:
    """Part of a request as a log line repeats it: its first `most` characters and its length."""
    return text if len(text) <= most else f"{text[:most]}... ({len(text):,} characters)"


class RefusalLog:
    def __init__(self, log: Callable[[str], None], clock: Callable[[], float] = time.monotonic) -> None:
        self.log = log
        self.clock = clock
        self.seen: Dict[str, Tuple[float, int]] = {}  # a refusal -> (when it was logged, repeats since)

    def __call__(self, text: str) -> None:
        text = echoed(text, LONGEST)
        now = self.clock()
        logged, repeats = self.seen.get(text, (-EVERY, 0))
        if now - logged < EVERY:
            self.seen[text] = (logged, repeats + 1)
            return
        if len(self.seen) >= MOST_KINDS:
            self.seen.clear()
        self.seen[text] = (now, 0)
        self.log(text + (f" ({repeats} more like it before)" if repeats else ""))
