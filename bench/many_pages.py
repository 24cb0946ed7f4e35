"""Many pages on one screen: WebSocket clients in this process, the command-to-frame time at each.

Used by bench_screen.py (`--pages`). Each page is a WebSocket on `/api/live`, as the screen's page
opens it (asking for permessage-deflate, as browsers do); a command is posted once every page has
been still for a while (idle off: only a command changes the face), and each page's first frame
after it is timed, on arrival here. The tree to compare with is served from `git archive` of it,
beside this one, in the same run.
"""

from __future__ import annotations

import asyncio
import io
import os
import subprocess
import tarfile
import tempfile
import time
import urllib.request
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Callable, Dict, Iterator, List, Optional

from studio_server import running_screen

BINARY = 0x2

SIDES = ("look left in 0.4s", "look right in 0.4s")
STILL = 0.3  # seconds without a frame at any page before a command: the last look is over everywhere


def post(base: str, text: str) -> None:
    request = urllib.request.Request(base + "/api/command", data=text.encode(), method="POST")
    with urllib.request.urlopen(request, timeout=60) as answer:
        answer.read()


class Page(asyncio.Protocol):
    """A page's WebSocket, read as little as a page must: the handshake, then each message's header,
    and the time a binary one (a frame of the face) has come whole; payloads are skipped, not
    copied. Python's `websockets` took this process longer a message than the server took to
    send it: 500 of them timed the client, not the screen."""

    def __init__(self, path: str, host: str, frame: Callable[[float], None]) -> None:
        self.request = (
            f"GET {path} HTTP/1.1\r\nHost: {host}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
            "Sec-WebSocket-Key: YmF4dGVyZmFjZSBwYWdlcw==\r\nSec-WebSocket-Version: 13\r\n"
            "Sec-WebSocket-Extensions: permessage-deflate; client_max_window_bits\r\n\r\n"
        ).encode()
        self.frame = frame
        self.buffer = bytearray()  # the handshake's answer, then a message's header, as they come
        self.opened = False
        self.left = 0  # bytes of the message under way still to come
        self.binary = False

    def connection_made(self, transport: Any) -> None:
        transport.write(self.request)

    def data_received(self, data: bytes) -> None:
        if not self.opened:
            self.buffer += data
            end = self.buffer.find(b"\r\n\r\n")
            if end < 0:
                return
            if not self.buffer.startswith(b"HTTP/1.1 101"):
                raise SystemExit(f"the screen refused a page: {bytes(self.buffer[:200])!r}")
            data = bytes(self.buffer[end + 4 :])
            self.buffer.clear()
            self.opened = True
        at, head = 0, self.buffer
        while at < len(data):
            if self.left:  # a message's payload: skipped, never copied
                taken = min(self.left, len(data) - at)
                self.left -= taken
                at += taken
                if not self.left and self.binary:
                    self.frame(time.monotonic())
                continue
            needed = 2 if len(head) < 2 else header_length(head)
            while len(head) < needed and at < len(data):
                head.append(data[at])
                at += 1
                needed = 2 if len(head) < 2 else header_length(head)
            if len(head) < needed:
                return
            size = head[1] & 0x7F
            self.left = int.from_bytes(head[2:needed], "big") if size >= 126 else size
            self.binary = head[0] & 0x0F == BINARY
            head.clear()
            if not self.left and self.binary:
                self.frame(time.monotonic())


def header_length(head: bytearray) -> int:
    """A server's message header: 2 bytes, and 2 or 8 more for a long payload's length."""
    return 2 + {126: 2, 127: 8}.get(head[1] & 0x7F, 0)


async def timed(base: str, pages: int, runs: int) -> List[float]:
    """Milliseconds from each command to its first frame at each page: runs x pages of them."""
    host, port = base.split("//")[1].split(":")
    last = [0.0] * pages  # when each page's latest frame came
    first: List[Optional[float]] = [None] * pages  # each page's first frame since the command
    armed = [False]

    def frame(i: int, at: float) -> None:
        last[i] = at
        if armed[0] and first[i] is None:
            first[i] = at

    loop = asyncio.get_running_loop()
    transports = []
    for i in range(pages):
        made = lambda i=i: Page("/api/live", f"{host}:{port}", lambda at: frame(i, at))  # noqa: E731
        transport, _ = await loop.create_connection(made, host, int(port))
        transports.append(transport)
    try:
        deadline = time.monotonic() + 300
        while not all(last):  # every page has its first frame
            if time.monotonic() > deadline:
                raise SystemExit(f"not all {pages} pages opened: {sum(1 for t in last if t)} did")
            await asyncio.sleep(0.1)
        await loop.run_in_executor(None, post, base, "look center")
        out: List[float] = []
        for run in range(runs + 1):  # the first warms up
            while time.monotonic() - max(last) < STILL:
                await asyncio.sleep(0.05)
            first[:] = [None] * pages
            armed[0] = True
            start = time.monotonic()
            await loop.run_in_executor(None, post, base, SIDES[run % 2])
            deadline = start + 60
            while any(f is None for f in first) and time.monotonic() < deadline:
                await asyncio.sleep(0.005)
            armed[0] = False
            if run:
                out += [1000 * ((f if f is not None else deadline) - start) for f in first]
        return out
    finally:
        for transport in transports:
            transport.close()


@contextmanager
def tree_of(revision: str) -> Iterator[Dict[str, str]]:
    """The environment that runs the package as it was at `revision` (git archive into a folder)."""
    here = Path(__file__).resolve().parent.parent
    with tempfile.TemporaryDirectory() as folder:
        archive = subprocess.run(
            ["git", "-C", str(here), "archive", revision, "baxterface_cli", "assets", "grammar"],
            check=True,
            capture_output=True,
        ).stdout
        with tarfile.open(fileobj=io.BytesIO(archive)) as tar:
            tar.extractall(folder)
        yield dict(os.environ, PYTHONPATH=folder)


def many_pages(folder: Path, pages: int, runs: int, env: Optional[Dict[str, str]] = None) -> List[float]:
    with running_screen(folder, "--no-idle", env=env) as screen:
        return asyncio.run(timed(screen.base, pages, runs))
