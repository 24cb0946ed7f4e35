"""Message types the robot's side needs that Debian's ROS lacks: Baxter's own, and sound_play's.

A subscriber refuses a publisher whose message md5sum differs from its own, so
the definitions are carried here word for word and built with genpy when their
package is not installed; an installed one is preferred. `check()` compares
every built class's md5sum with the one its package publishes.
"""

from __future__ import annotations

import atexit
import shutil
import tempfile
import threading
from typing import Any, Dict, List, NamedTuple, Optional, Tuple

from ..core.run_folders import own_folder

BAXTER = "baxter_core_msgs"  # the package a bare name ("HeadPanCommand") means

SEPARATOR = "=" * 80


class Carried(NamedTuple):
    """A message type's definition, its md5sum as its package has it, and the types it uses."""

    text: str
    md5sum: str
    dependencies: Tuple[str, ...] = ()  # package/Name of each, from the installed standard packages


# package/Name -> the carried type. Baxter's are the SDK 1.2 release's.
DEFINITIONS: Dict[str, Carried] = {
    "baxter_core_msgs/HeadPanCommand": Carried(
        """float32 target              # radians for target, 0 str
float32 speed_ratio         # Percentage of max speed [0-1]
#
  float32 MAX_SPEED_RATIO = 1.0
  float32 MIN_SPEED_RATIO = 0.0
#
uint8   enable_pan_request  # override automatic pan enable/disable
# enable_pan_request is tristate: 0 = disable pan; 1 = enable pan; 2 = don't change pan
  uint8   REQUEST_PAN_DISABLE = 0
  uint8   REQUEST_PAN_ENABLE = 1
  uint8   REQUEST_PAN_VOID = 2
#
""",
        "23b8a3f4b7ee9de7099d029e57660a8c",
    ),
    "baxter_core_msgs/HeadState": Carried(
        """float32 pan
bool isTurning
bool isNodding
bool isPanEnabled
""",
        "71c43b264307205358e7e49be5601348",
    ),
    "baxter_core_msgs/AssemblyState": Carried(
        """bool ready               # true if enabled and ready to operate, e.g., not homing
bool enabled             # true if enabled
bool stopped             # true if stopped -- e-stop asserted
bool error               # true if a component of the assembly has an error
#
# The following are specific to the robot top-level assembly:
uint8  estop_button      # One of the following:
  uint8   ESTOP_BUTTON_UNPRESSED = 0   # Robot is not stopped and button is not pressed
  uint8   ESTOP_BUTTON_PRESSED   = 1
  uint8   ESTOP_BUTTON_UNKNOWN   = 2   # STATE_UNKNOWN when estop was asserted by a non-user source
  uint8   ESTOP_BUTTON_RELEASED  = 3   # Was pressed, is now known to be released, but robot is still stopped.
#
uint8  estop_source      # If stopped is true, the source of the e-stop.  One of the following:
  uint8  ESTOP_SOURCE_NONE      = 0   # e-stop is not asserted
  uint8  ESTOP_SOURCE_USER      = 1   # e-stop source is user input (the red button)
  uint8  ESTOP_SOURCE_UNKNOWN   = 2   # e-stop source is unknown
  uint8  ESTOP_SOURCE_FAULT     = 3   # MotorController asserted e-stop in response to a joint fault
  uint8  ESTOP_SOURCE_BRAIN     = 4   # MotorController asserted e-stop in response to a lapse of the brain heartbeat
""",
        "356d9dd237ce73b2667da9235f541933",
    ),
    "baxter_core_msgs/EndpointState": Carried(
        """Header header
geometry_msgs/Pose   pose
geometry_msgs/Twist  twist
geometry_msgs/Wrench wrench
""",
        "44bea01d596ff699fa1447bec34167ac",
        ("std_msgs/Header", "geometry_msgs/Pose", "geometry_msgs/Twist", "geometry_msgs/Wrench"),
    ),
    "baxter_core_msgs/NavigatorState": Carried(
        """# buttons
string[] button_names
bool[] buttons

# wheel position
uint8   wheel

# true if the light is on, false if not
# lights map to button names
string[] light_names
bool[] lights
""",
        "680d121a1f16a32647298b292492fffd",
    ),
    # The cuffs' and other digital inputs: /robot/digital_io/NAME/state.
    "baxter_core_msgs/DigitalIOState": Carried(
        """int8 state
bool isInputOnly

int8 OFF = 0
int8 ON  = 1
int8 PRESSED = 1
int8 UNPRESSED = 0
""",
        "29d0be3859dae81a66b28f167ecec98c",
    ),
    # sound_play's as ROS Noetic has it: ros-drivers/audio_common, tag 0.3.18,
    # sound_play/msg/SoundRequest.msg (with `volume` and `arg2`; a `reverb` field proposed
    # since is in no release). Its md5sum as rosserial generated it, in jsk-ros-pkg/jsk_3rdparty,
    # smart_device_protocol/ros_lib/ros_lib/sound_play/SoundRequest.h (getMD5).
    "sound_play/SoundRequest": Carried(
        """# IMPORTANT: You should never have to generate this message yourself.
# Use the sound_play::SoundClient C++ helper or the
# sound_play.libsoundplay.SoundClient Python helper.

# Sounds
int8 BACKINGUP = 1
int8 NEEDS_UNPLUGGING = 2
int8 NEEDS_PLUGGING = 3
int8 NEEDS_UNPLUGGING_BADLY = 4
int8 NEEDS_PLUGGING_BADLY = 5

# Sound identifiers that have special meaning
int8 ALL = -1 # Only legal with PLAY_STOP
int8 PLAY_FILE = -2
int8 SAY = -3

int8 sound # Selects which sound to play (see above)

# Commands
int8 PLAY_STOP = 0 # Stop this sound from playing
int8 PLAY_ONCE = 1 # Play the sound once
int8 PLAY_START = 2 # Play the sound in a loop until a stop request occurs

int8 command # Indicates what to do with the sound

# Volume at which to play the sound, with 0 as mute and 1.0 as 100%.
float32 volume

string arg # file name or text to say
string arg2 # other arguments
""",
        "d098ce4a040686259137ece23a625167",
    ),
}

