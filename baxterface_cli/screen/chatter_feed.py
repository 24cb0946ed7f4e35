"""Commands for the screen from ROS: `display_chatter`, heard as the face node hears it.

The one place the screen meets ROS (`screen --ros 1|2`). Each command heard
goes to `hand`, which plays it as `POST /api/command` does. ROS 1 goes
through ros/chatter.py; ROS 2 plugs in here, in `listen`, once the ROS 2
link is there.
"""

from __future__ import annotations

from typing import Callable

from ..ros.connect import RosUnavailable

VERSIONS = (1, 2)
ROS2_NOT_YET = (
    "ROS 2 for the screen needs the ROS 2 link, which this baxterface does not have yet; "
    "use --ros 1, or send commands to POST /api/command"
)


def listen(version: int, topic: str, hand: Callable[[str], None]) -> Callable[[], None]:
    """Subscribe to `topic` on ROS `version`, each command to `hand`; returns what unsubscribes.

    RosUnavailable, with what to do, when that ROS cannot be reached from here.
    """
    if version not in VERSIONS:
        raise RosUnavailable(f"--ros takes 1 or 2, not {version}")
    if version == 2:
        raise RosUnavailable(ROS2_NOT_YET)
    from ..ros.connect import require_master, require_ros

    require_ros(images=False)
    require_master()
    from ..ros.chatter import ChatterListener

    return ChatterListener(topic, hand).close
