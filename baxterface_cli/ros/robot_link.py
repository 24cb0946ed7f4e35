"""The robot's topics through rospy: effects out, the head and enabled state in.

`connect_robot` wires a core `Robot` to the topics, sending each effect as
`wire.ros_commands` says.
"""

from __future__ import annotations

from typing import Any, Callable, Optional

from ..engine.effects import Speech
from ..robot.robot_rules import Robot
from .wire import COMMAND_TYPES, HEAD_STATE_TOPIC, ROBOT_STATE_TOPIC, ros_commands

WARN_EVERY = 5.0  # seconds between repeats of one warning about bad robot data


def connect_robot(
    rospy: Any,
    warn: Optional[Callable[[str], None]] = None,
    info: Optional[Callable[[str], None]] = None,
    speak: Callable[[Speech], None] = lambda effect: None,
    camera: Optional[Callable[..., Any]] = None,
) -> Robot:
    """A core `Robot` whose commands go out on the robot's topics and who hears its state.

    It logs with `warn` and `info` (rospy's own by default); its speech goes
    to `speak` (an `open_speaker(...).speak`); `camera` makes its CameraWatch.
    """
    from .messages import message_class

    classes = {topic: message_class(kind) for topic, kind in COMMAND_TYPES.items()}
    publishers = {topic: rospy.Publisher(topic, cls, queue_size=10) for topic, cls in classes.items()}

    def send(effect: Any) -> None:
        for command in ros_commands(effect):
            publishers[command.topic].publish(classes[command.topic](**command.fields))

    robot = Robot(send, warn=warn or rospy.logwarn, info=info or rospy.loginfo, speak=speak, camera=camera)

    def head_state(msg: Any) -> None:
        if not robot.heard_head(msg.pan):
            rospy.logwarn_throttle(WARN_EVERY, f"skipped a head state whose pan is not finite ({msg.pan})")

    def robot_state(msg: Any) -> None:
        robot.heard_enabled(msg.enabled)

    rospy.Subscriber(HEAD_STATE_TOPIC, message_class("HeadState"), head_state, queue_size=1)
    rospy.Subscriber(ROBOT_STATE_TOPIC, message_class("AssemblyState"), robot_state, queue_size=1)
    return robot
