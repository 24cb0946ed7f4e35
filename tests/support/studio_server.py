"""A real `baxterface studio` (or `baxterface screen`) in a subprocess, and small HTTP helpers to
talk to it.

Shared by the studio's and the screen's tests, their browser tests and bench/bench_studio.py and
bench/bench_screen.py.
"""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import time
import urllib.error
import urllib.request
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Dict, Iterator, List, Optional, Tuple

URL_LINE = re.compile(r"baxterface (?:studio|screen): (http://\S+)")


class Studio:
    def __init__(self, process: subprocess.Popen, url: str, log: Optional[Path] = None) -> None:
        self.process = process
        self.log_path = log
        self.url = url  # with ?token=... when it has one
        self.base = url.split("?")[0].rstrip("/")
        self.token = url.split("token=")[1] if "token=" in url else None

    def request(
        self, method: str, path: str, body: Any = None, headers: Optional[Dict[str, str]] = None
    ) -> Tuple[int, bytes]:
        data = None
        if body is not None:
            data = body.encode("utf-8") if isinstance(body, str) else json.dumps(body).encode("utf-8")
        all_headers = dict(headers or {})
        if self.token and "X-Baxterface-Token" not in all_headers:
            all_headers["X-Baxterface-Token"] = self.token
        req = urllib.request.Request(self.base + path, data=data, method=method, headers=all_headers)
        try:
            with urllib.request.urlopen(req, timeout=30) as response:
                return response.status, response.read()
        except urllib.error.HTTPError as e:
            return e.code, e.read()

    def json(self, method: str, path: str, body: Any = None) -> Tuple[int, Any]:
        status, data = self.request(method, path, body)
        return status, json.loads(data)

    def log(self) -> List[str]:
        """What the studio has printed so far, a line each."""
        return self.log_path.read_text(encoding="utf-8").splitlines() if self.log_path else []

    def stop(self, signum: int = signal.SIGTERM, timeout: float = 60.0) -> int:
        """Send `signum` and wait for the exit status. One that never comes fails the test with
        every thread's stack (faulthandler's, on SIGABRT) from the log."""
        self.process.send_signal(signum)
        try:
            return self.process.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            self.process.send_signal(signal.SIGABRT)
            self.process.wait(timeout=30)
            stacks = "\n".join(self.log())
            raise AssertionError(f"still running {timeout:.0f} s after {signum!r}:\n{stacks}") from None

    def frame(self) -> bytes:
        status, data = self.request("GET", "/api/frame.jpg")
        assert status == 200, data
        return data


def baxterface() -> str:
    return str(Path(sys.executable).with_name("baxterface"))


@contextmanager
def running_studio(
    script: Path, *args: str, timeout: float = 60.0, env: Optional[Dict[str, str]] = None
) -> Iterator[Studio]:
    """`baxterface studio SCRIPT --no-browser --port 0 ARGS`, until the block ends."""
    words = ["studio", str(script), "--no-browser", "--port", "0", "--seed", "7", *args]
    with running(words, script.parent, timeout, env) as studio:
        yield studio


@contextmanager
def running_screen(
    folder: Path, *args: str, port: int = 0, timeout: float = 60.0, env: Optional[Dict[str, str]] = None
) -> Iterator[Studio]:
    """`baxterface screen ARGS --no-browser --port PORT`, with its log in `folder`, until the block ends."""
    words = ["screen", *args, "--no-browser", "--port", str(port), "--seed", "7"]
    with running(words, folder, timeout, env) as screen:
        yield screen


@contextmanager
def running(
    words: List[str], folder: Path, timeout: float = 60.0, env: Optional[Dict[str, str]] = None
) -> Iterator[Studio]:
    """`baxterface WORDS`, once it prints its address, until the block ends (SIGTERM)."""
    log = folder / f".studio-{os.getpid()}-{time.monotonic_ns()}.log"
    with open(log, "w+", encoding="utf-8") as err:
        process = subprocess.Popen(
            [baxterface(), *words],
            stdout=subprocess.DEVNULL,
            stderr=err,
            env=dict(env or os.environ, PYTHONUNBUFFERED="1", PYTHONFAULTHANDLER="1"),
        )
        try:
            deadline = time.monotonic() + timeout
            url = None
            while url is None:
                if process.poll() is not None or time.monotonic() > deadline:
                    err.seek(0)
                    raise AssertionError(f"baxterface {words[0]} did not start: {err.read()}")
                err.seek(0)
                found = URL_LINE.search(err.read())
                url = found.group(1) if found else None
                time.sleep(0.05)
            yield Studio(process, url, log)
        finally:
            process.terminate()
            try:
                process.wait(timeout=20)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()
            log.unlink()
