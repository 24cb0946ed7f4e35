"""Files and folders being written, beside the name they will be renamed to.

A `PartialFile` is, where Linux allows it, a file with no name at all
(O_TMPFILE) in the target's folder: a writer killed with SIGKILL, or one
that fails, leaves nothing behind, and the file gets a name only for the
instant between linking and renaming it into place. Elsewhere, and for
folders, a partial is named `.NAME.PID.RANDOM.baxterface-partial`: created
exclusively (never through a link someone planted, never shared by two
writers), and with the writer's process id, so that one left by a killed
writer can be told apart from one still being written, and removed.
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
import secrets
import shutil
import stat
import tempfile
from pathlib import Path
from typing import BinaryIO, Optional, Tuple

SUFFIX = ".baxterface-partial"
_NAME = re.compile(r"^\..+\.(\d+)\.[A-Za-z0-9_]+" + re.escape(SUFFIX) + r"$")
_FLAGS = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_BINARY", 0)


def _prefix(target: Path) -> str:
    return f".{target.name}.{os.getpid()}."


def create_file(target: Path) -> Tuple[Path, BinaryIO]:
    """A new, empty partial file for `target`, open for writing."""
    for _ in range(100):
        path = _partial_name(target)
        try:
            # O_EXCL fails on any existing name, a link included; 0o666 lets
            # the umask decide, as for any file the user writes.
            fd = os.open(str(path), _FLAGS, 0o666)
        except FileExistsError:
            continue
        return path, os.fdopen(fd, "wb")
    raise FileExistsError(f"no free temporary name beside {target}")


class PartialFile:
    """A file being written for `target`: unseen until `commit`, gone after `discard`.

    `named=True` gives it a name from the start, for a program that opens
    it by name (ffmpeg); `path` is that name (None for an unnamed file).
    """

    def __init__(self, target: Path, named: bool = False) -> None:
        self.target = target
        self.path: Optional[Path] = None
        fd = None if named else _unnamed(target.parent)
        if fd is None:
            self.path, self.file = create_file(target)
        else:
            self.file = os.fdopen(fd, "wb")

    def commit(self) -> None:
        """Close the file and put it in place under `target`, replacing what was there."""
        if self.path is None:  # give it a name first: a link cannot replace an existing file
            self.file.flush()
            path = _partial_name(self.target)
            _link(self.file.fileno(), path)
            self.path = path
        self.file.close()
        try:
            os.replace(self.path, self.target)
        except BaseException:
            remove(self.path)
            raise

    def discard(self) -> None:
        """Close the file and remove what was written."""
        with contextlib.suppress(OSError):
            self.file.close()
        if self.path is not None:
            remove(self.path)


def _link(fd: int, path: Path) -> None:
    """Give the unnamed file `fd` the name `path`.

    linkat(AT_SYMLINK_FOLLOW) through /proc follows the descriptor's link to
    the file itself; Python calls linkat (not link, which would try to link
    /proc's own entry) only when given a folder descriptor, so it gets one.
    """
    folder = os.open(str(path.parent), os.O_RDONLY)
    try:
        os.link(f"/proc/self/fd/{fd}", path.name, src_dir_fd=folder, dst_dir_fd=folder, follow_symlinks=True)
    finally:
        os.close(folder)


def _partial_name(target: Path) -> Path:
    return target.with_name(f"{_prefix(target)}{secrets.token_hex(4)}{SUFFIX}")


def _unnamed(folder: Path) -> Optional[int]:
    """An unnamed file in `folder`, open for writing; None where the system or disk has none."""
    flag = getattr(os, "O_TMPFILE", 0)
    if not flag or not os.path.isdir("/proc/self/fd"):
        return None
    try:
        # 0o666: the umask decides, as for any file the user writes.
        return os.open(str(folder), flag | os.O_WRONLY | getattr(os, "O_CLOEXEC", 0), 0o666)
    except OSError as e:
        if e.errno in (errno.EOPNOTSUPP, errno.EISDIR, errno.EINVAL, errno.ENOENT):
            return None  # a file system without O_TMPFILE: a named partial instead
        raise


def create_folder(target: Path) -> Path:
    """A new, empty partial folder for `target`, writable by this user only."""
    return Path(tempfile.mkdtemp(prefix=_prefix(target), suffix=SUFFIX, dir=str(target.parent)))


def write_atomic(path: Path, data: bytes) -> None:
    """`data` as the file `path`, which is whole or untouched, never half-written."""
    partial = PartialFile(path)
    try:
        partial.file.write(data)
        partial.commit()
    except BaseException:
        partial.discard()
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
