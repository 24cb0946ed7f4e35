"""`baxterface screen` refusing what it cannot do, each in one line, before it serves."""

from __future__ import annotations

import os
import socket
import sys

import pytest

from conftest import baxterface

NO_ROS = dict(os.environ, ROS_MASTER_URI="http://127.0.0.1:9")  # no master there, if rospy is


def test_ros_1_without_ros_here_says_why_in_one_line():
    run = baxterface("screen", "--ros", "1", "--no-browser", "--port", "0", env=NO_ROS)
    assert run.code == 1
    (line,) = run.err.splitlines()
    # rospy missing for this Python, or (where it is there) no master at the address given
    assert line.startswith("baxterface screen: ") and ("ROS" in line or "master" in line)


def test_any_other_ros_version_is_a_usage_error():
    run = baxterface("screen", "--ros", "3", "--no-browser")
    assert run.code == 2 and "--ros" in run.err and "3 is not in the range 1<=x<=2" in run.err


def test_a_bad_script_is_shown_where_it_is_and_nothing_is_served(tmp_path):
    (tmp_path / "bad.face").write_text("happy\nlook 40 -20 in 0.5s eas-in\n")
    run = baxterface("screen", str(tmp_path / "bad.face"), "--no-browser", "--port", "0")
    assert run.code == 1
    assert run.err.startswith(f"{tmp_path / 'bad.face'}:2:21: error: unknown easing 'eas-in'")


@pytest.mark.parametrize("token", ["short", "semi;colon-0123456789abcdef"])
def test_a_token_from_the_environment_must_be_long_and_fit_an_address(token):
    env = dict(os.environ, BAXTERFACE_TOKEN=token)
    run = baxterface("screen", "--host", "0.0.0.0", "--no-browser", "--port", "0", env=env)
    assert run.code == 1
    (line,) = run.err.splitlines()
    assert line.startswith("baxterface screen: BAXTERFACE_TOKEN must be at least 16 letters, digits")


def test_a_taken_port_gives_one_line():
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        run = baxterface("screen", "--no-browser", "--port", str(port))
    assert run.code == 1
    taken_line = f"baxterface screen: cannot serve on 127.0.0.1:{port}: Address already in use"
    assert run.err.splitlines() == [taken_line]


def test_a_missing_extra_gives_one_line(tmp_path):
    import subprocess

    code = (
        "import sys; sys.modules['starlette'] = None; from baxterface_cli.cli import main; main(['screen'])"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode == 1
    assert done.stderr.strip().splitlines() == [
        "baxterface screen: the screen needs the 'starlette' module: pip install 'baxterface[studio]'"
    ]
