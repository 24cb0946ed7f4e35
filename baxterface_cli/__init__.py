"""baxterface: a face for the Baxter robot's head screen, as a scripting language."""

from typing import Any

from .core.face_state import FaceState, Parts
from .language.diagnostics import Diagnostic, ScriptError
from .language.parser import parse, parse_file
from .language.syntax_tree import Script

__version__ = "0.1.0"

# The package's rooms, lowest first: each imports only from those before it (and the modules at the
# root), which tests/test_layers.py holds. docs/architecture.md says what each room is.
LAYERS = (
    "core",
    "language",
    "speech",
    "engine",
    "drawing",
    "robot",
    "play",
    "ros",
    "export",
    "web",
    "studio",
    "screen",
    "cli",
)

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
_DRAWING = {"Face": "drawing.face", "Theme": "drawing.theme", "ThemeError": "drawing.theme"}


def __getattr__(name: str) -> Any:
    if name in _DRAWING:
        import importlib

        return getattr(importlib.import_module(f".{_DRAWING[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
