"""What firing an event costs in the studio, from the first to the last a session holds.

Each event fired runs the editor's script again over all the events so far (studio/reacting.py),
so the cost grows with the session; the bound (`MOST_EVENTS`) keeps it finite. No server: the
workspace directly, on a clock of its own, so the figures are the work alone. Run:

    .venv/bin/python bench/bench_studio_events.py
"""

from __future__ import annotations

import statistics
import sys
import tempfile
import time
from pathlib import Path

from baxterface_cli.language.event_line import read_event_line
from baxterface_cli.studio.reacting import MOST_EVENTS
from baxterface_cli.studio.workspace import Workspace

GREETER = (
    "sad\non signal poke {\n  happy\n  look left in 0.3s\n  wait 0.5s\n}\n"
    "on touch left eye queue {\n  angry\n  wait 0.2s\n}\nforever {\n  blink\n  wait 2s\n}\n"
)


class Clock:
    now = 0.0

    def __call__(self) -> float:
        return self.now


def main() -> int:
    clock = Clock()
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "greeter.face"
        path.write_text(GREETER)
        workspace = Workspace(path, seed=1, idle=False, clock=clock)
        lines = [read_event_line("signal poke"), read_event_line("touch left eye")]
        costs = []
        for i in range(MOST_EVENTS):
            clock.now += 0.7  # the preview plays on between events
            started = time.perf_counter()
            workspace.event(lines[i % 2])
            costs.append(time.perf_counter() - started)
    first, last = statistics.median(costs[:10]), statistics.median(costs[-10:])
    print(f"firing an event: {first * 1000:.1f} ms at the first 10, {last * 1000:.1f} ms at the last 10")
    print(f"(of {MOST_EVENTS}; ratio {last / first:.1f})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
