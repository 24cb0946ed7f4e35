"""`baxterface send` and `baxterface stream`: a face node's command topic, or the screen itself."""

from __future__ import annotations

import time
from typing import Any, List, Optional

from ..drawing.renderer import Renderer
from ..engine.animation import Animation
from ..engine.effects import Cue
from ..play.player import Player
from .compressed import CompressedFrames
from .connect import open_link
from .effect_messages import DISPLAY_TOPICS
from .images import image_fields
from .link import Link
from .robot_link import connect_robot
from .speakers import default_audio, open_speaker

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


class _RosScreen:
    """A screen that is the robot's: frames go to its display topic."""

    name = "robot"

    def __init__(self, link: Link, topic: str) -> None:
        self.link = link
        self.publisher = link.publisher(topic, "sensor_msgs/Image", latched=True, queue=1)
        self.jpeg = CompressedFrames(link, self.publisher.topic)  # for viewers elsewhere, as the node's
        self.last: Optional[bytes] = None

    def show(self, frame, status: str) -> None:
        fields = image_fields(frame)
        if fields["data"] != self.last:  # an unchanged frame is not sent again
            self.publisher.publish(**fields)
            self.last = fields["data"]
            self.jpeg.offer(frame)
        else:
            self.jpeg.tick(time.monotonic())

    def alive(self) -> bool:
        return self.link.ok()


def stream(
    animation: Animation,
    renderer: Renderer,
    robot: str,
    fps: float,
    argv: List[str],
    audio: Optional[str] = None,
    version: int = 1,
) -> float:
    """Play `animation` on the robot's screen in real time, with its robot effects and speech.

    The effects go through the same core `Robot` as the face node's, and the
    speech through the same speaker for the `audio` mode (by default the node's
    on that ROS version), so one script sends the same commands at the same
    times from both.
    """
    with open_link(version, "baxterface_stream", argv, anonymous=True, leaving="streamed") as link:
        screen = _RosScreen(link, DISPLAY_TOPICS[robot])
        with screen.jpeg, open_speaker(
            audio or default_audio(version), link, lambda t: link.log("warn", t), "--audio"
        ) as speaker:
            arm = connect_robot(link, speak=speaker.speak)
            wait_for_screen(screen.publisher, version)
            pending: List[Cue] = list(animation.timeline.cues)

            def on_time(t: float) -> None:
                while pending and pending[0].at <= t:
                    arm.take(pending.pop(0).effect, t)
                arm.tick(t)

            player = Player(animation, renderer, screen, fps, on_time=on_time)
            played = player.run()
            time.sleep(0.3)
    return played
