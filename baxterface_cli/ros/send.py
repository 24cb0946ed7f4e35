"""`baxterface send`: a face node's command topic; and the wait for the screen `stream` draws on."""

from __future__ import annotations

import time
from typing import Any, List

from .connect import open_link

DELIVERY = 5.0  # seconds a message may take to reach every listener before `send` moves on
CONNECT = 5.0  # seconds `stream` on ROS 2 waits for the screen to subscribe before it plays anyway


class NoSubscriber(Exception):
    pass


class Sender:
    """One connection to a face node's command topic, for one message or many.

    Nothing waits a fixed time for a message to leave: on ROS 1, when `send`
    returns the message is in the listeners' sockets (publishing without a
    queue); on ROS 2 every message is kept until the listeners acknowledge it,
    which leaving the `with` block waits for.
    """

    def __init__(self, topic: str, timeout: float, argv: List[str], version: int = 1) -> None:
        self.link = open_link(version, "baxterface_send", argv, anonymous=True)
        self.timeout = timeout
        self.publisher = self.link.publisher(topic, "std_msgs/String", queue=0)
        self.topic = self.publisher.topic

    def __enter__(self) -> Sender:
        return self

    def __exit__(self, *exc: object) -> None:
        self.publisher.wait_delivered(DELIVERY)  # ROS 2: what was sent reaches them before we leave
        self.publisher.close()
        self.link.close("sent")

    def send(self, text: str) -> int:
        """Publish `text` once something listens; how many listeners it reached."""
        deadline = time.monotonic() + self.timeout
        while self.publisher.listeners() == 0:
            if time.monotonic() > deadline:
                raise NoSubscriber(f"nothing listens on {self.topic}: is the face node running?")
            time.sleep(0.005)
        self.publisher.publish(data=text)
        return self.publisher.listeners()


def wait_for_screen(publisher: Any, version: int) -> None:
    """Until the screen subscribes to `publisher`'s frames, so that the first reach it: ROS 2's
    discovery takes seconds, ROS 1's a moment. After that, `stream` plays anyway."""
    publisher.wait_for_listener(CONNECT if version == 2 else 0.5)


def listeners(count: int) -> str:
    return f"{count} listener" + ("" if count == 1 else "s")
