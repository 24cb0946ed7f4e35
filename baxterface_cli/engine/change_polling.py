"""When a live face is looked at again after a command: soon, until its picture changes.

A loop that draws at its frame rate would show a command's first change up to a whole
frame later. After a command, the face node and the studio's pump look at the face every
POLL seconds instead, until the picture changes (then they keep their ticks) or EAGER_FOR
has passed (a command that changes nothing for a while costs no more than that). Looking
is cheap: a frame's key, not a drawing. The clock is the caller's.
"""

from __future__ import annotations

POLL = 0.002  # a timed statement's first change comes a few milliseconds after it starts
EAGER_FOR = 0.25


class ChangePolling:
    """The time of the next look: the loop's tick, or sooner while a command's change is awaited."""

    def __init__(self, poll: float = POLL, eager_for: float = EAGER_FOR) -> None:
        self.poll = poll
        self.eager_for = eager_for
        self.until = float("-inf")

    def heard(self, now: float) -> None:
        """A command started at `now`: look often until its first change shows."""
        self.until = now + self.eager_for

    def shown(self) -> None:
        """A changed picture went out: back to the ticks."""
        self.until = float("-inf")

    def next_look(self, tick: float, now: float) -> float:
        """When to look next, given the loop's own next tick."""
        return min(tick, now + self.poll) if now < self.until else tick
