"""The face on a ROS 2 robot's screen: ros2 launch ros/baxter_face/launch/baxter_face.launch.py

The ROS 2 twin of baxter_face.launch: the same arguments, given as
`name:=value` (`ros2 launch ... fps:=20 size:=1920x1200`), become the node's
parameters. It runs `baxterface node --ros 2` from PATH (pip install
'baxterface[ros2]', or baxterface beside a sourced ROS 2), so it needs no
colcon package: launch it by its path.
"""

from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, Shutdown
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node

# name, default, what it is: the node's parameters (docs/ros.md)
ARGUMENTS = [
    ("fps", "30", "most frames a second"),
    ("size", "1024x600", "the screen's size"),
    ("theme", "", "a theme folder; empty for the default theme"),
    ("idle", "true", "idle blinks and eye darts"),
    ("selftest", "true", "flash every layer at start, as the original did"),
    ("display_topic", "/robot/xdisplay", "where the frames go (sensor_msgs/Image, bgr8)"),
    ("audio", "local", "where `say` is heard: local (this machine's sound device) or none"),
    ("camera", "/cameras/head_camera/image", "the sensor_msgs/Image topic `follow face` looks through"),
    (
        "camera_hfov",
        "",
        "that camera's horizontal field of view in degrees; empty: its camera_info's, else 76",
    ),
    ("face_policy", "nearest", "which face `follow face` follows among several: nearest, central or longest"),
    ("recordings", "", "the folder `say file` reads recordings from; empty: none is read"),
    ("face_seen_after", "0.2", "seconds a face is found in the head camera before `face seen`"),
    ("face_lost_after", "0.8", "seconds unseen before `face lost`"),
    ("person_near", "1.0", "metres from the head sonar that make `person near`"),
    ("listen", "", "words for `on word`: default (the microphone), a WAV file's path, or empty: none"),
    ("barge_in", "false", "hear words while the face speaks"),
    ("script", "", "a script file the face plays once it is up, after its selftest; empty: none"),
    ("log", "", "a file for the session's record (JSON Lines: docs/session-log.md); empty: none"),
    ("log_size", "100", "megabytes the log grows to before it is rotated"),
    ("transport", "shm", "how frames reach this host's peers: shm (shared memory, UDP beside it) or default"),
]


def generate_launch_description():
    declared = [
        DeclareLaunchArgument(name, default_value=value, description=about)
        for name, value, about in ARGUMENTS
    ]
    face = Node(
        executable="baxterface",
        arguments=["node", "--ros", "2"],
        name="baxter_face",
        output="screen",
        on_exit=Shutdown(),  # `exit`, Ctrl-C: the launch ends with its node, as ROS 1's required="true"
        parameters=[{name: LaunchConfiguration(name) for name, _, _ in ARGUMENTS}],
    )
    return LaunchDescription([*declared, face])
