"""Shared helpers: run the real `baxterface` command the way a user does."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import Optional, Union

import pytest

ROOT = Path(__file__).resolve().parent.parent


class Run:
    def __init__(self, proc: subprocess.CompletedProcess) -> None:
        self.code = proc.returncode
        self.out = proc.stdout.decode("utf-8", "replace")
        self.err = proc.stderr.decode("utf-8", "replace")


def baxterface(
    *args: str, stdin: Union[bytes, str, None] = None, cwd: Optional[Path] = None, env: Optional[dict] = None
) -> Run:
    """Run `python -m baxterface_cli ARGS` in a subprocess and collect its output."""
    data = stdin.encode("utf-8") if isinstance(stdin, str) else stdin
    env = dict(env or os.environ, COLUMNS="100", NO_COLOR="1", TERM="dumb")
    env.pop("BAXTERFACE_DEBUG", None)
    proc = subprocess.run(
        [sys.executable, "-m", "baxterface_cli", *args],
        input=data if data is not None else b"",
        capture_output=True,
        cwd=str(cwd or ROOT),
        env=env,
        timeout=120,
    )
    return Run(proc)


@pytest.fixture
def cli():
    return baxterface
