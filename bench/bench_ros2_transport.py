"""ROS 2 frames by transport: Fast DDS as ROS sets it up (`default`) against baxterface's `shm`.

    .venv/bin/python bench/bench_ros2_transport.py [COMMANDS]

For each transport, in turns (twice each, so the machine's moods fall on
both), bench/node_latency.py measures from a command on display_chatter to the
first frame received after it (bgr8 1024x600, 1.8 MB): first from a relay that
answers each command with a frame it holds (the middleware's floor), then from
`baxterface node --ros 2`, every process with the same settings
(BAXTERFACE_ROS_TRANSPORT, ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST as the
tests run, a ROS domain of its own on loopback). COMMANDS (default 100) go at
about 10 a second. Goals, on a quiet machine: the shm node's p50 <= 12 ms,
p95 <= 25 ms, and the node's own cost over the relay <= 3 ms at the median.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

from bench_ros_versions import free_domain, percentile

ROOT = Path(__file__).resolve().parent.parent
PYTHON = ROOT / ".venv" / "bin" / "python"
TRANSPORTS = ("default", "shm")
ROUNDS = 2
GAP = 0.1  # seconds between commands (node_latency.py waits for each frame first)


def half(transport: str, count: int, domain: int) -> dict:
    env = dict(
        os.environ,
        BAXTERFACE_ROS_TRANSPORT=transport,
        ROS_DOMAIN_ID=str(domain),
        ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
        BAXTERFACE_BENCH_GAP=str(GAP),
    )
    run = subprocess.run(
        [str(PYTHON), str(ROOT / "bench" / "node_latency.py"), "2", str(count)],
        cwd=str(ROOT),
        env=env,
        stdout=subprocess.PIPE,
        check=True,
        timeout=900,
    )
    return json.loads(run.stdout.decode().strip().splitlines()[-1])


def main() -> None:
    if not PYTHON.exists():
        raise SystemExit(f"bench_ros2_transport: {PYTHON} is missing: make venv")
    count = int(sys.argv[1]) if len(sys.argv) > 1 else 100
    domain = free_domain()
    results = {(t, kind): [] for t in TRANSPORTS for kind in ("floor", "node")}
    loads = [os.getloadavg()[0]]
    for _ in range(ROUNDS):
        for transport in TRANSPORTS:
            got = half(transport, count, domain)
            for kind in ("floor", "node"):
                results[(transport, kind)] += got[kind]
            loads.append(os.getloadavg()[0])
    print("ROS 2: display_chatter -> first changed frame at a subscriber (ms), one run, in turns")
    print(f"  load average (1 min) during the run: {min(loads):.1f} to {max(loads):.1f}")
    print(f"  {'transport':<10} {'':<18} {'p50':>6} {'p95':>6} {'p99':>6}  answered")
    names = {"floor": "relay (the floor)", "node": "baxterface node"}
    for transport in TRANSPORTS:
        for kind in ("floor", "node"):
            values = results[(transport, kind)]
            p50, p95, p99 = statistics.median(values), percentile(values, 95), percentile(values, 99)
            print(f"  {transport:<10} {names[kind]:<18} {p50:6.1f} {p95:6.1f} {p99:6.1f}  {len(values)}")
    for transport in TRANSPORTS:
        node, floor = results[(transport, "node")], results[(transport, "floor")]
        over = statistics.median(node) - statistics.median(floor)
        print(f"  {transport}: node over relay at p50 {over:+.1f} ms")
    shm = results[("shm", "node")]
    p50, p95 = statistics.median(shm), percentile(shm, 95)
    over = p50 - statistics.median(results[("shm", "floor")])
    met = p50 <= 12.0 and p95 <= 25.0 and over <= 3.0
    print(
        f"  goals (quiet machine): shm node p50 {p50:.1f} <= 12, p95 {p95:.1f} <= 25, "
        f"over relay {over:+.1f} <= 3 ms: {'met' if met else 'NOT met'}"
    )
    sys.stdout.flush()


if __name__ == "__main__":
    main()
