"""Getting to ROS: clear words when it is not installed or its master is not there."""

from __future__ import annotations

import os

INSTALL_HINT = (
    "ROS 1 is not installed for this Python (rospy and cv_bridge are needed). On a robot "
    "workstation, source /opt/ros/noetic/setup.bash first; on Debian, "
    "'apt-get install python3-rospy python3-cv-bridge python3-sensor-msgs python3-std-msgs "
    "python3-genpy ros-core' and use /usr/bin/python3"
)


class RosUnavailable(Exception):
    """ROS cannot be used from here; the message says why and what to do."""


# Where ROS 1 puts rospy: Debian's packages, and a ROS distribution's own tree.
ROS_PYTHON_PATHS = ("/usr/lib/python3/dist-packages", "/opt/ros/noetic/lib/python3/dist-packages")


def require_ros(images: bool = True) -> None:
    """rospy importable, and cv_bridge too for a command that sends `images`."""
    try:
        import rospy  # noqa: F401

        if images:
            import cv_bridge  # noqa: F401
    except ImportError as e:
        raise RosUnavailable(f"{_why_not_here()} ({e})") from None


def _why_not_here() -> str:
    """How to get a Python that sees ROS: the common case is a virtual environment that cannot."""
    import sys

    installed = [p for p in ROS_PYTHON_PATHS if os.path.isdir(os.path.join(p, "rospy"))]
    if installed and sys.prefix != sys.base_prefix:
        return (
            f"ROS is installed ({installed[0]}), but this virtual environment ({sys.prefix}) does not "
            "see it; 'make ros' makes .venv-ros, one that does: run .venv-ros/bin/baxterface, "
            "or make your own with 'python3 -m venv --system-site-packages'"
        )
    return INSTALL_HINT


def require_master(timeout: float = 3.0) -> None:
    """Fail fast, naming ROS_MASTER_URI, instead of rospy's endless wait for a master."""
    import socket

    import rosgraph

    uri = os.environ.get("ROS_MASTER_URI", "http://localhost:11311 (ROS_MASTER_URI is not set)")
    previous = socket.getdefaulttimeout()
    socket.setdefaulttimeout(timeout)
    try:
        online = rosgraph.is_master_online()
    except Exception:
        online = False
    finally:
        socket.setdefaulttimeout(previous)
    if not online:
        raise RosUnavailable(f"cannot reach the ROS master at ROS_MASTER_URI={uri}; is roscore running?")
