"""An hour of random events on a fast clock through the session's log file (issue 47).

    .venv/bin/python bench/bench_log_soak.py [--hours 2]

The live session as the live ends drive it (tests/support/log_soak.py: each event recorded and
posted, the session's lines followed, a frame asked for every 0.25 s), an event a second on
average at random, its log written by the log file's own thread to a temporary folder. Then the
log is read back and replayed (`render LOG.jsonl`'s replay): complete when it holds every event
and every line the session logged, and the replay's log is the live one, line for line, at the
same times. Memory (tracemalloc's, the Python heap) every ten minutes of the session, once the
writer has written what it was handed. The session keeps the last 10,000 lines of its own log
(MAX_LOG, for ~state and the pages), which an event a second fills in about 40 minutes: memory
grows until then, and is flat from there when it moves less than 1 MB among the samples taken
with that log full (hence two hours by default).
Prints JSON; the tests run ten minutes of it (tests/engine/test_session_log_soak.py).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

sys.path[:0] = [str(Path(__file__).resolve().parent.parent / "tests" / d) for d in ("support", "")]

from log_soak import soak  # noqa: E402

from baxterface_cli.engine.live_session import MAX_LOG  # noqa: E402
from baxterface_cli.engine.log_replay import read_log, run_log  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--hours", type=float, default=2.0)
    args = parser.parse_args()
    seconds = args.hours * 3600
    path = os.path.join(tempfile.mkdtemp(prefix="bench_log_soak."), "soak.jsonl")
    began = time.monotonic()
    got = soak(path, seconds, sample=600.0, measure=True)
    ran = time.monotonic() - began
    session = got["session"]
    with open(path, encoding="utf-8") as f:
        records = [json.loads(line) for line in f]
    lines = [(r["t"], r["kind"], r["text"]) for r in records if r["type"] == "log"]
    began = time.monotonic()
    replay = read_log(path)
    run = run_log(replay, replay.seed, duration=seconds)
    replayed = [(line.at, line.kind, line.text) for line in run.log]
    memory = got["memory"]
    full = [m for m, kept in zip(memory, got["kept"]) if kept == MAX_LOG]
    print(
        json.dumps(
            {
                "load": [round(x, 2) for x in os.getloadavg()],
                "session_s": seconds,
                "ran_in_s": round(ran, 1),
                "replayed_in_s": round(time.monotonic() - began, 1),
                "events": got["events"],
                "log_bytes": os.path.getsize(path),
                "records": dict(Counter(r["type"] for r in records)),
                "lines": dict(Counter(kind for _, kind, _ in lines)),
                "every_event_logged": sum(r["type"] == "event" for r in records) == got["events"],
                "every_line_logged": len(lines) == session.logged,
                "nothing_skipped": not any(r["type"] == "skipped" for r in records),
                "replay_is_the_live_log": replayed == lines,
                "memory_kib_every_10_min": [m // 1024 for m in memory],
                "session_log_lines_kept": got["kept"],
                "memory_flat_once_its_log_is_full": max(full) - min(full) < 1_000_000
                if len(full) > 1
                else None,
            },
            indent=1,
        )
    )


if __name__ == "__main__":
    main()
