"""baxterface: a face for the Baxter robot's head screen, as a scripting language."""

from .diagnostics import Diagnostic, ScriptError
from .nodes import Script
from .parser import parse, parse_file

__version__ = "0.1.0"

__all__ = ["Diagnostic", "Script", "ScriptError", "parse", "parse_file", "__version__"]
