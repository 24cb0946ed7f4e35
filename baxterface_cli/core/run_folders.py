"""Temporary folders of a running process, named with its pid, and swept when it is gone.

A process killed outright (`kill -9`, a power cut) runs no clean-up, so what it
kept in the temporary folder stays. Each folder made here is named
`baxterface-KIND-PID-XXXX`; the next process to make one of that kind first
removes those whose process no longer runs (this user's only).
"""

from __future__ import annotations

import os
import re
import shutil
import tempfile
from pathlib import Path


def own_folder(kind: str) -> str:
    """A new folder of this process for `kind` (0700), after sweeping the dead ones' of that kind."""
    sweep(kind)
    return tempfile.mkdtemp(prefix=f"baxterface-{kind}-{os.getpid()}-")


def sweep(kind: str, under: str = "") -> int:
    """Remove the `kind` folders whose process is gone; how many were removed."""
    if os.name != "posix":  # a pid cannot be asked after without signalling it elsewhere
        return 0
    pattern = re.compile(rf"baxterface-{re.escape(kind)}-(\d+)-")
    removed = 0
    root = Path(under or tempfile.gettempdir())
    try:
        entries = list(root.iterdir())
    except OSError:
        return 0
    for entry in entries:
        found = pattern.match(entry.name)
        if not found or int(found.group(1)) == os.getpid():
            continue
        try:
            info = entry.lstat()
        except OSError:
            continue
        if not entry.is_dir() or entry.is_symlink() or info.st_uid != os.getuid():
            continue
        if not alive(int(found.group(1))):
            shutil.rmtree(str(entry), ignore_errors=True)
            removed += 1
    return removed


def alive(pid: int) -> bool:
    """Does process `pid` run (as anyone)?"""
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's
        return True
    except OSError:
        return False
    return True
