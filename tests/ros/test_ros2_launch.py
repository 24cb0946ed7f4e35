"""The ROS 2 launch file starts the face node with its arguments as the node's parameters.

`ros2 launch` (launch and launch_ros) is neither on PyPI nor in Debian 12, so
the file is run here as launch_ros runs it, by stand-ins for the four names it
uses, which do what launch_ros's own code does with them (launch_ros
actions/node.py and utilities/evaluate_parameters.py): the Node becomes
`EXECUTABLE ARGUMENTS --ros-args -r __node:=NAME --params-file FILE`, its
parameters written to FILE under the node's name, each argument's text read as
YAML. That command then runs for real, on rclpy, and must answer with those settings.
"""

from __future__ import annotations

import json
import runpy
import shutil
import signal
import subprocess
import sys
import types
from pathlib import Path

import pytest

from baxterface_cli.ros.connect import open_link
from conftest import ROOT
from ros2_world import Heard

pytestmark = pytest.mark.ros2
LAUNCH_FILE = ROOT / "ros" / "baxter_face" / "launch" / "baxter_face.launch.py"


class LaunchConfiguration:
    def __init__(self, name):
        self.name = name


class DeclareLaunchArgument:
    def __init__(self, name, default_value=None, description=""):
        self.name, self.default_value, self.description = name, default_value, description


class Node:
    def __init__(self, executable, arguments=(), name=None, parameters=(), output=None, on_exit=None):
        self.executable, self.arguments, self.name = executable, list(arguments), name
        self.parameters, self.on_exit = list(parameters), on_exit


class Shutdown:
    pass


def stand_ins():
    modules = {}
    for name, members in {
        "launch": {"LaunchDescription": list},
        "launch.actions": {"DeclareLaunchArgument": DeclareLaunchArgument, "Shutdown": Shutdown},
        "launch.substitutions": {"LaunchConfiguration": LaunchConfiguration},
        "launch_ros": {},
        "launch_ros.actions": {"Node": Node},
    }.items():
        module = types.ModuleType(name)
        module.__dict__.update(members)
        modules[name] = module
    return modules


def launched_command(given, folder):
    """What `ros2 launch baxter_face.launch.py NAME:=VALUE...` would run."""
    saved = {name: sys.modules.get(name) for name in stand_ins()}
    sys.modules.update(stand_ins())
    try:
        description = runpy.run_path(str(LAUNCH_FILE))["generate_launch_description"]()
    finally:
        for name, module in saved.items():
            if module is None:
                sys.modules.pop(name, None)
            else:
                sys.modules[name] = module
    arguments = {a.name: a.default_value for a in description if isinstance(a, DeclareLaunchArgument)}
    unknown = set(given) - set(arguments)
    assert not unknown, f"the launch file has no argument {unknown}"
    arguments.update(given)
    (node,) = [a for a in description if isinstance(a, Node)]
    assert isinstance(node.on_exit, Shutdown)  # the launch ends with its node
    import yaml  # PyYAML comes with rclpy: not on Python 3.8, where this module is skipped

    values = {}
    for params in node.parameters:
        for name, value in params.items():
            text = arguments[value.name] if isinstance(value, LaunchConfiguration) else str(value)
            values[name] = yaml.safe_load(text or "''")  # launch_ros reads each as YAML, '' as ''
    params_file = folder / "launch_params.yaml"
    params_file.write_text(yaml.dump({f"/{node.name}": {"ros__parameters": values}}), encoding="utf-8")
    executable = shutil.which(node.executable, path=str(Path(sys.executable).parent))
    assert executable, f"{node.executable} is not installed beside {sys.executable}"
    ros_args = ["--ros-args", "-r", f"__node:={node.name}", "--params-file", str(params_file)]
    return [executable, *node.arguments, *ros_args], values


def test_without_recordings_the_launched_node_reads_none(ros2, tmp_path):
    _, values = launched_command({}, tmp_path)
    assert values["recordings"] == "" and values["camera_hfov"] == "" and values["face_policy"] == "nearest"


def test_the_launch_file_starts_the_node_with_its_arguments_as_parameters(ros2, tmp_path):
    recordings = tmp_path / "recordings"
    recordings.mkdir()
    shutil.copy(ROOT / "scripts_examples" / "greeting.ogg", recordings / "greeting.ogg")
    given = {"fps": "20", "size": "512x300", "selftest": "false", "idle": "false", "camera_hfov": "60"}
    given.update(audio="none", recordings=str(recordings))
    command, values = launched_command(given, tmp_path)
    assert values["fps"] == 20 and values["idle"] is False and values["theme"] == ""
    link = open_link(2, "pytest_launch", anonymous=True)
    state = Heard(
        link, "/baxter_face/state", "std_msgs/String", latched=True, keep=lambda m: json.loads(m.data)
    )
    frames = Heard(
        link, "/robot/xdisplay", "sensor_msgs/Image", latched=True, keep=lambda m: (m.width, m.height)
    )
    node = subprocess.Popen(
        command, cwd=str(tmp_path), env=ros2, stdout=subprocess.PIPE, stderr=subprocess.STDOUT
    )
    try:
        assert state.wait_for(timeout=60)["emotion"] == "sleep"  # selftest:=false: asleep at once
        assert frames.wait_for() == (512, 300)
        chatter = link.publisher("/display_chatter", "std_msgs/String")
        while chatter.listeners() == 0:
            assert node.poll() is None
        chatter.publish(data="happy")
        state.wait_for(lambda r: r["emotion"] == "happy")
        chatter.publish(data='say file "greeting.ogg"')  # read from recordings:=FOLDER, and only there
        state.wait_for(lambda r: r["saying"] == "greeting.ogg")
    finally:
        node.send_signal(signal.SIGINT)
        out = node.communicate(timeout=30)[0].decode()
        link.close()
    assert node.returncode == 0 and "Traceback" not in out, out
