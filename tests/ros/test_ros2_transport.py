"""The face's frames on ROS 2 between transports, and its JPEGs, received by real subscribers.

The node runs with baxterface's default transport (shm: Fast DDS's shared
memory with segments that hold a frame) and a subscriber in another process
with ROS's own set-up (ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST, as before),
and the other way round: each gets the other's messages. Each subscriber
also takes `/robot/xdisplay/compressed` and decodes the JPEG it receives.
"""

from __future__ import annotations

import io
import subprocess
import sys
import time

import pytest
from test_ros2_node import NodeProcess

from conftest import ROOT, baxterface

pytestmark = [pytest.mark.ros2, pytest.mark.xdist_group("ros2_transport")]

# A plain subscriber to the face's frames, raw and JPEG, as a program of the user's would be.
PEER = r"""
import io, sys, time
import numpy as np
from PIL import Image
from baxterface_cli.ros.connect import open_link
from baxterface_cli.ros.images import image_pixels
link = open_link(2, "peer", anonymous=True)
print("peer transport:", link.transport or "-", flush=True)
got = {}
link.subscribe("/robot/xdisplay", "sensor_msgs/Image",
               lambda m: got.setdefault("frame", image_pixels(m).astype(int)), latched=True)
link.subscribe("/robot/xdisplay/compressed", "sensor_msgs/CompressedImage",
               lambda m: got.setdefault("jpeg", (m.format, bytes(m.data))), latched=True)
deadline = time.monotonic() + 90
while len(got) < 2 and time.monotonic() < deadline:
    time.sleep(0.05)
if "frame" in got:
    f = got["frame"]
    print("frame", f.shape[1], f.shape[0], "spread", int(f.max() - f.min()), flush=True)
if "jpeg" in got:
    fmt, data = got["jpeg"]
    pixels = np.asarray(Image.open(io.BytesIO(data)).convert("RGB"))[..., ::-1].astype(int)
    print("jpeg", repr(fmt), pixels.shape[1], pixels.shape[0], flush=True)
    if "frame" in got:
        print("jpeg off by", float(np.abs(pixels - got["frame"]).mean()), flush=True)
link.close()
"""


def peer(env, transport):
    """The subscriber's lines, run with `transport` (BAXTERFACE_ROS_TRANSPORT) in `env`."""
    run = subprocess.run(
        [sys.executable, "-c", PEER],
        cwd=str(ROOT),
        env=dict(env, BAXTERFACE_ROS_TRANSPORT=transport),
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        timeout=150,
    )
    return run.stdout


def assert_saw_the_face(out):
    assert "frame 1024 600" in out, out
    assert int(out.split("spread ")[1].split()[0]) > 100, out  # a face, not a blank screen
    assert "jpeg 'bgr8; jpeg compressed bgr8' 1024 600" in out, out
    assert float(out.split("jpeg off by ")[1].split()[0]) < 6.0, out  # the same picture, as JPEG


def test_a_shm_node_reaches_a_subscriber_with_ros_own_setup_and_sends_it_jpegs(ros2):
    node = NodeProcess(ros2, "--ros-args", "-p", "idle:=false", "-p", "audio:=none")
    try:
        node.wait_for_line("ROS 2 transport: shm (Fast DDS shared memory, 8 MB segments; this host only)")
        out = peer(ros2, "default")
        assert "peer transport: default (ROS's own Fast DDS set-up)" in out, out
        assert_saw_the_face(out)
    finally:
        code, log = node.stop()
    assert code == 0 and "Traceback" not in log, log


def test_a_node_with_ros_own_setup_reaches_a_shm_subscriber(ros2):
    node = NodeProcess(ros2, "--ros-transport", "default", "--ros-args", "-p", "idle:=false")
    try:
        node.wait_for_line("ROS 2 transport: default (ROS's own Fast DDS set-up)")
        out = peer(ros2, "shm")
        assert "peer transport: shm" in out, out
        assert_saw_the_face(out)
    finally:
        code, log = node.stop()
    assert code == 0 and "Traceback" not in log, log


def test_a_transport_of_the_users_own_wins_and_is_named(ros2):
    env = dict(ros2, FASTDDS_BUILTIN_TRANSPORTS="UDPv4")
    node = NodeProcess(env, "--ros-args", "-p", "idle:=false", "-p", "transport:=shm")
    try:
        node.wait_for_line("ROS 2 transport: default: yours (FASTDDS_BUILTIN_TRANSPORTS is set)")
    finally:
        code, log = node.stop()
    assert code == 0, log


@pytest.mark.parametrize(
    "args, said",
    [
        (["--ros-transport", "udp"], "baxterface node: --ros-transport must be shm or default, not 'udp'"),
        (
            ["--ros-args", "-p", "transport:=udp"],
            "baxterface node: parameter transport must be shm or default, not 'udp'",
        ),
    ],
)
def test_a_bad_transport_is_one_line_and_status_2(ros2, args, said):
    result = baxterface("node", "--ros", "2", *args, env=ros2)
    assert result.code == 2
    assert result.err.strip() == said


def test_jpegs_are_made_only_for_a_subscriber_and_a_late_one_gets_the_still_face(ros2, monkeypatch):
    import numpy as np

    from baxterface_cli.ros import compressed
    from baxterface_cli.ros.connect import open_link
    from ros2_world import Heard

    made = []
    encode = compressed.jpeg
    monkeypatch.setattr(compressed, "jpeg", lambda frame: made.append(1) or encode(frame))
    link = open_link(2, "pytest_jpegs", anonymous=True)
    try:
        frames = compressed.CompressedFrames(link, "/jpeg_screen")
        face = np.zeros((60, 80, 3), np.uint8)
        face[20:40, 30:50] = (0, 0, 255)  # a red square on black
        frames.offer(face)  # nobody listens: kept, not encoded
        assert made == [] and frames.waiting is None
        viewer = Heard(link, "/jpeg_screen/compressed", "sensor_msgs/CompressedImage", latched=True)
        deadline = time.monotonic() + 60
        while viewer.count() == 0 and time.monotonic() < deadline:
            frames.tick(time.monotonic())  # as the node's loop does while the face is still
            time.sleep(0.05)
        got = viewer.wait_for(timeout=1)
        from PIL import Image

        shown = np.asarray(Image.open(io.BytesIO(bytes(got.data))).convert("RGB"))
        assert shown.shape == (60, 80, 3) and shown[30, 40, 0] > 200 and shown[5, 5].max() < 40
        assert len(made) == 1
        frames.close()
    finally:
        link.close()
