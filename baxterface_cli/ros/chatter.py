"""The studio's line to the robot: each press published on the face node's command topic."""

from __future__ import annotations

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
