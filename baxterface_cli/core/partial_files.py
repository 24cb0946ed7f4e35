"""Files and folders being written, beside the name they will be renamed to.

A partial is named `.NAME.PID.RANDOM.baxterface-partial`: created
exclusively (never through a link someone planted, never shared by two
writers), and with the writer's process id, so that one left by a killed
writer can be told apart from one still being written, and removed.
"""

from __future__ import annotations

import os
import re
import secrets
import shutil
import stat
import tempfile
from pathlib import Path
from typing import BinaryIO, Tuple

SUFFIX = ".baxterface-partial"
_NAME = re.compile(r"^\..+\.(\d+)\.[A-Za-z0-9_]+" + re.escape(SUFFIX) + r"$")
_FLAGS = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_BINARY", 0)


def _prefix(target: Path) -> str:
    return f".{target.name}.{os.getpid()}."


def create_file(target: Path) -> Tuple[Path, BinaryIO]:
    """A new, empty partial file for `target`, open for writing."""
    for _ in range(100):
        path = target.with_name(f"{_prefix(target)}{secrets.token_hex(4)}{SUFFIX}")
        try:
            # O_EXCL fails on any existing name, a link included; 0o666 lets
            # the umask decide, as for any file the user writes.
            fd = os.open(str(path), _FLAGS, 0o666)
        except FileExistsError:
            continue
        return path, os.fdopen(fd, "wb")
    raise FileExistsError(f"no free temporary name beside {target}")


def create_folder(target: Path) -> Path:
    """A new, empty partial folder for `target`, writable by this user only."""
    return Path(tempfile.mkdtemp(prefix=_prefix(target), suffix=SUFFIX, dir=str(target.parent)))


def write_atomic(path: Path, data: bytes) -> None:
    """`data` as the file `path`, which is whole or untouched, never half-written."""
    tmp, file = create_file(path)
    try:
        with file:
            file.write(data)
        os.replace(tmp, path)
    except BaseException:
        remove(tmp)
        raise


def remove(path: Path) -> None:
    """Remove a partial file or folder; a link is removed itself, never followed."""
    try:
        if stat.S_ISDIR(os.lstat(path).st_mode):
            shutil.rmtree(path, ignore_errors=True)
        else:
            os.unlink(path)
    except OSError:
        pass


def _running(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)  # signal 0 only asks whether the process is there
    except (ProcessLookupError, OverflowError):
        return False
    except OSError:  # EPERM: there, but another user's
        return True
    return True


def remove_stale(folder: Path) -> None:
    """Remove this user's partials in `folder` whose writer no longer runs."""
    # Without signal 0 (Windows: os.kill would end the process) or owners,
    # a writer cannot be checked on: leave everything.
    if os.name != "posix":
        return
    try:
        names = os.listdir(folder)
    except OSError:
        return
    for name in names:
        match = _NAME.match(name)
        if not match:
            continue
        path = folder / name
        try:
            info = os.lstat(path)
        except OSError:
            continue
        if info.st_uid == os.geteuid() and not _running(int(match.group(1))):
            remove(path)
