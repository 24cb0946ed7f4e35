"""The Link, on real rclpy: the one interface through which every ROS end of baxterface talks.

The ROS 2 tests run on loopback in a domain of this module's own (the `ros2`
fixture): a publisher in a process of its own, a subscriber here. The ROS 1
link is the one every test in test_ros.py goes through.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import pytest

from baxterface_cli.ros.connect import open_link
from baxterface_cli.ros.link import CHATTER, STATE, RosVersionError, ros_version
from conftest import ROOT, baxterface
from ros2_world import Heard

PUBLISHER = textwrap.dedent(
    """
    import sys, time
    from baxterface_cli.ros.connect import open_link
    with open_link(2, "talker", ["--ros-args", "-r", "display_chatter:=/elsewhere/chatter"]) as link:
        chatter = link.publisher("display_chatter", "std_msgs/String", queue=0)
        state = link.publisher("~state", "std_msgs/String", latched=True, queue=1)
        state.publish(data="kept for latecomers")
        while chatter.listeners() == 0:
            time.sleep(0.01)
        chatter.publish(data=sys.argv[1])
        assert chatter.wait_delivered(10.0)
        print(chatter.topic, state.topic, flush=True)
        sys.stdin.read()  # stays, its state latched, until the test closes its input
    """
)


@pytest.mark.parametrize(
    "command",
    [
        ["node", "--ros", "2"],
        ["send", "--ros", "2", "happy"],
        ["stream", "--ros", "2", "-e", "happy"],
        ["screen", "--ros", "2", "--no-browser", "--port", "0"],
    ],
    ids=lambda c: c[0],
)
def test_without_rclpy_the_ros2_commands_say_in_one_line_which_extra_brings_it(command, tmp_path):
    hidden = tmp_path / "rclpy"  # an rclpy that is not there, whatever this Python has
    hidden.mkdir()
    (hidden / "__init__.py").write_text("raise ImportError(\"No module named 'rclpy'\")\n", encoding="utf-8")
    env = dict(os.environ, PYTHONPATH=str(tmp_path))
    run = baxterface(*command, env=env)
    assert run.code == 1 and len(run.err.strip().splitlines()) == 1, run.err
    assert run.err.startswith(f"baxterface {command[0]}: ROS 2 needs the 'rclpy' module and its messages: ")
    assert "pip install 'baxterface[ros2]'" in run.err and "Traceback" not in run.err


def test_ros_version_is_the_one_given_else_a_sourced_ros_s_else_1(monkeypatch):
    monkeypatch.delenv("ROS_VERSION", raising=False)
    assert ros_version() == 1
    monkeypatch.setenv("ROS_VERSION", "2")  # what a sourced ROS 2 set-up exports
    assert (ros_version(), ros_version(1)) == (2, 1)
    with pytest.raises(RosVersionError, match="--ros must be 1 or 2, not 3"):
        ros_version(3)
    monkeypatch.setenv("ROS_VERSION", "two")
    with pytest.raises(RosVersionError, match="ROS_VERSION is 'two'"):
        ros_version()


@pytest.mark.ros2
@pytest.mark.xdist_group("ros2_link")
def test_a_message_crosses_from_a_process_of_its_own_and_a_latched_one_waits_for_latecomers(ros2):
    link = open_link(2, "listener", anonymous=True)
    talker = subprocess.Popen(
        [sys.executable, "-c", PUBLISHER, "happy; look 40 -20 in 0.5s"],
        cwd=str(ROOT),
        env=ros2,
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        heard = Heard(link, "/elsewhere/chatter", "std_msgs/String", keep=lambda m: m.data)
        assert heard.wait_for(timeout=30) == "happy; look 40 -20 in 0.5s"
        # The talker's names: its remapping applied, "~state" under the node's own name.
        assert talker.stdout.readline().split() == ["/elsewhere/chatter", "/talker/state"]
        # Subscribed only now, long after it was published: transient local keeps it.
        late = Heard(link, "/talker/state", "std_msgs/String", latched=True, keep=lambda m: m.data)
        assert late.wait_for(timeout=30) == "kept for latecomers"
    finally:
        talker.communicate("", timeout=30)
        link.close()
    assert talker.returncode == 0


@pytest.mark.ros2
@pytest.mark.xdist_group("ros2_link")
def test_parameters_names_and_types_through_the_link(ros2):
    argv = [
        "--ros-args",
        "-p",
        "fps:=20",
        "-p",
        "size:=1920x1200",
        "-p",
        "idle:=false",
        "-r",
        "__node:=face2",
    ]
    with open_link(2, "baxter_face", argv) as link:
        assert link.name == "/face2"
        assert (link.param("fps", 30.0), link.param("size", "x"), link.param("idle", True)) == (
            20,
            "1920x1200",
            False,
        )
        assert link.param("theme", "") == ""  # not given: the default
        assert (link.resolve(STATE), link.resolve(CHATTER)) == ("/face2/state", "/display_chatter")
        assert link.has("std_msgs/String") and link.has("sensor_msgs/Image")
        assert not link.has("baxter_core_msgs/HeadPanCommand")  # Baxter's own: not on PyPI
        assert link.ok()
    assert not link.ok()  # the block's end left ROS
