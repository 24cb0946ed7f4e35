"""The face node's settings, read and checked in one place, without ROS.

The node reads its own parameters (ROS 1's `~fps`, ROS 2's `fps`, ...) through a
`get(name, default)` function; anything wrong is a `SettingError` that names
the parameter, so `baxterface node` can say which one and exit 2.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from typing import Any, Callable, Optional, Tuple

from ..drawing.theme import ThemeError, resolve
from ..drawing.theme_manifest import parse_size
from ..robot.person_choice import DEFAULT_FACE_POLICY, FACE_POLICIES, FACE_POLICY_CHOICES
from .effect_messages import DISPLAY_TOPICS
from .speakers import AUDIO_CHOICES, DEFAULT_AUDIO, SPEAKERS

CAMERA_TOPIC = "/cameras/head_camera/image"


class SettingError(ValueError):
    """One parameter's value is wrong; `name` is the parameter (without the `~`)."""

    def __init__(self, name: str, problem: str) -> None:
        super().__init__(f"~{name} {problem}")
        self.name, self.problem = name, problem


@dataclass(frozen=True)
class NodeSettings:
    fps: float = 30.0
    size: Tuple[int, int] = (1024, 600)
    theme: Optional[str] = None
    idle: bool = True
    selftest: bool = False
    display_topic: str = DISPLAY_TOPICS["baxter"]
    audio: str = DEFAULT_AUDIO
    camera: str = CAMERA_TOPIC
    recordings: Optional[str] = None  # the folder `say file` reads from; None: none is read
    camera_hfov: Optional[float] = None  # degrees; None: the camera's camera_info, or Baxter's head camera
    face_policy: str = DEFAULT_FACE_POLICY
    # Events for handlers (robot/event_sensors.py): the camera's hysteresis, the sonar's distance.
    face_seen_after: float = 0.2  # seconds a face is found before `face seen`
    face_lost_after: float = 0.8  # seconds unseen before `face lost`
    person_near: float = 1.0  # metres from the head sonar that make `person near`
    # Words (ros/node_ears.py): "" hears none, "default" the default input device, a .wav file's path
    # that recording played as a microphone would give it; `barge_in` hears words while it speaks.
    listen: str = ""
    barge_in: bool = False
    # A script the node starts with (after its selftest), as `baxterface node SCRIPT` gives it.
    script: Optional[str] = None
    # The session's log file (engine/session_log_file.py): None keeps none; rotated past log_size MB.
    log: Optional[str] = None
    log_size: float = 100.0

    @classmethod
    def read(cls, get: Callable[[str, Any], Any], defaults: Optional[NodeSettings] = None) -> NodeSettings:
        """Every setting from `get(name, default)`, with `defaults` where it has none (those of
        ROS 1 unless given); SettingError on the first bad one."""
        d = defaults or cls()
        return cls(
            fps=_number(get, "fps", d.fps, 1.0, 120.0),
            size=_size(get, "size", f"{d.size[0]}x{d.size[1]}"),
            theme=_text(get, "theme", "") or None,
            idle=_flag(get, "idle", d.idle),
            selftest=_flag(get, "selftest", d.selftest),
            display_topic=_topic(get, "display_topic", d.display_topic),
            audio=_choice(get, "audio", d.audio),
            camera=_topic(get, "camera", d.camera),
            recordings=_folder(get, "recordings"),
            camera_hfov=_unset_or(_number, get, "camera_hfov", 1.0, 179.0, " degrees"),
            face_policy=_one_of(get, "face_policy", d.face_policy, FACE_POLICIES, FACE_POLICY_CHOICES),
            face_seen_after=_number(get, "face_seen_after", d.face_seen_after, 0.0, 10.0, " s"),
            face_lost_after=_number(get, "face_lost_after", d.face_lost_after, 0.0, 60.0, " s"),
            person_near=_number(get, "person_near", d.person_near, 0.1, 5.0, " m"),
            listen=_listen(get, "listen", d.listen),
            barge_in=_flag(get, "barge_in", d.barge_in),
            script=_file(get, "script"),
            log=_log(get, "log"),
            log_size=_number(get, "log_size", d.log_size, 0.01, 1e6, " MB"),
        )


def camera_info_topic(image_topic: str) -> str:
    """Where a camera publishes its sensor_msgs/CameraInfo: `camera_info` beside its image topic."""
    folder, _, _ = image_topic.rpartition("/")
    return f"{folder}/camera_info" if folder or image_topic.startswith("/") else "camera_info"


