"""The node's intake: commands parsed off the frame loop, bounded, the newest take-over winning."""

from __future__ import annotations

import threading
import time

import pytest

from baxterface_cli.engine.command_intake import Intake
from baxterface_cli.engine.live_face import LiveFace

# Slow to compile (about a second): far longer than the handful of submissions made while it is.
BIG = "repeat 2000 { repeat 5 { look 40 -20 in 0.01s; skin 3 } }"


class Loop:
    """A frame loop's view: a clock we move by hand and a log."""

    def __init__(self, **kwargs) -> None:
        self.now = 0.0
        self.live = LiveFace(idle=False, seed=1, now=0.0, **kwargs)
        self.woken = threading.Event()
        self.intake = Intake(self.live, lambda: self.now, ready=self.woken.set)
        self.log = []

    def settle(self, timeout=60.0):
        """Wait until the intake has prepared everything, then hand it over as the loop would."""
        deadline = time.monotonic() + timeout
        while not self.intake.idle():
            assert time.monotonic() < deadline, "the intake did not finish"
            time.sleep(0.01)
        return self.intake.hand_over(self.now, warn=self.log.append, error=self.log.append)


def test_a_command_is_prepared_off_the_callers_thread_and_started_by_it():
    loop = Loop()
    assert loop.intake.submit("look 40 0 in 1s") is None
    assert loop.settle() is True and loop.woken.is_set()
    loop.now = 1.0
    assert loop.live.state(1.0).eye_x == pytest.approx(40)


def test_while_a_big_script_is_prepared_the_caller_keeps_going_and_only_the_newest_take_over_starts():
    loop = Loop()
    loop.intake.submit(BIG)
    while not loop.intake.busy:  # until the worker has it
        time.sleep(0.001)
    for k in range(1, 6):
        loop.intake.submit(f"look {10 * k} 0 in 0s")
        # Nothing is ready yet, and handing over does not wait for it.
        assert loop.intake.hand_over(0.0, loop.log.append, loop.log.append) is None
    loop.settle()
    assert loop.intake.dropped == 4  # looks 10 to 40 were replaced before they started
    loop.now = 0.1
    assert loop.live.state(0.1).eye_x == pytest.approx(50)  # the newest, which came after the big one


def test_queued_commands_wait_bounded_and_are_refused_beyond_with_a_reason():
    loop = Loop()
    loop.intake.submit(BIG)
    while not loop.intake.busy:
        time.sleep(0.001)
    refusals = [loop.intake.submit("blink", queued=True) for _ in range(12)]
    assert refusals[:8] == [None] * 8
    assert refusals[8:] == ["refused a queued script: 8 are already waiting to be read"] * 4


def test_the_live_queue_is_capped_and_says_so():
    loop = Loop(max_queue=3)
    loop.intake.submit("look 40 0 in 10s")
    loop.settle()
    for _ in range(5):
        loop.intake.submit("blink", queued=True)
        loop.settle()
    assert len(loop.live.queue) == 3
    assert loop.log == ["refused a queued script: the queue is full (3 scripts)"] * 2


def test_a_take_over_drops_queued_scripts_prepared_before_it():
    loop = Loop()
    loop.intake.submit("look 40 0 in 10s")
    loop.settle()
    loop.intake.submit("skin 0", queued=True)
    loop.intake.submit("look -40 0 in 0s")
    loop.settle()
    assert not loop.live.queue
    loop.now = 20.0
    assert loop.live.state(20.0).skin != 0


def test_a_bad_command_is_one_log_line_however_many_problems_it_has():
    loop = Loop()
    loop.intake.submit("a\n" * 5000)
    loop.settle()
    (line,) = loop.log
    assert line.startswith("bad command: display_chatter:1:1: error: unknown command 'a'")
    assert line.endswith("more problems)") and "\n" not in line
