"""`screen --ros 2`: display_chatter on real rclpy plays on the screen as POST /api/command does."""

from __future__ import annotations

from baxterface_cli.ros.connect import open_link
from studio_server import running_screen
from waiting import eventually


def test_display_chatter_on_ros_2_plays_on_the_screen_and_a_bad_command_is_logged(ros2, tmp_path):
    link = open_link(2, "pytest_screen_chatter", anonymous=True)
    chatter = link.publisher("/display_chatter", "std_msgs/String", queue=10)
    try:
        with running_screen(tmp_path, "--ros", "2", "--no-idle", env=ros2) as screen:
            assert "commands on display_chatter (ROS 2)" in screen.log()[0]
            eventually(lambda: chatter.listeners() > 0)  # the screen has found the topic
            chatter.publish(data="sad")
            eventually(lambda: screen.json("GET", "/api/state")[1]["face"]["emotion"] == "sad")
            chatter.publish(data="hapy")
            logged = eventually(lambda: [line for line in screen.log() if "hapy" in line])
            assert logged == [
                "baxterface screen: display_chatter: 400 1:1: unknown command 'hapy'; did you mean 'happy'?"
            ]
            chatter.publish(data="look_60_0_0")  # the old node's commands too
            eventually(lambda: screen.json("GET", "/api/state")[1]["face"]["eye_x"] == 60)
    finally:
        link.close()
