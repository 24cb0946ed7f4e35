"""Getting to ROS: a `Link` to ROS 1 or 2, and clear words where it is missing or its master is away."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, List, Sequence

if TYPE_CHECKING:
    from .link import Link

INSTALL_HINT = (
    "ROS 1 is not installed for this Python (rospy is needed). On a robot "
    "workstation, source /opt/ros/noetic/setup.bash first; on Debian, "
    "'apt-get install python3-rospy python3-sensor-msgs python3-std-msgs "
    "python3-genpy ros-core' and use /usr/bin/python3"
)


class RosUnavailable(Exception):
    """ROS cannot be used from here; the message says why and what to do."""


# Where ROS 1 puts rospy: Debian's packages, and a ROS distribution's own tree.
ROS_PYTHON_PATHS = ("/usr/lib/python3/dist-packages", "/opt/ros/noetic/lib/python3/dist-packages")
ROS2_FIRST_PYTHON = (3, 10)  # the first Python the rclpy wheels of the ros2 extra are built for


def importable_ros() -> List[int]:
    """The ROS versions whose client library (rospy, rclpy) this Python can import, not importing it."""
    from importlib.util import find_spec

    found = []
    for version, module in ((1, "rospy"), (2, "rclpy")):
        try:
            if find_spec(module) is not None:
                found.append(version)
        except (ImportError, ValueError):
            pass
    return found


def require_ros(version: int = 1) -> None:
    """ROS `version`'s client library (rospy, or rclpy with its message packages) importable."""
    if version == 2:
        return _require_rclpy()
    try:
        import rospy  # noqa: F401
    except ImportError as e:
        raise RosUnavailable(f"{_why_not_here()} ({e})") from None


def _require_rclpy() -> None:
    import sys

    try:
        import rclpy  # noqa: F401
        import sensor_msgs.msg  # noqa: F401
        import std_msgs.msg  # noqa: F401
    except ImportError as e:
        if sys.version_info < ROS2_FIRST_PYTHON:
            where = (
                "the ros2 extra brings it from PyPI for Python 3.10 and later (pip install "
                f"'baxterface[ros2]'), and this is Python {sys.version_info[0]}.{sys.version_info[1]}: "
                "source a ROS 2 install (source /opt/ros/jazzy/setup.bash), or use --ros 1"
            )
        else:
            where = (
                "pip install 'baxterface[ros2]', or source a ROS 2 install (source /opt/ros/jazzy/setup.bash)"
            )
        raise RosUnavailable(f"ROS 2 needs the 'rclpy' module and its messages: {where} ({e})") from None


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


def open_link(
    version: int,
    name: str,
    argv: Sequence[str] = (),
    anonymous: bool = False,
    node: bool = False,
    leaving: str = "done",
) -> Link:
    """Join ROS `version` (1 or 2) as node `name`; `argv` is the command line's ROS arguments.

    `anonymous` adds a unique suffix to the name (for tools of which several may run);
    `node` is for a long-running node that serves parameters (ROS 2's parameter services).
    The link is a context manager: `with open_link(...) as link:` leaves ROS at the block's end,
    giving `leaving` as the reason.
    Raises RosUnavailable (connect.py) when that ROS cannot be used from this Python, or when
    ROS 1's master does not answer.
    """
    require_ros(version)
    args: List[str] = [name, *argv]
    if version == 1:
        from .link_ros1 import RospyLink

        require_master()  # rospy would wait for one for ever

        return _leaving(RospyLink(name, args, anonymous), leaving)
    from .link_ros2 import RclpyLink
    from .transport import TransportError

    try:
        return _leaving(RclpyLink(name, args, anonymous, node), leaving)
    except TransportError as e:  # BAXTERFACE_ROS_TRANSPORT, or the node's parameter: one line to show
        raise RosUnavailable(str(e)) from None


def _leaving(link: Link, reason: str) -> Link:
    link.leaving = reason
    return link
