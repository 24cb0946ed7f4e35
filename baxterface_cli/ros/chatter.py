"""The face node's command topic from elsewhere: the studio's presses published on it, and the
commands a screen hears on it, on either ROS."""

from __future__ import annotations

from typing import Callable

from ..closing import ClosedOnExit
from .connect import open_link
from .link import CHATTER


class ChatterLink:
    """Publishes command texts on `topic` (std_msgs/String), as `baxterface send` does."""

    def __init__(self, topic: str = CHATTER, version: int = 1) -> None:
        # Not the main thread, and the studio's server owns Ctrl-C: the link installs no signal handlers.
        self.link = open_link(version, "baxterface_studio", anonymous=True)
        self.publisher = self.link.publisher(topic, "std_msgs/String", queue=16)
        self.topic = self.publisher.topic

    def send(self, text: str) -> None:
        self.publisher.publish(data=text)

    def status(self) -> str:
        listening = self.publisher.listeners()
        if listening == 0:
            return f"sending to {self.topic}, but no face node listens yet"
        return f"sending to {self.topic} ({listening} listening)"


class ChatterListener(ClosedOnExit):
    """Hands each command heard on `topic` to `hand`, in the order they came, as the face node
    hears them."""

    def __init__(self, topic: str, hand: Callable[[str], None], version: int = 1) -> None:
        self.link = open_link(version, "baxterface_screen", anonymous=True)
        # One thread calls back for a subscription, so `hand` returning once a command is taken
        # keeps them in order; what waits meanwhile queues here, as on the node.
        self.subscription = self.link.subscribe(
            topic, "std_msgs/String", lambda msg: hand(msg.data), queue=100
        )

    def close(self) -> None:
        self.subscription.close()
        self.link.close()
