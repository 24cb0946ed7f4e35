"""`screen --ros 1`: display_chatter on a real ROS master plays on the screen as POST /api/command does."""

from __future__ import annotations

import signal
import subprocess

import pytest

from studio_server import running_screen
from waiting import eventually

pytestmark = pytest.mark.ros


def publish(env, text, topic="/display_chatter"):
    """`rostopic pub -1`: latched for a few seconds, so a subscriber that is just connecting hears it."""
    subprocess.run(
        ["rostopic", "pub", "-1", topic, "std_msgs/String", f"data: '{text}'"],
        env=env,
        check=True,
        timeout=60,
        stdout=subprocess.DEVNULL,
    )


def test_display_chatter_plays_on_the_screen_and_a_bad_command_is_logged(roscore, tmp_path):
    with running_screen(tmp_path, "--ros", "1", "--no-idle", env=roscore) as screen:
        assert "commands on display_chatter (ROS 1)" in screen.log()[0]
        publish(roscore, "sad")
        eventually(lambda: screen.json("GET", "/api/state")[1]["face"]["emotion"] == "sad")
        publish(roscore, "hapy")
        logged = eventually(lambda: [line for line in screen.log() if "hapy" in line])
        assert logged == [
            "baxterface screen: display_chatter: 400 1:1: unknown command 'hapy'; did you mean 'happy'?"
        ]
        publish(roscore, "look_60_0_0")  # the old node's commands too, and it still takes them
        eventually(lambda: screen.json("GET", "/api/state")[1]["face"]["eye_x"] == 60)
        assert screen.json("POST", "/api/command", "happy")[0] == 200  # and HTTP beside ROS
        eventually(lambda: screen.json("GET", "/api/state")[1]["face"]["emotion"] == "happy")
        # It stops on SIGTERM while commands keep coming.
        flood = subprocess.Popen(
            ["rostopic", "pub", "-r", "50", "/display_chatter", "std_msgs/String", "data: 'look left in 2s'"],
            env=roscore,
            stdout=subprocess.DEVNULL,
        )
        try:
            eventually(lambda: screen.json("GET", "/api/state")[1]["face"]["eye_x"] > 0)  # the flood plays
            assert screen.stop(signal.SIGTERM) == 128 + signal.SIGTERM
        finally:
            flood.terminate()
            flood.wait(timeout=30)
        assert screen.log()[-1] == "baxterface screen: stopped"
