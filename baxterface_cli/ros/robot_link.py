"""The robot's topics through a `Link`: effects out, the head and enabled state in.

`connect_robot` wires a core `Robot` to the topics, sending each effect as
`effect_messages.ros_commands` says. A message type the link does not have (Baxter's own,
on a ROS 2 without baxter_core_msgs) leaves its topic out: the face still does
what the script says, and the first effect that would have gone there says so.
"""

from __future__ import annotations

from typing import Any, Callable, Dict, Optional, Set

from ..engine.effects import Speech
from ..robot.robot_rules import Robot
from .effect_messages import COMMAND_TYPES, HEAD_STATE_TOPIC, ROBOT_STATE_TOPIC, SOUND_TOPIC, ros_commands
from .link import Link

WARN_EVERY = 5.0  # seconds between repeats of one warning about bad robot data
HEAD_STATE_TYPE = "baxter_core_msgs/HeadState"
ROBOT_STATE_TYPE = "baxter_core_msgs/AssemblyState"


def connect_robot(
    link: Link,
    warn: Optional[Callable[[str], None]] = None,
    info: Optional[Callable[[str], None]] = None,
    speak: Callable[[Speech], None] = lambda effect: None,
    camera: Optional[Callable[..., Any]] = None,
) -> Robot:
    """A core `Robot` whose commands go out on the robot's topics and who hears its state.

    It logs with `warn` and `info` (the link's own by default); its speech goes
    to `speak` (an `open_speaker(...).speak`); `camera` makes its CameraWatch.
    """
    warn = warn or (lambda text: link.log("warn", text))
    info = info or (lambda text: link.log("info", text))
    # Every command topic is advertised from the start (sound_play's too, though the speaker sends
    # what is said), so that whoever listens is connected before the first command.
    wanted = dict(COMMAND_TYPES)
    publishers: Dict[str, Any] = {
        topic: link.publisher(topic, kind) for topic, kind in wanted.items() if link.has(kind)
    }
    missing: Set[str] = set(wanted) - set(publishers) - {SOUND_TOPIC}  # speech is the speaker's to say

    def send(effect: Any) -> None:
        for command in ros_commands(effect):
            if command.topic in publishers:
                publishers[command.topic].publish(**command.fields)
            elif command.topic in missing:  # said once a topic
                missing.discard(command.topic)
                warn(
                    f"not sent on {command.topic}: its type {wanted[command.topic]} is not installed "
                    f"for this ROS {link.version}"
                )

    robot = Robot(send, warn=warn, info=info, speak=speak, camera=camera)

    def head_state(msg: Any) -> None:
        if not robot.heard_head(msg.pan):
            link.log("warn", f"skipped a head state whose pan is not finite ({msg.pan})", every=WARN_EVERY)

    def robot_state(msg: Any) -> None:
        robot.heard_enabled(msg.enabled)

    if link.has(HEAD_STATE_TYPE):
        link.subscribe(HEAD_STATE_TOPIC, HEAD_STATE_TYPE, head_state, queue=1)
    if link.has(ROBOT_STATE_TYPE):
        link.subscribe(ROBOT_STATE_TOPIC, ROBOT_STATE_TYPE, robot_state, queue=1)
    return robot
