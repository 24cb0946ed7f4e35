"""The face node on ROS 1 and on ROS 2, side by side in one run: command to first changed frame.

    .venv/bin/python bench/bench_ros_versions.py

ROS 1 runs under .venv-ros (Debian's Python with rospy) against a roscore of
its own on a free loopback port; ROS 2 under .venv (rclpy from PyPI, Fast DDS)
on loopback (ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST) in a ROS domain of its
own, with baxterface's ROS 2 transport (shm unless BAXTERFACE_ROS_TRANSPORT
says default; bench_ros2_transport.py sets the two side by side). Each half
(bench/node_latency.py) measures, through baxterface's own
Link, the milliseconds from a command on display_chatter (`skin_3` / `skin_1`,
which change the face at once) to the first frame received after it: first
from a relay that answers with a frame it holds (that ROS's own floor), then
from `baxterface node --ros N`. The two halves take turns, each run twice, so
the machine's moods fall on both. Goal: the ROS 2 node's median within 20 ms.
"""

from __future__ import annotations

import json
import os
import signal
import socket
import statistics
import subprocess
import sys
from pathlib import Path

from ros_master import start_roscore

ROOT = Path(__file__).resolve().parent.parent
PYTHONS = {1: ROOT / ".venv-ros" / "bin" / "python", 2: ROOT / ".venv" / "bin" / "python"}
GOAL_MS = 20.0
ROUNDS = 2


def free_domain() -> int:
    """A ROS domain no participant on this machine uses (its first discovery port is free)."""
    for domain in range(90, 101):
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
            try:
                s.bind(("0.0.0.0", 7400 + 250 * domain + 10))
            except OSError:
                continue
        return domain
    raise SystemExit("no free ROS domain")


def percentile(values, p):
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(round(p / 100 * (len(ordered) - 1))))]


def half(version: int, env) -> dict:
    run = subprocess.run(
        [str(PYTHONS[version]), str(ROOT / "bench" / "node_latency.py"), str(version)],
        cwd=str(ROOT),
        env=env,
        stdout=subprocess.PIPE,
        check=True,
        timeout=600,
    )
    return json.loads(run.stdout.decode().strip().splitlines()[-1])


def main() -> None:
    for python in PYTHONS.values():
        if not python.exists():
            raise SystemExit(f"bench_ros_versions: {python} is missing: make venv venv-ros")
    core, ros1 = start_roscore()
    ros2 = dict(os.environ, ROS_DOMAIN_ID=str(free_domain()), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST")
    results = {(v, kind): [] for v in (1, 2) for kind in ("floor", "node")}
    try:
        for _ in range(ROUNDS):
            for version, env in ((1, ros1), (2, ros2)):
                got = half(version, env)
                for kind in ("floor", "node"):
                    results[(version, kind)] += got[kind]
    finally:
        core.send_signal(signal.SIGINT)
        core.wait()
    print("display_chatter -> first changed frame at a subscriber (ms), side by side in one run")
    print(f"  {'':<28} {'p50':>6} {'p95':>6} {'p99':>6}  answered")
    names = {"floor": "relay (the floor)", "node": "baxterface node"}
    for version in (1, 2):
        for kind in ("floor", "node"):
            values = results[(version, kind)]
            p50, p95, p99 = statistics.median(values), percentile(values, 95), percentile(values, 99)
            print(f"  ROS {version} {names[kind]:<22} {p50:6.1f} {p95:6.1f} {p99:6.1f}  {len(values)}")
    node2 = statistics.median(results[(2, "node")])
    node1 = statistics.median(results[(1, "node")])
    verdict = "met" if node2 <= GOAL_MS else "NOT met"
    print(
        f"  ROS 2 node p50 {node2:.1f} ms (goal {GOAL_MS:.0f} ms: {verdict}); ROS 1 node p50 {node1:.1f} ms"
    )
    print(
        f"  node / floor, p50: ROS 1 {node1 / statistics.median(results[(1, 'floor')]):.1f}x, "
        f"ROS 2 {node2 / statistics.median(results[(2, 'floor')]):.1f}x"
    )
    sys.stdout.flush()


if __name__ == "__main__":
    main()
