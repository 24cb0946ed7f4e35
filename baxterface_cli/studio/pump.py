"""The frame pump: the preview drawn when the face changes and handed to every open page.

It runs in the server's event loop, at most `fps` times a second and at once
when woken (after a press); it also tells the pages the preview's status and
what changed on disk (the script, the panel).
"""

from __future__ import annotations

import asyncio
import contextlib
import io
import sys
import threading
import time
from typing import Any, Optional, Set

from ..drawing.renderer import Renderer
from .workspace import Workspace

STATUS_EVERY = 0.1  # seconds between status messages to the page
DISK_EVERY = 0.5  # seconds between looks at the script and the panel on disk
JPEG_QUALITY = 85


def log(message: str) -> None:
    print(f"baxterface studio: {message}", file=sys.stderr, flush=True)


class Frames:
    """The preview drawn and encoded: one renderer, one thread at a time."""

    def __init__(self, renderer: Renderer) -> None:
        self.renderer = renderer
        self.lock = threading.Lock()
        self.last_state: Any = None
        self.last_jpeg = b""

    def jpeg(self, state: Any) -> bytes:
        from PIL import Image

        with self.lock:
            if state == self.last_state and self.last_jpeg:
                return self.last_jpeg
            bgr = self.renderer.render(state)
            out = io.BytesIO()
            Image.fromarray(bgr[:, :, ::-1]).save(out, "JPEG", quality=JPEG_QUALITY)
            self.last_state, self.last_jpeg = state, out.getvalue()
            return self.last_jpeg


class Pages:
    """The open pages: each gets the newest frame and messages; a slow page skips frames, not messages."""

    def __init__(self) -> None:
        self.queues: Set[asyncio.Queue] = set()

    def add(self) -> asyncio.Queue:
        queue: asyncio.Queue = asyncio.Queue(maxsize=64)
        self.queues.add(queue)
        return queue

    def remove(self, queue: asyncio.Queue) -> None:
        self.queues.discard(queue)

    def send(self, item: Any) -> None:
        for queue in list(self.queues):
            if queue.full():  # a page that does not keep up: drop its oldest
                queue.get_nowait()
            queue.put_nowait(item)


class Pump:
    """Draws and sends what the pages show; started by the first request, in the server's loop."""

    def __init__(self, workspace: Workspace, frames: Frames, pages: Pages, fps: float) -> None:
        self.workspace, self.frames, self.pages, self.fps = workspace, frames, pages, fps
        self._wake: Optional[asyncio.Event] = None
        self._task: Optional[asyncio.Task] = None

    def start(self) -> None:
        if self._task is None:
            self._wake = asyncio.Event()  # Python 3.8 ties an Event to the loop it is made in
            self._task = asyncio.get_running_loop().create_task(self._run())

    def wake(self) -> None:
        """Draw now rather than at the next tick: something changed."""
        if self._wake is not None:
            self._wake.set()

    async def _run(self) -> None:
        from starlette.concurrency import run_in_threadpool

        assert self._wake is not None
        workspace, pages = self.workspace, self.pages
        last_status = last_disk = 0.0
        shown: Any = None
        heard: Any = []
        while True:
            with contextlib.suppress(asyncio.TimeoutError):
                await asyncio.wait_for(self._wake.wait(), timeout=1.0 / self.fps)
            self._wake.clear()
            try:
                face = workspace.face()
                if pages.queues and face != shown:
                    pages.send(await run_in_threadpool(self.frames.jpeg, face))
                    shown = face
                now = time.monotonic()
                status = workspace.status()
                # A sound that starts or stops is told at once: the page plays it in step with the frames.
                if now - last_status >= STATUS_EVERY or status["sounds"] != heard:
                    pages.send(status)
                    last_status, heard = now, status["sounds"]
                if now - last_disk >= DISK_EVERY:
                    last_disk = now
                    for change in await run_in_threadpool(workspace.disk_changes):
                        pages.send(change)
                        if change["kind"] == "disk":
                            pages.send({"kind": "timeline", "timeline": workspace.timeline()})
            except Exception as e:  # the pump must not die with one bad frame
                log(f"preview: {type(e).__name__}: {e}")
