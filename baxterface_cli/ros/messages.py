"""Baxter's own message types (SDK 1.2), without needing baxter_core_msgs.

The robot refuses a publisher whose message md5sum differs from its own, so
the definitions are carried here word for word and built with genpy when the
`baxter_core_msgs` package is not installed; an installed one is preferred.
`check()` compares every class's md5sum with the SDK's.
"""

from __future__ import annotations

from typing import Any, Dict

SEPARATOR = "=" * 80

# type -> (definition, md5sum from the SDK 1.2 release)
DEFINITIONS: Dict[str, tuple] = {
    "HeadPanCommand": (
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
    "HeadState": (
        """float32 pan
bool isTurning
bool isNodding
bool isPanEnabled
""",
        "71c43b264307205358e7e49be5601348",
    ),
    "AssemblyState": (
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
    "EndpointState": (
        """Header header
geometry_msgs/Pose   pose
geometry_msgs/Twist  twist
geometry_msgs/Wrench wrench
""",
        "44bea01d596ff699fa1447bec34167ac",
    ),
    "NavigatorState": (
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
}

# Types the definitions above refer to, from the installed standard packages.
DEPENDENCIES = {
    "EndpointState": ("std_msgs/Header", "geometry_msgs/Pose", "geometry_msgs/Twist", "geometry_msgs/Wrench")
}

_classes: Dict[str, Any] = {}


def message_class(name: str) -> Any:
    """The class of baxter_core_msgs/`name`: installed, or built from the carried definition."""
    if name in _classes:
        return _classes[name]
    try:
        import importlib

        cls = getattr(importlib.import_module("baxter_core_msgs.msg"), name)
    except (ImportError, AttributeError):
        cls = _generate(name)
    _classes[name] = cls
    return cls


def _generate(name: str) -> Any:
    import genpy.dynamic

    text, _ = DEFINITIONS[name]
    full = text
    for dependency in _dependency_closure(name):
        full += f"\n{SEPARATOR}\nMSG: {dependency}\n{_installed_text(dependency)}"
    return genpy.dynamic.generate_dynamic(f"baxter_core_msgs/{name}", full)[f"baxter_core_msgs/{name}"]


def _installed_text(type_name: str) -> str:
    package, name = type_name.split("/")
    import importlib

    return getattr(importlib.import_module(f"{package}.msg"), name)._full_text.split(f"\n{SEPARATOR}")[0]


def _dependency_closure(name: str) -> list:
    """Every message type the definition needs, nested ones included, each once."""
    import importlib

    seen: list = []
    for top in DEPENDENCIES.get(name, ()):
        package, short = top.split("/")
        full_text = getattr(importlib.import_module(f"{package}.msg"), short)._full_text
        for dependency in [top] + [
            line[5:].strip() for line in full_text.splitlines() if line.startswith("MSG: ")
        ]:
            if dependency not in seen:
                seen.append(dependency)
    return seen


def check() -> Dict[str, bool]:
    """Does each class's md5sum match the SDK's?"""
    return {name: message_class(name)._md5sum == md5 for name, (_, md5) in DEFINITIONS.items()}
