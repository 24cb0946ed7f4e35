"""What the session log costs the face node (issue 47): `_log:=FILE` against no log, in one run.

    .venv-ros/bin/python bench/bench_logging.py [--count 120] [--rate 100] [--seconds 10] [--rounds 2]

A roscore of its own on a free loopback port; the node (`baxterface node`, ROS 1, idle off) as a
process of its own, started by turns without a log (the baseline) and with `_log:=FILE` in a
temporary folder, `--rounds` times each, so that a shared machine's changing load falls on both
alike. Measured from this process, through a Link as any ROS program would:

1. An event's time to frame: a navigator button press (a real baxter_core_msgs/NavigatorState on
   the left navigator's topic) whose handler changes the skin, to the first frame received on
   /robot/xdisplay after it, `--count` times. Goal: p50 with the log no more than 1 ms above
   the baseline's.
2. CPU at `--rate` events a second for `--seconds`: `signal`s on display_chatter at a handler
   that moves the eyes (most are dropped while it runs, each a line in the log), the node's CPU
   time (its /proc stat, every thread: the log's writer too) over the storm's wall time. Goal:
   no more than 5 % above the baseline's.

Prints JSON: each round's figures, the medians of each way, and the ratios.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench_reacting import HANDLERS, State, timed, until
from node_latency import Frames
from ros_master import start_roscore

ROOT = Path(__file__).resolve().parent.parent
STORM = "on signal poke { look left in 0.1s; look right in 0.1s }"


def cpu_seconds(pid: int) -> float:
    """The process's user and system time so far, every thread's."""
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def one_node(link, frames, chatter, nav, log, args):
    """A node started (with `log` as its `_log` when given), measured, and stopped."""
    state = State(link)
    argv = [sys.executable, "-m", "baxterface_cli", "node", "_idle:=false", "_audio:=none"]
    proc = subprocess.Popen(
        [*argv, *([f"_log:={log}"] if log else [])], cwd=str(ROOT), stdout=subprocess.DEVNULL
    )
    try:
        # `state` subscribed after the node before was gone: what it hears is this node's.
        up = lambda: chatter.listeners() > 0 and nav.listeners() > 0 and state.last  # noqa: E731
        until(up, 60, "the node connecting")
        chatter.publish(data=HANDLERS)
        until(lambda: len(state.last.get("handlers", {})) == 4, 30, "the handlers installing")
        names = ["0", "1", "2"]

        def press(i):
            up = i % 2 == 0
            nav.publish(button_names=names, buttons=[False, False, False], wheel=0)
            time.sleep(0.02)  # a release, then the press timed
            frames.event.clear()
            sent = time.monotonic()
            nav.publish(button_names=names, buttons=[False, up, not up], wheel=0)
            return sent

        latencies = timed(frames, press, args.count)
        chatter.publish(data=STORM)
        until(lambda: len(state.last.get("handlers", {})) == 5, 30, "the storm's handler installing")
        time.sleep(1.0)
        cpu, began, sent = cpu_seconds(proc.pid), time.monotonic(), 0
        while sent < args.rate * args.seconds:
            due = began + sent / args.rate
            if due > time.monotonic():
                time.sleep(due - time.monotonic())
            chatter.publish(data="signal poke")
            sent += 1
        wall = time.monotonic() - began
        used = cpu_seconds(proc.pid) - cpu
        return {
            "log": bool(log),
            "event_p50_ms": round(statistics.median(latencies), 2),
            "answered": f"{len(latencies)}/{args.count}",
            "storm_cpu_percent": round(100 * used / wall, 1),
            "storm_sent_in_s": round(wall, 2),
            "log_bytes": os.path.getsize(log) if log and os.path.exists(log) else None,
        }
    finally:
        proc.send_signal(signal.SIGTERM)
        proc.wait(timeout=30)
        state.sub.close()


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--count", type=int, default=120)
    parser.add_argument("--rate", type=float, default=100.0)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--rounds", type=int, default=2)
    args = parser.parse_args()
    sys.path.insert(0, str(ROOT))
    from baxterface_cli.ros.connect import open_link

    load = os.getloadavg()
    core, env = start_roscore()
    os.environ.update(env)
    link = open_link(1, "bench_logging", anonymous=True)
    folder = tempfile.mkdtemp(prefix="bench_logging.")
    rounds = []
    try:
        frames = Frames(link)
        chatter = link.publisher("display_chatter", "std_msgs/String", queue=1000)
        nav = link.publisher("/robot/navigators/left_navigator/state", "baxter_core_msgs/NavigatorState")
        for k in range(args.rounds):
            for logged in (False, True):
                log = os.path.join(folder, f"session-{k}.jsonl") if logged else None
                rounds.append(one_node(link, frames, chatter, nav, log, args))
    finally:
        link.close()
        core.send_signal(signal.SIGINT)
        core.wait(timeout=30)

    def median(key, logged):
        return statistics.median(r[key] for r in rounds if r["log"] == logged)

    base_ms, log_ms = median("event_p50_ms", False), median("event_p50_ms", True)
    base_cpu, log_cpu = median("storm_cpu_percent", False), median("storm_cpu_percent", True)
    out = {
        "load_before": [round(x, 2) for x in load],
        "load_after": [round(x, 2) for x in os.getloadavg()],
        "cores": os.cpu_count(),
        "rounds": rounds,
        "event_p50_ms": {"without": base_ms, "with_log": log_ms, "difference": round(log_ms - base_ms, 2)},
        "storm_cpu_percent": {
            "without": base_cpu,
            "with_log": log_cpu,
            "ratio": round(log_cpu / base_cpu, 3) if base_cpu else None,
        },
        "goals": {"p50_difference_ms": 1.0, "cpu_ratio": 1.05},
    }
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
