"""baxterface: a face for the Baxter robot's head screen, as a scripting language."""

from .diagnostics import Diagnostic, ScriptError
from .face import Face
from .nodes import Script
from .parser import parse, parse_file
from .state import FaceState, Parts
from .theme import Theme, ThemeError

__version__ = "0.1.0"

__all__ = [
    "Diagnostic",
    "Face",
    "FaceState",
    "Parts",
    "Script",
    "ScriptError",
    "Theme",
    "ThemeError",
    "parse",
    "parse_file",
    "__version__",
]
