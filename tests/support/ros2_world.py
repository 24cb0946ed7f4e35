"""ROS 2 for the tests: a domain of each module's own on loopback, and ears on topics through a Link.

Every module that starts ROS 2 processes names its domain here, so that
pytest-xdist workers running two modules at once never meet; a domain that
another program on this machine already uses (its first participant's
discovery port is taken) gives way to a spare one.
"""

from __future__ import annotations

import os
import socket
import threading
import time
from typing import Any, Callable, Dict, List, Optional, Tuple

from waiting import PATIENCE

# module file name -> its ROS domain id (0 to 101 keep clear of Linux's ephemeral ports)
DOMAINS = {
    "test_link.py": 41,
    "test_ros2_node.py": 42,
    "test_ros2_speech.py": 43,
    "test_docs_ros2.py": 44,
    "test_ros2_launch.py": 45,
    "test_screen_ros2.py": 46,
    "test_ros2_transport.py": 47,
    "test_ros2_reacting.py": 48,
}
SPARE = range(60, 100)


def domain_is_free(domain: int) -> bool:
    """Whether no participant of `domain` runs here: its participant 0's discovery port is free."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        try:
            s.bind(("0.0.0.0", 7400 + 250 * domain + 10))
        except OSError:
            return False
    return True


def domain_for(module_file: str) -> int:
    if module_file not in DOMAINS:
        raise LookupError(f"give {module_file} a ROS domain of its own in tests/support/ros2_world.py")
    for domain in (DOMAINS[module_file], *SPARE):
        if domain_is_free(domain):
            return domain
    raise RuntimeError("no free ROS domain on this machine")


def loopback_env(domain: int, base: Optional[Dict[str, str]] = None) -> Dict[str, str]:
    env = dict(base if base is not None else os.environ)
    env.update(ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST")
    # Fast DDS as baxterface sets it up by default (transport.py: shm), whatever the caller's shell has
    theirs = ("FASTRTPS_DEFAULT_PROFILES_FILE", "FASTDDS_DEFAULT_PROFILES_FILE", "FASTDDS_BUILTIN_TRANSPORTS")
    for other in ("ROS_LOCALHOST_ONLY", "ROS_STATIC_PEERS", "BAXTERFACE_ROS_TRANSPORT", *theirs):
        env.pop(other, None)
    return env


class Heard:
    """Every message on a topic since this started listening, through a Link (ROS 1 or 2)."""

    def __init__(self, link: Any, topic: str, kind: str, latched: bool = False, keep: Callable = lambda m: m):
        self.messages: List[Tuple[float, Any]] = []
        self.arrived = threading.Condition()
        self.keep = keep  # what to keep of each message (a frame's few bytes, say)
        self.topic = topic
        self.sub = link.subscribe(topic, kind, self._got, queue=100, latched=latched)

    def _got(self, msg: Any) -> None:
        kept = self.keep(msg)
        with self.arrived:
            self.messages.append((time.monotonic(), kept))
            self.arrived.notify_all()

    def wait_for(
        self, test: Callable[[Any], bool] = lambda m: True, timeout: float = PATIENCE, after: int = 0
    ):
        """The first message (from index `after`) passing `test`."""
        deadline = time.monotonic() + timeout
        with self.arrived:
            while True:
                for _, msg in self.messages[after:]:
                    if test(msg):
                        return msg
                left = deadline - time.monotonic()
                last = self.messages[-1:]
                assert left > 0, f"nothing such on {self.topic} ({len(self.messages)} seen, the last {last})"
                self.arrived.wait(left)

    def count(self) -> int:
        with self.arrived:
            return len(self.messages)

    def close(self) -> None:
        self.sub.close()
