"""The web pages' lines to ROS: the studio's presses published on the face node's command topic,
and the commands a screen hears on it."""

from __future__ import annotations

from typing import Callable


def _node(name: str) -> None:
    """This process as a ROS node, once; its server, not rospy, owns Ctrl-C."""
    import rospy

    if not rospy.core.is_initialized():
        # Not the main thread, and the server owns Ctrl-C: no signal handlers.
        rospy.init_node(name, anonymous=True, disable_signals=True)


class ChatterLink:
    """Publishes command texts on `topic` (std_msgs/String), as `baxterface send` does."""

    def __init__(self, topic: str = "display_chatter") -> None:
        import rospy
        from std_msgs.msg import String

        _node("baxterface_studio")
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


class ChatterListener:
    """Hands each command heard on `topic` to `hand`, in the order they came, as the face node hears them."""

    def __init__(self, topic: str, hand: Callable[[str], None]) -> None:
        import rospy
        from std_msgs.msg import String

        _node("baxterface_screen")
        # One thread calls back for a subscription, so `hand` returning once a command is taken
        # keeps them in order; what waits meanwhile queues here, as on the node.
        self.subscriber = rospy.Subscriber(topic, String, lambda msg: hand(msg.data), queue_size=100)
        self.topic = rospy.resolve_name(topic)

    def close(self) -> None:
        self.subscriber.unregister()
