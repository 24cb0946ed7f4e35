"""One ROS version's half of bench_ros_versions.py: command to first changed frame, relay and node.

    PYTHON bench/node_latency.py 1|2

Run with the Python that has that ROS (.venv-ros for 1, with ROS_MASTER_URI
set; .venv for 2, with ROS_DOMAIN_ID set), it measures through a Link of its
own, as any ROS program would see the face: from a command published on
display_chatter to the first frame received on /robot/xdisplay after it,
first against a relay that answers each command with a frame it already holds
(what ROS itself takes to move 1.8 MB: the floor), then against the face node
(`baxterface node --ros N`), each a process of its own. Prints JSON. On ROS 2,
every process takes the transport of BAXTERFACE_ROS_TRANSPORT (transport.py);
BAXTERFACE_BENCH_GAP is the pause in seconds after each frame (0.15).
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

from baxterface_cli.ros.connect import open_link

ROOT = Path(__file__).resolve().parent.parent
RELAY = """
import signal, sys, threading
import numpy
from baxterface_cli.ros.connect import open_link
from baxterface_cli.ros.images import image_fields
stop = threading.Event()
signal.signal(signal.SIGTERM, lambda *_: stop.set())
link = open_link(int(sys.argv[1]), "relay")
held = image_fields(numpy.zeros((600, 1024, 3), numpy.uint8))
screen = link.publisher("/robot/xdisplay", "sensor_msgs/Image", latched=True, queue=1)
link.subscribe("display_chatter", "std_msgs/String", lambda msg: screen.publish(**held), queue=100)
stop.wait()
link.close()
"""
COMMANDS = ("skin_3", "skin_1")  # each changes the face at once


class Frames:
    def __init__(self, link) -> None:
        self.times = []
        self.event = threading.Event()
        self.sub = link.subscribe("/robot/xdisplay", "sensor_msgs/Image", self._got, queue=10)

    def _got(self, msg) -> None:
        self.times.append(time.monotonic())
        self.event.set()


def connected(publisher, frames, who, timeout=60.0) -> None:
    """Until `who` hears our commands and we hear its frames (ROS 2 discovery takes seconds)."""
    deadline = time.monotonic() + timeout
    while publisher.listeners() == 0 or frames.sub.publishers() == 0:
        if who.poll() is not None or time.monotonic() > deadline:
            raise SystemExit(f"node_latency: {who.args} never connected")
        time.sleep(0.05)
    time.sleep(1.0)


GAP = float(os.environ.get("BAXTERFACE_BENCH_GAP", "0.15"))


def latencies(publisher, frames, count=120, gap=GAP):
    """Milliseconds from each command to the first frame that reaches us after it."""
    out = []
    for i in range(count):
        frames.event.clear()
        sent = time.monotonic()
        publisher.publish(data=COMMANDS[i % len(COMMANDS)])
        if frames.event.wait(2.0):
            out.append((frames.times[-1] - sent) * 1000)
        time.sleep(gap)
    return out


def measure(link, frames, argv, count):
    proc = subprocess.Popen(argv, cwd=str(ROOT), stdout=subprocess.DEVNULL)
    publisher = link.publisher("display_chatter", "std_msgs/String", queue=10)
    try:
        connected(publisher, frames, proc)
        return latencies(publisher, frames, count)
    finally:
        publisher.close()
        proc.send_signal(signal.SIGTERM)
        proc.wait(timeout=30)


def main() -> None:
    version = int(sys.argv[1])
    count = int(sys.argv[2]) if len(sys.argv) > 2 else 120
    link = open_link(version, "bench_latency", anonymous=True)
    frames = Frames(link)
    try:
        floor = measure(link, frames, [sys.executable, "-c", RELAY, str(version)], count)
        if version == 1:
            node_args = ["_idle:=false"]
        else:
            node_args = ["--ros-args", "-p", "idle:=false", "-p", "audio:=none"]
        node = measure(
            link,
            frames,
            [sys.executable, "-m", "baxterface_cli", "node", "--ros", str(version), *node_args],
            count,
        )
    finally:
        link.close()
    print(json.dumps({"version": version, "floor": floor, "node": node}))


if __name__ == "__main__":
    main()
