"""Can `render` write where `--out` points? Asked before a frame is drawn, answered in a user's words.

A render can take minutes; a target it cannot write must fail at once, naming the folder at fault,
not after the last frame with the system's bare "Permission denied". Writing is tried for real
(a file made and removed in the folder the render will write in): permission bits say nothing to
root, nor to ACLs, read-only mounts or network file systems.
"""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path
from typing import Dict, Optional, Tuple

from ..core import partial_files as partial

# File systems that hold the kernel's own objects, never a user's files.
SPECIAL_FILE_SYSTEMS = {
    "devtmpfs",
    "devpts",
    "proc",
    "sysfs",
    "cgroup",
    "cgroup2",
    "debugfs",
    "tracefs",
    "securityfs",
    "mqueue",
    "bpf",
    "configfs",
    "pstore",
    "efivarfs",
    "fusectl",
    "hugetlbfs",
    "binfmt_misc",
}
_KINDS = {
    stat.S_IFIFO: "a named pipe",
    stat.S_IFCHR: "a character device",
    stat.S_IFBLK: "a block device",
    stat.S_IFSOCK: "a socket",
    stat.S_IFREG: "a file",
    stat.S_IFLNK: "a broken link",
}


class TargetError(OSError):
    """`--out` cannot be written; the message says why, naming the path at fault."""

    def __init__(self, code: int, message: str) -> None:
        super().__init__(code, message)


def check_target(path: Path, folder: bool) -> None:
    """Make the folders on the way to `path` and check that it can be written; TargetError if not.

    `folder`: `path` is a folder of frames, written inside itself; otherwise a file, written
    beside itself. Nothing is left behind but the folders made on the way.
    """
    if folder:
        if os.path.lexists(path) and not path.is_dir():
            raise TargetError(errno.ENOTDIR, f"{path} is {_kind(path)}, not a folder")
    elif os.path.lexists(path):
        mode = os.lstat(path).st_mode
        if not (stat.S_ISREG(mode) or stat.S_ISLNK(mode)):
            # Replaced by a file, a pipe a reader waits on would never hear of it.
            raise TargetError(errno.EEXIST, f"{path} is {_kind(path)}; render replaces only files")
    where = path if folder and path.is_dir() else path.parent  # the folder the partial goes in
    existing = where
    while not os.path.lexists(existing) and existing != existing.parent:
        existing = existing.parent
    if not existing.is_dir():
        raise TargetError(errno.ENOTDIR, f"{existing} is {_kind(existing)}, not a folder")
    _refuse_special(existing)
    try:
        where.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise _unwritable(existing, e) from None
    try:
        partial.PartialFile(where / ".baxterface-check").discard()
    except OSError as e:
        raise _unwritable(where, e) from None


def _kind(path: Path) -> str:
    try:
        mode = os.lstat(path).st_mode
    except OSError:
        return "missing"
    if stat.S_ISLNK(mode) and os.path.exists(path):
        mode = os.stat(path).st_mode
    return _KINDS.get(stat.S_IFMT(mode), "not a folder")


def _unwritable(folder: Path, error: OSError) -> TargetError:
    code = error.errno or errno.EACCES
    if code == errno.EROFS:
        return TargetError(code, f"{folder} is on a read-only file system")
    if code in (errno.EACCES, errno.EPERM):
        return TargetError(code, f"{folder} is not writable ({error.strerror})")
    return TargetError(code, f"{folder}: {error.strerror or error}")


def _refuse_special(folder: Path) -> None:
    """A folder of the kernel's (/dev, /proc, /sys) is no place for a render, even for root."""
    real = os.path.realpath(folder)
    mount = mount_of(real)
    if mount is None:  # no mount table to read: the usual places
        if real == "/dev" or real.startswith(("/dev/", "/proc/", "/sys/")) or real in ("/proc", "/sys"):
            raise TargetError(errno.EPERM, f"{folder} is a system folder, not a place for files")
        return
    point, kind = mount
    # /dev is often a plain tmpfs in containers: its own mount point tells it apart (/dev/shm is a
    # mount of its own, and writable).
    if kind in SPECIAL_FILE_SYSTEMS or point == "/dev":
        where = f"{kind} at {point}"
        raise TargetError(errno.EPERM, f"{folder} is a system folder ({where}), not a place for files")


def mount_of(real_path: str) -> Optional[Tuple[str, str]]:
    """(mount point, file system type) of the mount holding `real_path`; None without /proc."""
    try:
        with open("/proc/self/mountinfo", encoding="utf-8", errors="replace") as f:
            lines = f.read().splitlines()
    except OSError:
        return None
    mounts: Dict[str, str] = {}
    for line in lines:
        fields = line.split()
        if "-" not in fields[6:]:
            continue
        dash = fields.index("-", 6)
        # Later mounts over the same point hide earlier ones: the last one wins.
        mounts[_unescape(fields[4])] = fields[dash + 1]
    best = ""
    for point in mounts:
        inside = real_path == point or real_path.startswith(point.rstrip("/") + "/")
        if inside and len(point) > len(best):
            best = point
    return (best, mounts[best]) if best else None


def _unescape(field: str) -> str:
    """mountinfo writes a space, tab, newline and backslash in a path as octal escapes."""
    for code in ("040", "011", "012", "134"):
        field = field.replace("\\" + code, chr(int(code, 8)))
    return field
