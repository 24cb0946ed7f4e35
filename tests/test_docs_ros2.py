"""The docs' ROS 2 examples: each `--ros 2` command and each Link program, on real rclpy.

On loopback, in a domain of this module's own; a face node of the docs'
own answers the commands that need one.
"""

from __future__ import annotations

import contextlib
import json
import queue
import shlex
import signal
import subprocess
import sys
import threading
import time

import pytest
from test_docs import console_examples, doc_env, matches

from baxterface_cli.ros.connect import open_link
from conftest import ROOT
from doc_blocks import python_examples
from ros2_world import Heard

pytestmark = [pytest.mark.ros2, pytest.mark.xdist_group("docs_ros2")]

COMMANDS = [e for e in console_examples() if "--ros 2" in e[1]]
LINKS = [e for e in python_examples() if "open_link(" in e.code]
RCLPY = [e for e in python_examples() if "import rclpy" in e.code]


def test_the_ros2_examples_are_found():
    assert any(c.startswith("baxterface node --ros 2") for _, c, _ in COMMANDS)
    assert any(c.startswith("baxterface send --ros 2") for _, c, _ in COMMANDS)
    assert any(e.doc == "ros.md" for e in LINKS)
    assert any(e.doc == "ros.md" and e.expected for e in RCLPY)


@pytest.fixture(scope="module")
def docs_world(ros2):
    env = dict(doc_env(), **{k: ros2[k] for k in ("ROS_DOMAIN_ID", "ROS_AUTOMATIC_DISCOVERY_RANGE")})
    link = open_link(2, "pytest_docs", anonymous=True)
    yield env, link
    link.close()


def state_of(link, topic="/baxter_face/state"):
    return Heard(link, topic, "std_msgs/String", latched=True, keep=lambda m: json.loads(m.data))


def running_node(env, *args):
    return subprocess.Popen(
        ["baxterface", "node", "--ros", "2", *args], cwd=str(ROOT), env=env, stdout=subprocess.DEVNULL
    )


def stopped(proc):
    proc.send_signal(signal.SIGINT)
    return proc.wait(timeout=60)


@pytest.mark.parametrize("doc, command, expected", COMMANDS, ids=[f"{e[0]}: {e[1]}" for e in COMMANDS])
def test_ros2_console_examples_do_what_the_docs_show(docs_world, doc, command, expected):
    env, link = docs_world
    state = state_of(link)
    if command.startswith("baxterface node"):  # runs until stopped: it must come up and answer
        proc = subprocess.Popen(shlex.split(command), cwd=str(ROOT), env=env)
        try:
            state.wait_for(timeout=60)
        finally:
            assert stopped(proc) == 0
            state.close()
        return
    node = running_node(env, "--ros-args", "-p", "idle:=false")
    try:
        state.wait_for(timeout=60)
        run = subprocess.run(
            command, shell=True, cwd=str(ROOT), env=env, capture_output=True, text=True, timeout=120
        )
        printed = (run.stdout + run.stderr).strip("\n").splitlines()
        assert run.returncode == 0 and matches(expected, printed), printed
    finally:
        assert stopped(node) == 0
        state.close()


@pytest.mark.parametrize("example", LINKS, ids=[f"{e.doc}: python {e.number}" for e in LINKS])
def test_link_examples_hear_what_the_docs_say(docs_world, example, tmp_path):
    env, link = docs_world
    program = tmp_path / "example.py"
    program.write_text(example.code, encoding="utf-8")
    listener = subprocess.Popen(
        [sys.executable, str(program)], cwd=str(tmp_path), env=env, stdout=subprocess.PIPE, text=True
    )
    lines: queue.Queue = queue.Queue()
    threading.Thread(target=lambda: [lines.put(line) for line in listener.stdout], daemon=True).start()
    try:
        chatter = link.publisher("/display_chatter", "std_msgs/String")
        deadline = time.monotonic() + 60
        heard = None
        while heard is None:
            assert listener.poll() is None and time.monotonic() < deadline, "the example heard nothing"
            if chatter.listeners():
                # What the doc says `baxterface send --ros 2 happy` does; again until heard, for
                # DDS may still be joining the two ends when the first goes.
                chatter.publish(data="happy")
            with contextlib.suppress(queue.Empty):
                heard = lines.get(timeout=0.5)
        assert heard.strip() == "command: happy"
    finally:
        listener.send_signal(signal.SIGINT)
        listener.communicate(timeout=30)
    assert listener.returncode == 0


@pytest.mark.parametrize("example", RCLPY, ids=[f"{e.doc}: python {e.number}" for e in RCLPY])
def test_rclpy_examples_talk_to_a_face_node_as_the_docs_show(docs_world, example, tmp_path):
    env, link = docs_world
    program = tmp_path / "example.py"
    program.write_text(example.code, encoding="utf-8")
    state = state_of(link)
    node = running_node(env, "--ros-args", "-p", "idle:=false")
    try:
        state.wait_for(timeout=60)
        run = subprocess.run(
            [sys.executable, str(program)],
            cwd=str(tmp_path),
            env=env,
            capture_output=True,
            text=True,
            timeout=120,
        )
    finally:
        assert stopped(node) == 0
        state.close()
    assert run.returncode == 0, run.stderr
    assert matches(example.expected, run.stdout.rstrip("\n").splitlines()), run.stdout
