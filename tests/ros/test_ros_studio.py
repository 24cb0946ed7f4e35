"""The studio's presses on a real ROS master: published on the face node's display_chatter."""

from __future__ import annotations

import subprocess
import time

import pytest

from studio_server import running_studio
from waiting import PATIENCE

pytestmark = pytest.mark.ros


def echo_all(env, out, topic="/display_chatter"):
    """A real subscriber: `rostopic echo` of every message into the file `out`, until stopped."""
    return subprocess.Popen(["rostopic", "echo", "-p", topic], env=env, stdout=out, text=True)


def pressed_until_heard(studio, command, heard, deadline):
    """Press `command` until the echo has it: a ROS 1 subscriber counted as listening may not be
    connected yet, and a message sent before it is is not queued for it (a busy machine's case)."""
    while command not in heard.read_text():
        assert time.monotonic() < deadline, f"{command!r} never reached display_chatter"
        assert studio.json("POST", "/api/command", command)[0] == 200
        time.sleep(0.5)


def test_presses_reach_display_chatter_once_switched_on(roscore, tmp_path):
    (tmp_path / "show.face").write_text("happy\n")
    heard = tmp_path / "heard.txt"
    with running_studio(tmp_path / "show.face", env=roscore) as studio, open(heard, "w") as out:
        status, answer = studio.json("POST", "/api/robot", {"on": True})
        assert status == 200 and answer["on"] and answer["available"]
        echo = echo_all(roscore, out)
        try:
            deadline = time.monotonic() + PATIENCE
            while "1 listening" not in studio.json("POST", "/api/robot", {"on": True})[1]["status"]:
                assert time.monotonic() < deadline, "rostopic echo never subscribed"
                time.sleep(0.1)
            pressed_until_heard(studio, "look left in 0.4s", heard, deadline)
            # Switched off, a press plays on the preview only: switched on again, the next press
            # reaches the echo after it, in order, and the one pressed while off never does.
            assert studio.json("POST", "/api/robot", {"on": False})[1]["on"] is False
            assert studio.json("POST", "/api/command", "sad")[0] == 200
            assert studio.json("POST", "/api/robot", {"on": True})[1]["on"] is True
            pressed_until_heard(studio, "happy", heard, time.monotonic() + PATIENCE)
        finally:
            echo.terminate()
            echo.wait(timeout=30)
    assert "sad" not in heard.read_text()


def test_with_no_master_the_switch_stays_off_and_says_why(tmp_path):
    import os

    env = dict(os.environ, ROS_MASTER_URI="http://127.0.0.1:9")
    (tmp_path / "show.face").write_text("happy\n")
    with running_studio(tmp_path / "show.face", env=env) as studio:
        status, answer = studio.json("POST", "/api/robot", {"on": True})
        assert status == 200 and answer["on"] is False
        assert "master" in answer["status"] and "127.0.0.1:9" in answer["status"]
        assert studio.json("POST", "/api/command", "happy")[0] == 200  # the preview plays on
