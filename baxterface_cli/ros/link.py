"""One process's line to ROS, 1 or 2: the small interface every ROS end of baxterface goes through.

`connect.open_link(version, name)` joins ROS 1 (rospy, `link_ros1.py`) or ROS 2
(rclpy, `link_ros2.py`) as a node and returns a `Link`; the face node, `send`,
`stream`, the studio's robot switch and the benchmarks speak only to it, so
their behaviour is written once. Through it a process subscribes and
publishes by topic name and message type ("std_msgs/String"), reads its
node's parameters, logs, and shuts down:

    link = open_link(2, "baxterface_screen", anonymous=True)  # connect.open_link
    link.subscribe(CHATTER, "std_msgs/String", lambda msg: print(msg.data))
    link.spin()  # or your own loop; callbacks come on the link's own thread

Callbacks run on a thread of the link's (rospy's or the link's executor), so
they should hand the message over and return. Messages are the ROS version's
own objects; the fields baxterface uses have the same names in both.
"""

from __future__ import annotations

import math
import os
import sys
import time
from typing import Any, Callable, Optional

from ..closing import ClosedOnExit

VERSIONS = (1, 2)
# The face node's topics, in the spelling both versions take ("~" is the node's own).
CHATTER = "display_chatter"  # commands and scripts in (std_msgs/String)
QUEUE = "~queue"  # scripts that wait for what is playing
EVENT = "~event"  # events raised by hand (std_msgs/String, an events file's line without its time)
STATE = "~state"  # what the face is doing, as JSON, latched (transient local on ROS 2)
NODE_NAME = "baxter_face"


class RosVersionError(ValueError):
    """A ROS version other than 1 or 2."""


def ros_version(given: Optional[int] = None) -> int:
    """The ROS version to use: `given`, else the ROS_VERSION a sourced ROS set-up exports, else 1."""
    if given is None:
        exported = os.environ.get("ROS_VERSION", "").strip()
        if not exported:
            return 1
        if exported not in ("1", "2"):
            raise RosVersionError(f"ROS_VERSION is {exported!r}; --ros takes 1 or 2")
        return int(exported)
    if given not in VERSIONS:
        raise RosVersionError(f"--ros must be 1 or 2, not {given}")
    return given


class Publisher:
    """Publishes one topic's messages, built from their fields."""

    topic: str  # its resolved name

    def publish(self, **fields: Any) -> None:
        raise NotImplementedError

    def listeners(self) -> int:
        """How many subscribers are connected now."""
        raise NotImplementedError

    def wait_for_listener(self, most: float, least: float = 0.5) -> None:
        """Until anything subscribes (the screen, for a stream's first frames), at least `least`
        seconds and at most `most`: ROS 2 may take seconds to discover a new node."""
        start = time.monotonic()
        time.sleep(least)
        while self.listeners() == 0 and time.monotonic() < start + most:
            time.sleep(0.02)

    def wait_delivered(self, timeout: float) -> bool:
        """Wait until what was published has reached every subscriber (ROS 1: it has on return)."""
        return True

    def close(self) -> None:
        raise NotImplementedError


class Subscription:
    """A callback on a topic's messages, until closed."""

    topic: str

    def publishers(self) -> int:
        """How many publishers are connected now."""
        raise NotImplementedError

    def close(self) -> None:
        raise NotImplementedError


class Link(ClosedOnExit):
    """A node on ROS 1 or ROS 2. See the module's docstring, and docs/ros.md for the contract.

    A `with` block closes it, giving `leaving` as the reason (ROS 1 logs it; open_link sets it).
    """

    version: int
    name: str  # the node's full name, "/baxter_face"
    transport = ""  # ROS 2: how frames travel, in words for the log (transport.py)
    leaving = "done"  # why the node leaves ROS when a `with` block closes the link

    def resolve(self, topic: str) -> str:
        """A topic's full name, remappings applied ("~state" -> "/baxter_face/state")."""
        raise NotImplementedError

    def param(self, name: str, default: Any) -> Any:
        """The node's own parameter `name` (ROS 1: `~name`), or `default` when it is not set."""
        raise NotImplementedError

    def has(self, kind: str) -> bool:
        """Whether messages of type `kind` ("baxter_core_msgs/HeadPanCommand") can be used here."""
        raise NotImplementedError

    def publisher(self, topic: str, kind: str, latched: bool = False, queue: int = 10) -> Publisher:
        """A publisher; `latched` keeps the last message for subscribers that come later
        (ROS 1 latching, ROS 2 transient-local durability)."""
        raise NotImplementedError

    def subscribe(
        self,
        topic: str,
        kind: str,
        callback: Callable[[Any], None],
        queue: int = 10,
        latched: bool = False,
        sensor: bool = False,
    ) -> Subscription:
        """Call `callback(message)` for each message. `latched` also takes the last one published
        before (ROS 2: transient local); `sensor` is for large sensor streams such as camera
        images: only the newest is kept, and ROS 2's best-effort publishers are heard too."""
        raise NotImplementedError

    def log(self, level: str, text: str, every: float = 0.0) -> None:
        """Log `text` at `level` ("info", "warn" or "error"); with `every`, a line from the
        same place of the caller's code at most once in `every` seconds (as rospy's throttle)."""
        if every > 0:
            caller = sys._getframe(1)
            place = (caller.f_code.co_filename, caller.f_lineno)
            now = time.monotonic()
            throttled = self.__dict__.setdefault("_last_logged", {})
            if now < throttled.get(place, -math.inf) + every:
                return
            throttled[place] = now
        self._emit(level, text)

    def _emit(self, level: str, text: str) -> None:
        raise NotImplementedError

    def stay_connected(self, info: Callable[[str], None]) -> None:
        """Keep this node reachable while it runs (ROS 1: register again with a restarted master,
        saying so through `info`; ROS 2 needs nothing: discovery is between the nodes)."""

    def forget_bad(self, name: str) -> Optional[str]:
        """After parameter `name` was refused: what the user must do about a value that outlives
        this run (ROS 1's parameter server), or None. A value this run put there is taken off."""
        return None

    def ok(self) -> bool:
        """False once the link is shut down."""
        raise NotImplementedError

    def spin(self) -> None:
        """Block until the link is shut down (Ctrl-C raises KeyboardInterrupt here)."""
        raise NotImplementedError

    def close(self, reason: str = "done") -> None:
        """Leave ROS: publishers, subscriptions and the node go."""
        raise NotImplementedError

    def __exit__(self, kind: Any, error: Any, trace: Any) -> None:
        self.close(self.leaving)
