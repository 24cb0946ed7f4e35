"""Robot effects as ROS messages, with no rospy: the one mapping the node, `stream` and the bag writer share.

`ros_commands` turns an effect into what goes on which topic, as plain values
(a topic and the message's fields by name); rospy links (robot_link.py) and
the bag writer (export/bag.py) build the messages from them.
"""

from __future__ import annotations

from typing import Any, Dict, List, NamedTuple

from ..engine.effects import EffectHandler, HeadNod, HeadPan, SetEnabled, SetFollowing, ShutDown, Speech

HEAD_PAN_TOPIC = "/robot/head/command_head_pan"
HEAD_NOD_TOPIC = "/robot/head/command_head_nod"
ENABLE_TOPIC = "/robot/set_super_enable"
SOUND_TOPIC = "/robotsound"  # ROS's sound_play listens here
HEAD_STATE_TOPIC = "/robot/head/head_state"
ROBOT_STATE_TOPIC = "/robot/state"
NAVIGATOR_TOPIC = "/robot/navigators/{}_navigator/state"  # a navigator's (language/events.py names them)
CUFF_TOPIC = "/robot/digital_io/{}_{}/state"  # an arm's side, and one of its cuff's inputs
CUFF_SIDES = ("left", "right")
# Where each robot's head screen takes its frames.
DISPLAY_TOPICS = {"baxter": "/robot/xdisplay", "sawyer": "/robot/head_display"}

# Each command topic's message type.
COMMAND_TYPES: Dict[str, str] = {
    HEAD_PAN_TOPIC: "baxter_core_msgs/HeadPanCommand",
    HEAD_NOD_TOPIC: "std_msgs/Bool",
    ENABLE_TOPIC: "std_msgs/Bool",
    SOUND_TOPIC: "sound_play/SoundRequest",
}


# sound_play/SoundRequest's constants
SOUND_PLAY_FILE, SOUND_SAY, PLAY_ONCE = -2, -3, 1
PLAY_STOP = 0


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

    def follow(self, effect: SetFollowing, at: float) -> List[RosCommand]:
        return []  # following happens on the face, from sensors

    def exit(self, effect: ShutDown, at: float) -> List[RosCommand]:
        return []

    def speech(self, effect: Speech, at: float) -> List[RosCommand]:
        # sound_play speaks the text in its own voice: a message that names a sound
        # file would name one that is gone by the time a bag of it is played. A
        # recording is the user's own file, there to be played by its path.
        recording = effect.utterance.recording
        if recording is not None:
            sound, arg = SOUND_PLAY_FILE, recording.path
        else:
            sound, arg = SOUND_SAY, effect.utterance.text
        fields = {"sound": sound, "command": PLAY_ONCE, "volume": 1.0, "arg": arg, "arg2": ""}
        return [RosCommand(SOUND_TOPIC, fields)]


_TO_ROS = _ToRos()


def ros_commands(effect: Any) -> List[RosCommand]:
    """The messages that carry out an effect on the robot (none for face-only effects)."""
    return effect.visit(_TO_ROS, 0.0)
