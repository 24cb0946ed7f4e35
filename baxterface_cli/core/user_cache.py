"""The user's cache folder: what baxterface works out once and keeps between runs.

`$XDG_CACHE_HOME/baxterface/`, or `~/.cache/baxterface/`: the parser's tables (language/)
and the mouths heard in recordings (speech/). A folder of the user's own, never a shared
temporary one: what is kept there is loaded back as it was written.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Optional


def cache_folder(*parts: str) -> Path:
    """`$XDG_CACHE_HOME/baxterface/PARTS...` (or under `~/.cache`), not made."""
    base = os.environ.get("XDG_CACHE_HOME", "")
    root = Path(base) if base and os.path.isabs(base) else Path.home() / ".cache"
    return root.joinpath("baxterface", *parts)


def made_cache_folder(*parts: str) -> Optional[Path]:
    """The cache folder of `parts`, made for this user alone if it was not there; None where it
    cannot be (a home that cannot be written): then nothing is kept."""
    folder = cache_folder(*parts)
    try:
        folder.mkdir(mode=0o700, parents=True, exist_ok=True)
    except OSError:
        return None
    return folder if os.access(folder, os.W_OK) else None
