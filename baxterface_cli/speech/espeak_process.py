"""The process that asks: a long-lived speech process (espeak_child.py), started when first needed.

A crash of espeak-ng (a signal in the child) fails that one request with a message that names
it, and the next request starts a fresh child; so does a synthesis that runs past DEADLINE,
which is killed. The child is kept between requests, so a `say` costs a round trip through two
pipes, not a start. It is started with fork and exec (subprocess), which is safe in the threaded
servers (uvicorn, rospy) where a bare fork is not, and it ends with the process that started it:
at exit its pipe is closed and it is waited for; a parent killed outright closes the pipe too,
and the child, reading the end of it, exits.
"""

from __future__ import annotations

import atexit
import json
import os
import select
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Any, Dict, List, Optional, Tuple

from ..extras import MissingTool
from .espeak import Heard, Spoken
from .espeak_child import FRAME, send

# The longest `say` a script may hold (1,000 characters at 80 words a minute, about 9 minutes of
# speech) is synthesised in about a second; this leaves room for a machine many times slower.
DEADLINE = 60.0
# How long a child may take to start and greet: a Python's start, which a loaded machine stretches
# to seconds. Apart from `deadline`, a synthesis's bound: a short one (a test's) must not fail starts.
START_DEADLINE = 60.0

# Run by `python -c BOOT ROOT REQUESTS REPLIES`. The child needs espeak.py alone: a bare package
# object stands in for baxterface_cli, whose __init__ would import the language (lark) and add
# 0.1 s to every start. The working folder leaves sys.path, as it would for an installed program.
BOOT = (
    "import sys, types\n"
    "if sys.path and sys.path[0] in ('', '.'):\n"
    "    del sys.path[0]\n"
    "root, requests, replies = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])\n"
    "package = types.ModuleType('baxterface_cli')\n"
    "package.__path__ = [root]\n"
    "sys.modules['baxterface_cli'] = package\n"
    "from baxterface_cli.speech.espeak_child import serve\n"
    "serve(requests, replies)\n"
)
_PACKAGE = str(Path(__file__).resolve().parent.parent)


class SynthesisFailed(RuntimeError):
    """espeak-ng crashed on a text, or took too long over it: that text cannot be said."""

    def __init__(self, message: str, crashed: bool) -> None:
        super().__init__(message)
        self.crashed = crashed  # a crash comes back every time; an overrun may not


class _Gone(Exception):
    """The child closed its end: it has died."""


