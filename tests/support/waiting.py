"""Waiting for a positive event in tests: asked again until it holds, never a sleep and a hope."""

from __future__ import annotations

import time
from typing import Callable, TypeVar

T = TypeVar("T")

# How long a test waits for something it expects to happen (a state, a frame, a sound, a line)
# before it fails. Generous: only a failing test waits it out, and a machine busy with other work
# (`make test-busy`, a robot beside heavy nodes) stretches a start or a first `say` to seconds.
PATIENCE = 60.0


def eventually(check: Callable[[], T], timeout: float = PATIENCE) -> T:
    """`check()` once it is truthy (asked every 50 ms for up to `timeout` seconds)."""
    deadline = time.monotonic() + timeout
    while True:
        value = check()
        if value:
            return value
        assert time.monotonic() < deadline, "waited in vain"
        time.sleep(0.05)


def caught_up(intake, now: float) -> None:
    """Wait until a live session at its intake has done all it had to by `now` on its clock (a test's
    clock, moved by hand): what was handed over taken, each step due by then begun."""

    def done() -> bool:
        with intake.session.lock:
            due = intake.session.next_due()
        return intake.idle() and (due is None or due[0] > now)

    eventually(done)
