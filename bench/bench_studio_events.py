"""What firing an event costs in the studio, at the 1st, the 200th and the 2,000th of a session.

Now: the run is kept at its last event and continued (studio/event_run.py). Before: the script
ran again over all the events so far at each one; that is measured here too, in the same run
(the same machine, the same load), by running the script over the first 1, 200 and 2,000 events
as the studio used to. No server: the workspace directly, on a clock of its own, so the figures
are the work alone, with the preview's idle life on (its blinks are planned over the whole run).
Memory: the process's resident size before and after the session's events.

Then an edit of the script at the last event (`Workspace.update`, as the editor sends it): a
handler added for an event the session has not had (`on face seen`), which the run goes on with
from its last checkpoint; against the same edit run again over every event (`EventRun.start`, as
the studio did), in the same run. Run:

    .venv/bin/python bench/bench_studio_events.py [--events 2000] [--no-idle]
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import sys
import tempfile
import time
from pathlib import Path

from baxterface_cli.engine.session_run import NeverRests, run_over
from baxterface_cli.language.event_line import read_event_line
from baxterface_cli.language.event_trace import Trace
from baxterface_cli.language.parser import parse
from baxterface_cli.studio.event_run import WINDOW, EventRun
from baxterface_cli.studio.workspace import Workspace

GREETER = (
    "sad\non signal poke {\n  happy\n  look left in 0.3s\n  wait 0.5s\n}\n"
    "on touch left eye queue {\n  angry\n  wait 0.2s\n}\nforever {\n  blink\n  wait 2s\n}\n"
)
AROUND = 5  # events either side of each one measured: the median of these


class Clock:
    now = 0.0

    def __call__(self) -> float:
        return self.now


def rss_mb() -> float:
    with open("/proc/self/statm") as statm:
        return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


def replayed(script, events) -> float:
    """What an event cost before: the script run again over all the events so far."""
    started = time.perf_counter()
    trace = Trace(tuple(events), "events")
    try:
        run_over(script, trace, 1)
    except NeverRests:
        run_over(script, trace, 1, trace.end + WINDOW)
    return time.perf_counter() - started


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--events", type=int, default=2000)
    parser.add_argument("--no-idle", action="store_true", help="the preview without its idle life")
    options = parser.parse_args()
    count = options.events
    marks = [m for m in (1, 200, 2000) if m <= count]
    clock = Clock()
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "greeter.face"
        path.write_text(GREETER)
        workspace = Workspace(path, seed=1, idle=not options.no_idle, clock=clock)
        lines = [read_event_line("signal poke"), read_event_line("touch left eye")]
        costs = []
        before_mb = rss_mb()
        for i in range(count):
            clock.now += 0.7  # the preview plays on between events
            started = time.perf_counter()
            workspace.event(lines[i % 2])
            costs.append(time.perf_counter() - started)
        after_mb = rss_mb()
        events = list(workspace.preview.inputs)
        run_length = workspace.preview.duration
    script = parse(GREETER, "greeter.face")
    idle = "off" if options.no_idle else "on"
    print(
        f"load: {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores; {count} events, 0.7 s apart; idle {idle}"
    )
    print("event    now (continued)    before (run again over all)")
    for mark in marks:
        near = costs[max(0, mark - 1 - AROUND) : mark + AROUND]
        again = [replayed(script, events[:mark]) for _ in range(3 if mark < 1000 else 1)]
        print(f"{mark:>5}    {statistics.median(near) * 1000:8.1f} ms        {min(again) * 1000:8.1f} ms")
    # The preview stops where the run comes to rest (a handler done, the main script in its
    # `forever`): an event fired after that comes at the end, so the run is shorter than the clock.
    print(f"the run: {run_length:.0f} s, its last event at {events[-1].at:g} s")
    grown = after_mb - before_mb
    print(
        f"memory: {grown:.1f} MB more resident after {count} events ({grown * 1024 / count:.1f} KB an event)"
    )
    print(f"(peak resident size {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MB)")
    edit(workspace, count)
    return 0


EDIT = GREETER + "on face seen {\n  happy\n}\n"


def edit(workspace: Workspace, count: int) -> None:
    """The edit at the last event: gone on with (now) against run again over every event (before)."""
    now, again = [], []
    events = tuple(workspace.preview.inputs)
    for i in range(3):
        text = EDIT if i % 2 == 0 else GREETER  # back and forth: each one an edit of the last
        started = time.perf_counter()
        answer = workspace.update(text)
        now.append(time.perf_counter() - started)
        assert answer["diagnostics"] == [], answer
        started = time.perf_counter()
        EventRun.start(
            parse(text, "greeter.face"), workspace.preview.seed, workspace.preview.recordings, events
        )
        again.append(time.perf_counter() - started)
    fast, slow = statistics.median(now), statistics.median(again)
    print(f"an edit at the {count}th event (a handler added for an event not fired yet), the median of 3:")
    print(f"  now (gone on from the last checkpoint) {fast * 1000:8.1f} ms")
    print(f"  before (run again over every event)    {slow * 1000:8.1f} ms  -> {slow / fast:.1f}x faster")


if __name__ == "__main__":
    sys.exit(main())
