"""`--log FILE` and `--log-size MB`: the live ends' session log (engine/session_log_file.py)."""

from __future__ import annotations

import random
import sys
from typing import Any, Dict, Optional, Tuple

import typer

from .app import fail

LOG_OPT = typer.Option(
    None,
    "--log",
    metavar="FILE",
    help="Keep the session's record in FILE (JSON Lines): scripts, events, handlers, speech "
    "(docs/session-log.md); 'baxterface render FILE' replays it.",
)
LOG_SIZE_OPT = typer.Option(
    100.0, "--log-size", metavar="MB", help="Rotate --log's file past this size: FILE.1, ... FILE.4 kept."
)

LogFile = Tuple[str, int, Dict[str, Any]]  # (its path, its size before it rotates, the settings)


def logged_seed(path: Optional[str], seed: Optional[int]) -> Optional[int]:
    """The seed a session runs with: the one given; with --log and none given, one drawn here,
    which the log says, so that a replay's `one of`s and faces choose as the session's did."""
    return random.randrange(2**31) if path is not None and seed is None else seed


def log_file(path: Optional[str], megabytes: float, end: str, **settings: Any) -> Optional[LogFile]:
    """What the session's log file is made with, or None without --log; a bad size is one line."""
    from ..engine.session_log_file import log_size

    if path is None:
        return None
    try:
        size = log_size(megabytes)
    except ValueError as e:
        raise fail(f"baxterface {end}: --log-size {e}", 2) from None
    return path, size, {"end": end, "command": sys.argv[1:], **settings}


def open_log(made: Optional[LogFile], origin: float, warn):
    """The session's log file (a SessionLogFile) from `log_file`'s, or None."""
    from ..engine.session_log_file import SessionLogFile

    if made is None:
        return None
    path, size, settings = made
    return SessionLogFile(path, origin, settings, warn, size)
