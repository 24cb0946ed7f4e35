"""Both launch files give the node every setting it has, and docs/ros.md documents each argument.

Read without ROS: ROS 1's roslaunch XML with ElementTree, ROS 2's Python file's ARGUMENTS table
by its syntax tree (it imports launch_ros, which neither PyPI nor Debian 12 has).
"""

from __future__ import annotations

import ast
import dataclasses
import re
import xml.etree.ElementTree as ET

from baxterface_cli.ros.node_settings import NodeSettings
from conftest import ROOT

LAUNCH = ROOT / "ros" / "baxter_face" / "launch"
DOC = (ROOT / "docs" / "ros.md").read_text(encoding="utf-8")
SETTINGS = {field.name for field in dataclasses.fields(NodeSettings)}
OWN = {"buttons", "mapping"}  # ROS 1's launch file's own: the navigator buttons beside the node
# ROS 2's own: Fast DDS's transport, read from the parameters before the node joins ROS (transport.py)
OWN2 = {"transport"}


def ros1_launch():
    """(its arguments and their defaults, the face node's params as {name: the argument it takes})."""
    root = ET.parse(str(LAUNCH / "baxter_face.launch")).getroot()
    arguments = {arg.get("name"): arg.get("default") for arg in root.findall("arg")}
    (node,) = [n for n in root.findall("node") if n.get("type") == "baxterface_node"]
    params = {}
    for param in node.findall("param"):
        taken = re.fullmatch(r"\$\(arg (\w+)\)", param.get("value", ""))
        params[param.get("name")] = taken.group(1) if taken else None
    return arguments, params


def ros2_launch():
    """The ROS 2 launch file's ARGUMENTS: {name: default}."""
    tree = ast.parse((LAUNCH / "baxter_face.launch.py").read_text(encoding="utf-8"))
    (table,) = [
        node.value for node in tree.body if isinstance(node, ast.Assign) and node.targets[0].id == "ARGUMENTS"
    ]
    return {name: default for name, default, _ in ast.literal_eval(table)}


def documented_arguments():
    """The rows of docs/ros.md's launch arguments table: {name: (ROS 1 default, ROS 2 default)}."""
    section = DOC.split("## `roslaunch baxter_face baxter_face.launch`", 1)[1].split("\n## ", 1)[0]
    rows = re.findall(r"^\| `(\w+)` \| ([^|]+) \| ([^|]+) \|", section, re.M)
    return {name: (one.strip(), two.strip()) for name, one, two in rows}


def test_the_ros1_launch_file_passes_every_setting_of_the_node_from_an_argument_of_its_name():
    arguments, params = ros1_launch()
    assert set(params) == SETTINGS
    assert all(params[name] == name for name in params)
    assert set(arguments) == SETTINGS | OWN


def test_the_ros2_launch_file_declares_every_setting_of_the_node():
    assert set(ros2_launch()) == SETTINGS | OWN2


def test_every_launch_argument_is_in_the_docs_table_with_its_defaults():
    documented = documented_arguments()
    ros1, ros2 = ros1_launch()[0], ros2_launch()
    assert set(documented) == set(ros1) | set(ros2)
    for name, (one, two) in documented.items():
        for default, shown in ((ros1.get(name), one), (ros2.get(name), two)):
            if default is None:
                assert shown == "-", name
            elif default == "":
                assert shown.startswith("(empty"), name
            else:
                assert shown.strip("*") == default, name


def test_the_node_parameter_tables_name_every_setting():
    ros1_rows = set(re.findall(r"^\| `_(\w+)` \|", DOC, re.M))
    ros2_section = DOC.split("### Topics and parameters", 1)[1].split("\n### ", 1)[0]
    ros2_rows = set(re.findall(r"^\| `(\w+)` \|", ros2_section, re.M))
    assert ros1_rows == SETTINGS and ros2_rows == SETTINGS | OWN2
