"""Where the files that ship with baxterface are: the grammar and the assets.

In a wheel they sit inside the package (`baxterface_cli/grammar/...`); in a
source checkout or an editable install they are the repository's top-level
folders, which is where they are edited.
"""

from __future__ import annotations

from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent


def resource(relative: str) -> Path:
    """The path of a shipped file, e.g. `resource("grammar/face.lark")`."""
    for root in (_PACKAGE, _PACKAGE.parent):
        candidate = root / relative
        if candidate.exists():
            return candidate
    raise FileNotFoundError(f"baxterface is missing its file {relative}; reinstall it")