_classes: Dict[str, Any] = {}


def full_name(name: str) -> str:
    """package/Name for a type name; a bare name is Baxter's."""
    return name if "/" in name else f"{BAXTER}/{name}"


def message_class(name: str) -> Any:
    """The class of a message type ("sound_play/SoundRequest"; "HeadPanCommand" is Baxter's):
    its installed package's, or else built from the carried definition."""
    name = full_name(name)
    if name not in _classes:
        try:
            _classes[name] = _installed(name)
        except (ImportError, AttributeError):
            if name not in DEFINITIONS:
                raise
            _classes[name] = _generate(name)
    return _classes[name]


def _installed(name: str) -> Any:
    import importlib

    package, short = name.split("/")
    return getattr(importlib.import_module(f"{package}.msg"), short)


def _generate(name: str) -> Any:
    import genpy.dynamic

    full = DEFINITIONS[name].text
    for dependency in _dependency_closure(name):
        own = _installed(dependency)._full_text.split(f"\n{SEPARATOR}")[0]
        full += f"\n{SEPARATOR}\nMSG: {dependency}\n{own}"
    # genpy writes each class to a `genpy_*` folder in the temporary folder and removes it only at
    # exit: made inside a folder named with our pid instead, a node killed outright leaves nothing
    # the next one does not sweep (core/run_folders.py).
    with _GENERATING:
        genpy.dynamic.tempfile = _InFolder(_genpy_folder())
        try:
            return genpy.dynamic.generate_dynamic(name, full)[name]
        finally:
            genpy.dynamic.tempfile = tempfile


_GENERATING = threading.Lock()
_folder: List[str] = []


def _genpy_folder() -> str:
    if not _folder:
        _folder.append(own_folder("genpy"))
        # Registered before genpy registers its own clean-ups, so it runs after them.
        atexit.register(shutil.rmtree, _folder[0], ignore_errors=True)
    return _folder[0]


class _InFolder:
    """The `tempfile` module as genpy sees it, its new folders made inside `parent`."""

    def __init__(self, parent: str) -> None:
        self.parent = parent

    def mkdtemp(self, suffix: Optional[str] = None, prefix: Optional[str] = None, dir: Any = None) -> str:
        return tempfile.mkdtemp(suffix, prefix, self.parent)

    def __getattr__(self, name: str) -> Any:
        return getattr(tempfile, name)


def _dependency_closure(name: str) -> list:
    """Every message type the definition needs, nested ones included, each once."""
    seen: list = []
    for top in DEFINITIONS[name].dependencies:
        full_text = _installed(top)._full_text
        for dependency in [top] + [
            line[5:].strip() for line in full_text.splitlines() if line.startswith("MSG: ")
        ]:
            if dependency not in seen:
                seen.append(dependency)
    return seen


def check() -> Dict[str, bool]:
    """Does each class's md5sum match its package's?"""
    return {name: message_class(name)._md5sum == carried.md5sum for name, carried in DEFINITIONS.items()}
