"""The frame pump: the face drawn when it changes and handed to every open page.

It runs in the server's event loop, `fps` times a second and at once when
woken (after a command); it also tells the pages the face's status (what
is being said, for the page to play in step) and, for the studio, what
changed on disk (the script, the panel). The studio's preview and the screen
both show their face through it.
"""

from __future__ import annotations

import asyncio
import io
import threading
import time
from typing import Any, Callable, Dict, List, Optional, Protocol

import numpy as np

from ..drawing.renderer import Renderer
from ..drawing.touch_places import TouchMap
from ..engine.change_polling import ChangePolling
from .pages import Pages

STATUS_EVERY = 0.1  # seconds between status messages to the page
DISK_EVERY = 0.5  # seconds between looks at the script and the panel on disk
JPEG_QUALITY = 85
EARLY = 0.0005  # seconds a timer may wake before its time (the clock's grain) and still be on time


class Shown(Protocol):
    """What the pages show: the studio's workspace, or the screen's live face, on its own clock.

    The pump lets time pass (`step`), then reads the face and the status at that time: reads,
    which move nothing.
    """

    clock: Callable[[], float]

    def step(self, now: float) -> None: ...

    def face(self, now: float) -> Any: ...

    def status(self, now: float) -> Dict[str, Any]: ...


class Frames:
    """The face drawn and encoded: one renderer, one thread at a time."""

    def __init__(self, renderer: Renderer) -> None:
        self.renderer = renderer
        self.lock = threading.Lock()
        self.last_key: Any = None
        self.last_jpeg = b""
        self.drawn: Optional[TouchMap] = None  # the places on the last frame drawn, for a tap on it

    def key(self, state: Any) -> Any:
        """Equal for two states exactly when their frames are the same (the renderer's frame key)."""
        with self.lock:
            return self.renderer.frame_key(state)

    def place(self, state: Any, x: float, y: float) -> str:
        """Where on the face, as drawn for `state`, a tap at (x, y) lands (fractions of the frame):
        a place `touch` names, or "" for anywhere else."""
        with self.lock:
            return TouchMap(self.renderer.layers, state).place(x, y)

    def jpeg(self, state: Any) -> bytes:
        from PIL import Image

        with self.lock:
            key = self.renderer.frame_key(state)
            if key == self.last_key and self.last_jpeg:
                return self.last_jpeg
            bgr = np.ascontiguousarray(self.renderer.render(state))
            height, width = bgr.shape[:2]
            # Read as BGR where it lies: a flipped view (bgr[..., ::-1]) made Pillow copy it pixel by
            # pixel first, which took longer than the encoding (18 ms against 7 at 1024x600).
            image = Image.frombuffer("RGB", (width, height), bgr, "raw", "BGR", 0, 1)
            out = io.BytesIO()
            image.save(out, "JPEG", quality=JPEG_QUALITY)
            self.last_key, self.last_jpeg = key, out.getvalue()
            self.drawn = TouchMap(self.renderer.layers, state)
            return self.last_jpeg


class Pump:
    """Draws and sends what the pages show; started by the first request, in the server's loop.

    `watch`, when given, is asked every `DISK_EVERY` seconds (in a thread) for
    messages to pass on to the pages.
    """

    def __init__(
        self,
        shown: Shown,
        frames: Frames,
        pages: Pages,
        fps: float,
        log: Callable[[str], None],
        status_every: float = STATUS_EVERY,
        watch: Optional[Callable[[], List[Dict[str, Any]]]] = None,
    ) -> None:
        self.shown, self.frames, self.pages, self.fps = shown, frames, pages, fps
        self.log, self.status_every, self.watch = log, status_every, watch
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

    async def _woken(self, timeout: float) -> bool:
        """Wait for a wake, `timeout` seconds at most: was there one? Not `asyncio.wait_for`, which
        before Python 3.12 loses a cancel that comes as the wait ends: with wakes every few
        milliseconds, the server's shutdown waited for the pump for ever."""
        assert self._wake is not None
        waiting = asyncio.ensure_future(self._wake.wait())
        try:
            done, _ = await asyncio.wait({waiting}, timeout=timeout)
        finally:
            waiting.cancel()
        return bool(done)

    async def _run(self) -> None:
        from starlette.concurrency import run_in_threadpool

        assert self._wake is not None
        shown, pages = self.shown, self.pages
        period = 1.0 / self.fps
        tick = time.monotonic()
        change_polling = ChangePolling()  # after a command (as the face node): looked at often until it shows
        last_status = last_disk = 0.0
        next_frame = 0.0  # no frame before: however many commands come, at most `fps` frames a second
        drawn: Any = None
        heard: Any = []
        while True:
            now = time.monotonic()
            at = max(change_polling.next_look(tick, now), min(next_frame, tick))
            woken = await self._woken(max(0.0, at - now))
            self._wake.clear()
            now = time.monotonic()
            if woken:
                change_polling.heard(now)
            if now >= tick:
                # Ticks keep their own rhythm, however long a frame took; a late pump skips the
                # ticks it missed rather than hurrying to catch up.
                tick += period
                if tick < now:
                    tick = now + period
            try:
                # With no page open nothing is looked at: a page that opens is sent the face as it is
                # then (face_api.py), as the first page always was, before the pump started.
                pages.catch_up()  # a page that was still sending the last frame is sent the newest
                if pages.open:
                    at_clock = shown.clock()
                    shown.step(at_clock)
                    # A command wakes the pump at once; a flood of them must not draw more often.
                    face = shown.face(at_clock) if now >= next_frame - EARLY else None
                    key = self.frames.key(face) if face is not None else drawn
                    if key != drawn:  # a new state may still draw the same frame: none is sent
                        pages.send(await run_in_threadpool(self.frames.jpeg, face))
                        drawn = key
                        change_polling.shown()
                        # From when this look was due, not when the loop got to it: frames at the
                        # ticks keep the ticks' rhythm.
                        next_frame = min(at, now) + period
                    status = shown.status(at_clock)
                    # A sound that starts or stops is told at once: the page plays it in step with the frames.
                    if now - last_status >= self.status_every or status["sounds"] != heard:
                        pages.send(status)
                        last_status, heard = now, status["sounds"]
                if self.watch is not None and now - last_disk >= DISK_EVERY:
                    last_disk = now
                    for change in await run_in_threadpool(self.watch):
                        pages.send(change)
            except Exception as e:  # the pump must not die with one bad frame
                self.log(f"drawing the face: {type(e).__name__}: {e}")