def camera_focal(k: Any, binning_x: Any) -> Optional[float]:
    """The focal length in pixels of a camera's images, from its CameraInfo's K and binning_x (a
    region of interest crops the image, which leaves it); None if K has none (not calibrated)."""
    try:
        fx = float(k[0])
        binning = max(1, int(binning_x))
    except (TypeError, ValueError, IndexError):
        return None
    return fx / binning if math.isfinite(fx) and fx > 0.0 else None


def theme_layers(settings: NodeSettings) -> Any:
    """The theme's layers at the node's size; SettingError naming `~theme` if it cannot be used."""
    try:
        return resolve(settings.theme).layers(settings.size)
    except ThemeError as e:
        raise SettingError("theme", f"cannot be used: {e}") from None


def _number(get, name: str, default: float, low: float, high: float, unit: str = "") -> float:
    value = get(name, default)
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise SettingError(name, f"must be a number, not {str(value)[:40]!r}") from None
    if not low <= number <= high:  # also refuses nan
        raise SettingError(name, f"must be from {low:g} to {high:g}{unit}, not {number:g}")
    return number


def _unset_or(read, get, name: str, *limits: Any) -> Any:
    """None when the parameter is not set (or set to ''), else `read`'s value of it."""
    value = get(name, None)
    if value is None or value == "":
        return None
    return read(lambda _, default: value, name, None, *limits)


def _one_of(get, name: str, default: str, choices: Tuple[str, ...], said: str) -> str:
    value = str(get(name, default))
    if value not in choices:
        raise SettingError(name, f"must be {said}, not {value[:40]!r}")
    return value


def _size(get, name: str, default: str) -> Tuple[int, int]:
    try:
        return parse_size(str(get(name, default)))
    except ValueError as e:
        raise SettingError(name, str(e).replace("size ", "", 1)) from None


def _text(get, name: str, default: str) -> str:
    value = get(name, default)
    if not isinstance(value, str):
        raise SettingError(name, f"must be text, not {value!r}")
    return value


def _folder(get, name: str) -> Optional[str]:
    return _path(get, name, os.path.isdir, "a folder")


def _file(get, name: str) -> Optional[str]:
    return _path(get, name, os.path.isfile, "a script file")


def _path(get, name: str, there: Callable[[str], bool], what: str) -> Optional[str]:
    """The setting's absolute path, if given; it must be `what` (`there` says whether it is)."""
    value = _text(get, name, "").strip()
    if not value:
        return None
    path = os.path.abspath(os.path.expanduser(value))
    if not there(path):
        raise SettingError(name, f"must be {what}, not {value[:80]!r}")
    return path


def _log(get, name: str) -> Optional[str]:
    """A file to write: a folder it is in (it need not be writable: that is a line in the log)."""
    value = _text(get, name, "").strip()
    if not value:
        return None
    path = os.path.abspath(os.path.expanduser(value))
    if os.path.isdir(path) or not os.path.isdir(os.path.dirname(path)):
        raise SettingError(name, f"must be a file in a folder that is there, not {value[:80]!r}")
    return path


def _listen(get, name: str, default: str) -> str:
    value = _text(get, name, default).strip()
    if value in ("", "default"):
        return value
    path = os.path.abspath(os.path.expanduser(value))
    if not value.lower().endswith(".wav") or not os.path.isfile(path):
        raise SettingError(name, f"must be default or a WAV file, not {value[:80]!r}")
    return path


def _topic(get, name: str, default: str) -> str:
    value = _text(get, name, default)
    if not value or any(c.isspace() for c in value):
        raise SettingError(name, f"must be a topic name, not {value!r}")
    return value


def _flag(get, name: str, default: bool) -> bool:
    value = get(name, default)
    if isinstance(value, bool):
        return value
    # rospy makes `_idle:=false` a bool, but a launch file may give a string.
    words = {"true": True, "false": False, "1": True, "0": False}
    if str(value).lower() in words:
        return words[str(value).lower()]
    raise SettingError(name, f"must be true or false, not {str(value)[:40]!r}")


def _choice(get, name: str, default: str) -> str:
    value = str(get(name, default))
    if value not in SPEAKERS:
        raise SettingError(name, f"must be {AUDIO_CHOICES}, not {value[:40]!r}")
    return value
