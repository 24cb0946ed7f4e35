"""Commands for the screen from ROS: `display_chatter`, heard as the face node hears it.

The one place the screen meets ROS (`screen --ros 1|2`). Each command heard
goes to `hand`, which plays it as `POST /api/command` does, through the
ROS link of either version (ros/link.py).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Callable

if TYPE_CHECKING:
    from ..ros.chatter import ChatterListener


def listen(version: int, topic: str, hand: Callable[[str], None]) -> ChatterListener:
    """Subscribe to `topic` on ROS `version`, each command to `hand`; returns the listener, which
    unsubscribes when closed (or at the end of a `with` block).

    RosUnavailable, with what to do, when that ROS cannot be reached from here.
    """
    from ..ros.chatter import ChatterListener

    return ChatterListener(topic, hand, version)
