"""The studio's line to the robot: each press published on the face node's command topic."""

from __future__ import annotations


class ChatterLink:
    """Publishes command texts on `topic` (std_msgs/String), as `baxterface send` does."""

    def __init__(self, topic: str = "display_chatter") -> None:
        import rospy
        from std_msgs.msg import String

        if not rospy.core.is_initialized():
            # Not the main thread, and the studio's server owns Ctrl-C: no signal handlers.
            rospy.init_node("baxterface_studio", anonymous=True, disable_signals=True)
        self._string = String
        self.publisher = rospy.Publisher(topic, String, queue_size=16)
        self.topic = rospy.resolve_name(topic)

    def send(self, text: str) -> None:
        self.publisher.publish(self._string(text))

    def status(self) -> str:
        listening = self.publisher.get_num_connections()
        if listening == 0:
            return f"sending to {self.topic}, but no face node listens yet"
        return f"sending to {self.topic} ({listening} listening)"
