"""The ROS 2 face node reacts as the ROS 1 node does: handlers sent on display_chatter install
themselves and `signal NAME` sent there runs them (marker `ros2`)."""

from __future__ import annotations

import json

import pytest
from test_ros2_node import NodeProcess, chatter

from baxterface_cli.ros.connect import open_link
from ros2_world import Heard

pytestmark = [pytest.mark.ros2, pytest.mark.xdist_group("ros2_node")]


def runs(record, line):
    return next((c["runs"] for label, c in record.get("handlers", {}).items() if label.startswith(line)), 0)


def test_a_handler_sent_to_the_ros2_node_runs_on_a_signal_and_a_second_one_replaces_it(ros2):
    link = open_link(2, "pytest_reacting", anonymous=True)
    state = Heard(
        link, "/baxter_face/state", "std_msgs/String", latched=True, keep=lambda m: json.loads(m.data)
    )
    node = NodeProcess(ros2, "--ros-args", "-p", "idle:=false", "-p", "audio:=none")
    try:
        state.wait_for(timeout=60)
        commands = chatter(link)
        commands.publish(data="on signal poke { sad }\non signal cheer { happy }")
        state.wait_for(lambda r: len(r.get("handlers", {})) == 2)
        commands.publish(data="on signal poke { angry }")  # replaces the first `on signal poke`
        state.wait_for(
            lambda r: (
                any(label.startswith("line 1 'on signal poke'") for label in r["handlers"])
                and len(r["handlers"]) == 2
                and "line 2 'on signal cheer'" in r["handlers"]
            )
        )
        seen = state.count()
        commands.publish(data="signal poke")
        # The face may show the handler's first step a moment before the counts say it ran.
        shown = state.wait_for(
            lambda r: r["emotion"] == "angry" and runs(r, "line 1 'on signal poke'") >= 1, after=seen
        )
        assert runs(shown, "line 1 'on signal poke'") == 1
        commands.close()
    finally:
        code, out = node.stop()
        link.close()
    assert code == 0 and "Traceback" not in out, out
