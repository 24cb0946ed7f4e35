"""The user's cache folder: what baxterface works out once and keeps between runs.

`$XDG_CACHE_HOME/baxterface/`, or `~/.cache/baxterface/`: the parser's tables (language/)
and the mouths heard in recordings (speech/). A folder of the user's own (0700, as every
folder baxterface makes), never a shared temporary one: what is kept there is loaded back
as it was written. What grows with use is trimmed by bytes, and by count where asked (`trim`).
"""

from __future__ import annotations

import contextlib
import os
from pathlib import Path
from typing import Optional


def cache_folder(*parts: str) -> Path:
    """`$XDG_CACHE_HOME/baxterface/PARTS...` (or under `~/.cache`), not made."""
    base = os.environ.get("XDG_CACHE_HOME", "")
    root = Path(base) if base and os.path.isabs(base) else Path.home() / ".cache"
    return root.joinpath("baxterface", *parts)


def make_private(folder: Path) -> None:
    """Make `folder` and any parent it lacks, each for this user alone; OSError if it cannot be."""
    missing = []
    at = folder
    while not at.exists() and at.parent != at:
        missing.append(at)
        at = at.parent
    for part in reversed(missing):
        with contextlib.suppress(FileExistsError):  # made meanwhile by another process
            part.mkdir(mode=0o700)
    folder.mkdir(mode=0o700, exist_ok=True)
    info = folder.stat()
    if info.st_mode & 0o077 and info.st_uid == getattr(os, "getuid", lambda: info.st_uid)():
        folder.chmod(0o700)  # made open by an older version


def made_cache_folder(*parts: str) -> Optional[Path]:
    """The cache folder of `parts`, made for this user alone if it was not there; None where it
    cannot be (a home that cannot be written): then nothing is kept."""
    folder = cache_folder(*parts)
    try:
        make_private(folder)
    except OSError:
        return None
    return folder if os.access(folder, os.W_OK) else None


def trim(folder: Path, pattern: str, most: Optional[int], most_files: Optional[int] = None) -> None:
    """Remove the files of `folder` matching `pattern` least recently used first (by their
    modification time, which a reader touches), until they take at most `most` bytes (if given)
    and are at most `most_files` (if given)."""
    found = []
    for path in folder.glob(pattern):
        with contextlib.suppress(OSError):
            info = path.stat()
            found.append((info.st_mtime_ns, info.st_size, path))
    total = sum(size for _, size, _ in found)
    count = len(found)
    for _, size, path in sorted(found, key=lambda row: row[0])[:-1]:  # the newest stays, however big
        if (most is None or total <= most) and (most_files is None or count <= most_files):
            break
        count -= 1
        with contextlib.suppress(OSError):
            path.unlink()
        total -= size
