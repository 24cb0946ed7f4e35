"""`baxterface send` and `baxterface stream`: a face node's command topic, or the screen itself."""

from __future__ import annotations

import time
import warnings
from typing import List, Optional

from ..drawing.renderer import Renderer
from ..engine.animation import Animation
from ..engine.effects import Cue
from ..play.player import Player
from .robot_link import connect_robot
from .speakers import DEFAULT_AUDIO, open_speaker
from .wire import DISPLAY_TOPICS


class NoSubscriber(Exception):
    pass


class Sender:
    """One connection to a face node's command topic, for one message or many.

    Publishing is synchronous (no queue_size): when `send` returns, the message
    is in the listeners' sockets, so nothing waits a fixed time for it to leave.
    """

    def __init__(self, topic: str, timeout: float, argv: List[str]) -> None:
        import rospy
        from std_msgs.msg import String

        rospy.init_node("baxterface_send", argv=argv, anonymous=True, disable_signals=True)
        self.rospy, self.String, self.timeout = rospy, String, timeout
        self.topic = rospy.resolve_name(topic)
        with warnings.catch_warnings():  # rospy warns of a publisher without a queue: that is the point
            warnings.simplefilter("ignore")
            self.publisher = rospy.Publisher(self.topic, String)

    def __enter__(self) -> Sender:
        return self

    def __exit__(self, *exc: object) -> None:
        self.publisher.unregister()

    def send(self, text: str) -> int:
        """Publish `text` once something listens; how many listeners it reached."""
        deadline = time.monotonic() + self.timeout
        while self.publisher.get_num_connections() == 0:
            if time.monotonic() > deadline:
                raise NoSubscriber(f"nothing listens on {self.topic}: is the face node running?")
            time.sleep(0.005)
        self.publisher.publish(self.String(text))
        return self.publisher.get_num_connections()


def listeners(count: int) -> str:
    return f"{count} listener" + ("" if count == 1 else "s")


class _RosScreen:
    """A screen that is the robot's: frames go to its display topic."""

    name = "robot"

    def __init__(self, topic: str) -> None:
        import cv_bridge
        import rospy
        from sensor_msgs.msg import Image

        self.rospy = rospy
        self.bridge = cv_bridge.CvBridge()
        self.publisher = rospy.Publisher(topic, Image, latch=True, queue_size=1)
        self.last: Optional[bytes] = None

    def show(self, frame, status: str) -> None:
        data = frame.tobytes()
        if data != self.last:  # an unchanged frame is not sent again
            self.publisher.publish(self.bridge.cv2_to_imgmsg(frame, encoding="bgr8"))
            self.last = data

    def alive(self) -> bool:
        return not self.rospy.is_shutdown()


def stream(
    animation: Animation,
    renderer: Renderer,
    robot: str,
    fps: float,
    argv: List[str],
    audio: str = DEFAULT_AUDIO,
) -> float:
    """Play `animation` on the robot's screen in real time, with its robot effects and speech.

    The effects go through the same core `Robot` as the face node's, and the
    speech through the same speaker for the `audio` mode, so one script sends
    the same commands at the same times from both.
    """
    import rospy

    rospy.init_node("baxterface_stream", argv=argv, anonymous=True, disable_signals=True)
    screen = _RosScreen(DISPLAY_TOPICS[robot])
    speaker = open_speaker(audio, rospy, rospy.logwarn, name="--audio")
    try:
        arm = connect_robot(rospy, speak=speaker.speak)
        time.sleep(0.5)  # let subscribers connect before the first frame
        pending: List[Cue] = list(animation.timeline.cues)

        def on_time(t: float) -> None:
            while pending and pending[0].at <= t:
                arm.take(pending.pop(0).effect, t)
            arm.tick(t)

        player = Player(animation, renderer, screen, fps, on_time=on_time)
        played = player.run()
        time.sleep(0.3)
    finally:
        speaker.close()
    rospy.signal_shutdown("streamed")
    return played
