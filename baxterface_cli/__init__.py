"""baxterface: a face for the Baxter robot's head screen, as a scripting language."""

from typing import Any

from .diagnostics import Diagnostic, ScriptError
from .nodes import Script
from .parser import parse, parse_file
from .state import FaceState, Parts

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

# Drawing (numpy, Pillow) loads only when asked for: parsing, checking and
# compiling a script never need it.
_DRAWING = {"Face": "face", "Theme": "theme", "ThemeError": "theme"}


def __getattr__(name: str) -> Any:
    if name in _DRAWING:
        import importlib

        return getattr(importlib.import_module(f".{_DRAWING[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