class EspeakProcess:
    """One speech process at a time, each request answered in turn."""

    def __init__(self, deadline: float = DEADLINE, command: Optional[List[str]] = None) -> None:
        self.deadline = deadline
        # What runs the child, less its two pipes' numbers (tests give a stand-in).
        self.command = command or [sys.executable, "-c", BOOT, _PACKAGE]
        self.sample_rate = 0
        self.version = ""
        self.starts = 0  # how many children have been started, for tests and benchmarks
        self._lock = threading.Lock()
        self._child: Optional[subprocess.Popen] = None
        self._requests = self._replies = -1
        self._owner = 0  # the pid that started the child: a fork's copy must start its own
        atexit.register(self.close)

    @property
    def pid(self) -> Optional[int]:
        return self._child.pid if self._child is not None else None

    def start(self) -> None:
        """Start the child now, if none is running; MissingTool without espeak-ng."""
        with self._lock:
            self._ensure()

    def say(self, text: str, voice: str, rate: int) -> Spoken:
        """espeak_Synth's result for `text`; ValueError for a voice espeak-ng lacks, SynthesisFailed
        if it crashed or overran."""
        head, data = self._ask({"op": "say", "text": text, "voice": voice, "rate": rate}, voice)
        return Spoken(int(head["status"]), data, [Heard(*event) for event in head["heard"]])

    def voice_file(self, voice: str) -> str:
        return str(self._ask({"op": "voice_file", "voice": voice}, voice)[0]["voice_file"])

    def close(self) -> None:
        """End the child (it reads the end of its pipe) and wait for it: no zombie is left."""
        # A thread still waiting on a synthesis at exit holds the lock: not for long, then.
        if self._lock.acquire(timeout=5.0):
            try:
                self._stop(grace=2.0)
            finally:
                self._lock.release()
        elif self._child is not None and self._child.poll() is None:
            self._child.kill()

    # -- under the lock ---------------------------------------------------------------------------

    def _ask(self, request: Dict[str, Any], voice: str) -> Tuple[Dict[str, Any], bytes]:
        with self._lock:
            self._ensure()
            started = time.monotonic()
            try:
                send(self._requests, request)
                head, data = self._receive(started + self.deadline)
            except (_Gone, BrokenPipeError):
                code = self._stop(grace=5.0)
                raise SynthesisFailed(
                    f"espeak-ng {self.version} crashed saying this text in voice {voice} "
                    f"({_reason(code)}); it cannot be said",
                    crashed=True,
                ) from None
            except TimeoutError:
                self._stop(grace=0.0)
                raise SynthesisFailed(
                    f"espeak-ng {self.version} was still saying this text in voice {voice} "
                    f"after {self.deadline:.0f} s and was stopped",
                    crashed=False,
                ) from None
            except BaseException:  # Ctrl-C while waiting: the answer would be read as the next one's
                self._stop(grace=0.0)
                raise
        if "refused" in head:
            raise ValueError(head["refused"])
        return head, data

    def _ensure(self) -> None:
        if self._child is not None and (self._owner != os.getpid() or self._child.poll() is not None):
            self._stop(grace=0.0)  # died between requests (killed from outside), or a fork's copy
        if self._child is not None:
            return
        child_requests, requests = os.pipe()
        replies, child_replies = os.pipe()
        try:
            # stderr too: espeak-ng prints a line for each sound it lacks an envelope for, thousands
            # for a long text in some voices, and glibc its abort message; the failure is reported.
            child = subprocess.Popen(
                [*self.command, str(child_requests), str(child_replies)],
                stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
                pass_fds=(child_requests, child_replies),
            )
        except OSError as e:  # no interpreter to run it with (an embedded Python), no processes left
            os.close(requests)
            os.close(replies)
            raise MissingTool(
                f"speech runs espeak-ng in a process of its own, which cannot start: {e}"
            ) from None
        finally:
            os.close(child_requests)
            os.close(child_replies)
        self._child, self._requests, self._replies, self._owner = child, requests, replies, os.getpid()
        self.starts += 1
        try:
            hello, _ = self._receive(time.monotonic() + START_DEADLINE)
        except (_Gone, TimeoutError):
            code = self._stop(grace=5.0)
            raise MissingTool(
                f"speech runs espeak-ng in a process of its own, which did not start ({_reason(code)})"
            ) from None
        if "missing" in hello:
            self._stop(grace=5.0)
            raise MissingTool(hello["missing"])
        self.sample_rate, self.version = int(hello["sample_rate"]), str(hello["version"])

    def _receive(self, deadline: float) -> Tuple[Dict[str, Any], bytes]:
        lengths = self._read(FRAME.size, deadline)
        head_length, data_length = FRAME.unpack(lengths)
        body = self._read(head_length + data_length, deadline)
        return json.loads(body[:head_length].decode("utf-8")), body[head_length:]

    def _read(self, count: int, deadline: float) -> bytes:
        parts, left = [], count
        while left:
            wait = deadline - time.monotonic()
            if wait <= 0 or not select.select([self._replies], [], [], wait)[0]:
                raise TimeoutError
            part = os.read(self._replies, min(left, 1 << 20))
            if not part:
                raise _Gone
            parts.append(part)
            left -= len(part)
        return b"".join(parts)

    def _stop(self, grace: float) -> Optional[int]:
        """Close the pipes and reap the child, killing it after `grace` seconds; its exit code."""
        for fd in (self._requests, self._replies):
            if fd >= 0:
                os.close(fd)
        self._requests = self._replies = -1
        child, self._child = self._child, None
        if child is None or self._owner != os.getpid():
            return None
        try:
            return child.wait(timeout=grace) if grace > 0 else _kill(child)
        except subprocess.TimeoutExpired:
            return _kill(child)


def _kill(child: subprocess.Popen) -> int:
    if child.poll() is None:
        child.kill()
    return child.wait()


def _reason(code: Optional[int]) -> str:
    """How a child ended, in words: "Segmentation fault", "Aborted", "exit status 1"."""
    if code is not None and code < 0:
        try:
            return signal.strsignal(-code) or f"signal {-code}"
        except ValueError:
            return f"signal {-code}"
    return f"exit status {code}"
