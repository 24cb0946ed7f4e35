"""`play` as the tests drive it: in a terminal they read, and on a clock they move."""

from __future__ import annotations

import os
import sys

import pexpect

from conftest import ROOT


def spawn_play(*args, env=None):
    return pexpect.spawn(
        sys.executable,
        ["-m", "baxterface_cli", "play", "--terminal", "--no-idle", *args],
        cwd=str(ROOT),
        dimensions=(32, 100),
        encoding="utf-8",
        # The terminal echoes a Ctrl-C where it lands, even inside a half-written block character.
        codec_errors="replace",
        timeout=30,
        env=env or terminal_env(),
    )


def terminal_env():
    """This environment for a program in a pseudo-terminal: it must measure the terminal itself,
    not take COLUMNS and LINES from whoever ran the tests (pytest-xdist's workers set them)."""
    env = {k: v for k, v in os.environ.items() if k not in ("COLUMNS", "LINES")}
    return dict(env, TERM="xterm-256color")


class FakeClock:
    """Time that passes only when the player sleeps or a frame costs some."""

    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now

    def sleep(self, seconds: float) -> None:
        self.now += seconds


def paced(times, fps: float = 30.0) -> bool:
    """Whether frames heard at `times` (seconds, in order) came at a real-time player's pace at
    `fps`, not all at once. A real-time player sends each frame at its time in the script and
    drops the ones it is late for, so however late its first (on a busy machine), the rest come
    at least half a frame apart on average; all at once, they come milliseconds apart. A busy
    machine may drop all but a few (ROS 2 loses whole frames when its reader falls behind), so two
    are enough when they are a tenth of a second apart or more, which a burst never is."""
    span = times[-1] - times[0] if times else 0.0
    return len(times) >= 2 and span >= max(0.1, (len(times) - 1) * 0.5 / fps)
