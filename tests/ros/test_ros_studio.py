"""The studio's presses on a real ROS master: published on the face node's display_chatter."""

from __future__ import annotations

import subprocess
import time

import pytest

from studio_server import running_studio

pytestmark = pytest.mark.ros


def echo_one(env, topic="/display_chatter"):
    """A real subscriber: `rostopic echo` of one message, started before anything is sent."""
    return subprocess.Popen(
        ["rostopic", "echo", "-n", "1", "-p", topic], env=env, stdout=subprocess.PIPE, text=True
    )


def test_presses_reach_display_chatter_once_switched_on(roscore, tmp_path):
    (tmp_path / "show.face").write_text("happy\n")
    with running_studio(tmp_path / "show.face", env=roscore) as studio:
        status, answer = studio.json("POST", "/api/robot", {"on": True})
        assert status == 200 and answer["on"] and answer["available"]
        echo = echo_one(roscore)
        deadline = time.monotonic() + 30
        while "1 listening" not in studio.json("POST", "/api/robot", {"on": True})[1]["status"]:
            assert time.monotonic() < deadline, "rostopic echo never subscribed"
            time.sleep(0.1)
        assert studio.json("POST", "/api/command", "look left in 0.4s")[0] == 200
        out, _ = echo.communicate(timeout=30)
        assert out.splitlines()[-1].endswith(",look left in 0.4s")
        # switched off, a press plays on the preview only
        assert studio.json("POST", "/api/robot", {"on": False})[1]["on"] is False
        echo = echo_one(roscore)
        time.sleep(1.0)
        assert studio.json("POST", "/api/command", "sad")[0] == 200
        time.sleep(1.0)
        echo.terminate()
        out, _ = echo.communicate(timeout=30)
        assert "sad" not in out


def test_with_no_master_the_switch_stays_off_and_says_why(tmp_path):
    import os

    env = dict(os.environ, ROS_MASTER_URI="http://127.0.0.1:9")
    (tmp_path / "show.face").write_text("happy\n")
    with running_studio(tmp_path / "show.face", env=env) as studio:
        status, answer = studio.json("POST", "/api/robot", {"on": True})
        assert status == 200 and answer["on"] is False
        assert "master" in answer["status"] and "127.0.0.1:9" in answer["status"]
        assert studio.json("POST", "/api/command", "happy")[0] == 200  # the preview plays on
