"""The robot's topics: effects out as ROS messages, the head and enabled state in.

`ros_commands` is the one mapping from an effect to what goes on which topic,
as plain values (so a bag writer can use it without rospy); `connect_robot`
wires a core `Robot` to the topics for the face node and for `stream` alike.
"""

from __future__ import annotations

from typing import Any, Callable, Dict, List, NamedTuple, Optional

from ..effects import EffectHandler, Exit, Follow, HeadNod, HeadPan, SetEnabled
from ..robot import Robot

HEAD_PAN_TOPIC = "/robot/head/command_head_pan"
HEAD_NOD_TOPIC = "/robot/head/command_head_nod"
ENABLE_TOPIC = "/robot/set_super_enable"
HEAD_STATE_TOPIC = "/robot/head/head_state"
ROBOT_STATE_TOPIC = "/robot/state"
# Where each robot's head screen takes its frames.
DISPLAY_TOPICS = {"baxter": "/robot/xdisplay", "sawyer": "/robot/head_display"}
WARN_EVERY = 5.0  # seconds between repeats of one warning about bad robot data

# Each command topic's message type.
COMMAND_TYPES: Dict[str, str] = {
    HEAD_PAN_TOPIC: "baxter_core_msgs/HeadPanCommand",
    HEAD_NOD_TOPIC: "std_msgs/Bool",
    ENABLE_TOPIC: "std_msgs/Bool",
}


class RosCommand(NamedTuple):
    """One message to publish: its topic, and its fields by name."""

    topic: str
    fields: Dict[str, Any]


class _ToRos(EffectHandler):
    def head_pan(self, effect: HeadPan, at: float) -> List[RosCommand]:
        # enable_pan_request 1: the SDK's REQUEST_PAN_ENABLE, as baxter_interface sends.
        fields = {"target": effect.target, "speed_ratio": effect.speed, "enable_pan_request": 1}
        return [RosCommand(HEAD_PAN_TOPIC, fields)]

    def head_nod(self, effect: HeadNod, at: float) -> List[RosCommand]:
        return [RosCommand(HEAD_NOD_TOPIC, {"data": True})]

    def set_enabled(self, effect: SetEnabled, at: float) -> List[RosCommand]:
        return [RosCommand(ENABLE_TOPIC, {"data": effect.enabled})]

    def follow(self, effect: Follow, at: float) -> List[RosCommand]:
        return []  # following happens on the face, from sensors

    def exit(self, effect: Exit, at: float) -> List[RosCommand]:
        return []


_TO_ROS = _ToRos()


def ros_commands(effect: Any) -> List[RosCommand]:
    """The messages that carry out an effect on the robot (none for face-only effects)."""
    return effect.visit(_TO_ROS, 0.0)


def message_type(type_name: str) -> Any:
    """The message class for 'package/Name'."""
    import importlib

    from .messages import DEFINITIONS, message_class

    package, name = type_name.split("/")
    if package == "baxter_core_msgs" and name in DEFINITIONS:
        return message_class(name)
    return getattr(importlib.import_module(f"{package}.msg"), name)


def connect_robot(
    rospy: Any, warn: Optional[Callable[[str], None]] = None, info: Optional[Callable[[str], None]] = None
) -> Robot:
    """A core `Robot` whose commands go out on the robot's topics and who hears its state.

    It logs with `warn` and `info` (rospy's own by default).
    """
    from .messages import message_class

    classes = {topic: message_type(kind) for topic, kind in COMMAND_TYPES.items()}
    publishers = {topic: rospy.Publisher(topic, cls, queue_size=10) for topic, cls in classes.items()}

    def send(effect: Any) -> None:
        for command in ros_commands(effect):
            publishers[command.topic].publish(classes[command.topic](**command.fields))

    robot = Robot(send, warn=warn or rospy.logwarn, info=info or rospy.loginfo)

    def head_state(msg: Any) -> None:
        if not robot.heard_head(msg.pan):
            rospy.logwarn_throttle(WARN_EVERY, f"skipped a head state whose pan is not finite ({msg.pan})")

    def robot_state(msg: Any) -> None:
        robot.heard_enabled(msg.enabled)

    rospy.Subscriber(HEAD_STATE_TOPIC, message_class("HeadState"), head_state, queue_size=1)
    rospy.Subscriber(ROBOT_STATE_TOPIC, message_class("AssemblyState"), robot_state, queue_size=1)
    return robot
