"""The robot's topics: effects out as ROS messages, the head and enabled state in; speech out.

`ros_commands` is the one mapping from an effect to what goes on which topic,
as plain values (so a bag writer can use it without rospy); `connect_robot`
wires a core `Robot` to the topics, and `open_speaker` turns an audio mode
into where its speech goes, for the face node and for `stream` alike.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
import time
from collections import deque
from typing import Any, Callable, Deque, Dict, List, NamedTuple, Optional, Tuple

from ..effects import EffectHandler, Exit, Follow, HeadNod, HeadPan, SetEnabled, Speech
from ..robot import Robot
from ..soundtrack import write_wav

HEAD_PAN_TOPIC = "/robot/head/command_head_pan"
HEAD_NOD_TOPIC = "/robot/head/command_head_nod"
ENABLE_TOPIC = "/robot/set_super_enable"
SOUND_TOPIC = "/robotsound"  # ROS's sound_play listens here
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

    def follow(self, effect: Follow, at: float) -> List[RosCommand]:
        return []  # following happens on the face, from sensors

    def exit(self, effect: Exit, at: float) -> List[RosCommand]:
        return []

    def speech(self, effect: Speech, at: float) -> List[RosCommand]:
        # sound_play speaks the text in its own voice: a message that names a sound
        # file would name one that is gone by the time a bag of it is played.
        fields = {
            "sound": SOUND_SAY,
            "command": PLAY_ONCE,
            "volume": 1.0,
            "arg": effect.utterance.text,
            "arg2": "",
        }
        return [RosCommand(SOUND_TOPIC, fields)]


_TO_ROS = _ToRos()


def ros_commands(effect: Any) -> List[RosCommand]:
    """The messages that carry out an effect on the robot (none for face-only effects)."""
    return effect.visit(_TO_ROS, 0.0)


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


# -- speech


class Speaker:
    """Where speech goes: nowhere (`_audio:=none`: the mouth moves, nothing is heard).

    `speak` runs on the frame loop as a Speech cue falls due, which is when the
    mouth starts moving, so it starts the sound and returns.
    """

    def __init__(self, rospy: Any, warn: Callable[[str], None]) -> None:
        pass

    def speak(self, effect: Speech) -> None:
        """Start saying the effect's utterance now."""

    def stop(self) -> None:
        """Stop what is being said: a new command took over."""

    def close(self) -> None:
        """Let go of what it holds."""


class SoundPlaySpeaker(Speaker):
    """Each utterance as a WAV file, played by ROS's sound_play (PLAY_FILE on /robotsound).

    sound_play opens the file by its path, so it must run on this machine. The
    files live in a folder of this speaker's own, each removed once it has surely
    been played, and the folder with them on `close`.
    """

    KEEP = 30.0  # seconds a file outlives its sound: sound_play may open it late

    def __init__(self, rospy: Any, warn: Callable[[str], None]) -> None:
        from .messages import message_class

        self.warn = warn
        self.request = message_class(COMMAND_TYPES[SOUND_TOPIC])
        self.publisher = rospy.Publisher(SOUND_TOPIC, self.request, queue_size=10)
        self.folder = tempfile.mkdtemp(prefix="baxterface-speech-")
        self.files: Deque[Tuple[str, float]] = deque()  # (path, when it may go), oldest first
        self.playing: Optional[Tuple[str, float]] = None  # (path, when its sound ends)
        self.said = 0

    def speak(self, effect: Speech) -> None:
        now = time.monotonic()
        while self.files and self.files[0][1] <= now:
            with contextlib.suppress(OSError):  # gone already
                os.remove(self.files.popleft()[0])
        if self.said == 0 and self.publisher.get_num_connections() == 0:
            # A request that nobody hears is dropped without a word: only this tells.
            self.warn(
                f"nothing listens on {SOUND_TOPIC}, so the face is not heard: start sound_play on this "
                "machine (rosrun sound_play soundplay_node.py), or choose another audio mode"
            )
        self.said += 1
        utterance = effect.utterance
        path = os.path.join(self.folder, f"say-{self.said:06d}.wav")
        write_wav(path, utterance.samples, utterance.sample_rate)
        self._request(PLAY_ONCE, path)
        self.files.append((path, now + utterance.duration + self.KEEP))
        self.playing = (path, now + utterance.duration)

    def stop(self) -> None:
        if self.playing is not None and self.playing[1] > time.monotonic():
            self._request(PLAY_STOP, self.playing[0])
        self.playing = None

    def close(self) -> None:
        shutil.rmtree(self.folder, ignore_errors=True)

    def _request(self, command: int, path: str) -> None:
        self.publisher.publish(
            self.request(sound=SOUND_PLAY_FILE, command=command, volume=1.0, arg=path, arg2="")
        )


class LocalSpeaker(Speaker):
    """The utterance on this machine's own sound device (none there: a warning, once, and silence)."""

    def __init__(self, rospy: Any, warn: Callable[[str], None]) -> None:
        from ..audio import open_sound

        self.sound = open_sound(warn)

    def speak(self, effect: Speech) -> None:
        self.sound.play(effect.utterance.samples, effect.utterance.sample_rate)

    def stop(self) -> None:
        self.sound.stop()

    def close(self) -> None:
        self.sound.close()


# The audio modes (the node's `_audio:=`, stream's `--audio`) and their speakers.
SPEAKERS: Dict[str, Callable[[Any, Callable[[str], None]], Speaker]] = {
    "soundplay": SoundPlaySpeaker,
    "local": LocalSpeaker,
    "none": Speaker,
}
DEFAULT_AUDIO = "soundplay"  # a Baxter lab's speakers are on a workstation running sound_play
AUDIO_CHOICES = ", ".join(list(SPEAKERS)[:-1]) + " or " + list(SPEAKERS)[-1]


class UnknownAudio(ValueError):
    """An audio mode that is not one of SPEAKERS."""


def open_speaker(mode: str, rospy: Any, warn: Callable[[str], None], name: str = "~audio") -> Speaker:
    """The speaker for audio `mode`; UnknownAudio, naming the setting `name`, for no such mode."""
    if mode not in SPEAKERS:
        raise UnknownAudio(f"{name} must be {AUDIO_CHOICES}, not {mode!r}")
    return SPEAKERS[mode](rospy, warn)
