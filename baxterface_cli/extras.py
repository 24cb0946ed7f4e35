"""Optional parts: a clear one-line error that names the extra to install when one is missing."""

from __future__ import annotations

import importlib
from types import ModuleType


class MissingTool(RuntimeError):
    """A library or program a feature needs is not installed; the message says how to get it."""


def need(module: str, extra: str, purpose: str) -> ModuleType:
    """Import `module`, or raise MissingTool naming `pip install 'baxterface[extra]'`."""
    try:
        return importlib.import_module(module)
    except ImportError:
        raise MissingTool(
            f"{purpose} needs the '{module}' module: pip install 'baxterface[{extra}]'"
        ) from None
