"""The screen's web API: the face routes every page has (web/face_api.py) over a `ScreenFace`,
`GET /api/state`, and the events that reach its handlers: `POST /api/event` (one event line, as
in an events file without its time: web/face_api.py's, as the studio's) and `POST /api/touch`
(where the page was tapped: web/face_api.py's too).

`/` is the screen's page (static/screen.html): the face alone, filling the
window. Imported only once the `studio` extra is known to be there.
"""

from __future__ import annotations

import asyncio
import contextlib
from pathlib import Path
from typing import Any, Callable, Dict

from starlette.concurrency import run_in_threadpool
from starlette.requests import Request
from starlette.responses import JSONResponse, Response
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles

from ..drawing.renderer import Renderer
from ..engine.session_intake import Refused
from ..language import syntax_tree as n
from ..language.events import in_words
from ..web.face_api import Busy, FaceApi, answered
from .screen_face import ScreenFace

STATIC = Path(__file__).resolve().parent / "static"
# The page needs no status ten times a second as the studio's transport does: once a second it
# tells the page the connection lives; a sound that starts or stops is told at once all the same.
STATUS_EVERY = 1.0


class ScreenApi(FaceApi):
    page = STATIC / "screen.html"

    def __init__(self, face: ScreenFace, renderer: Renderer, fps: float, log: Callable[[str], None]) -> None:
        super().__init__(face, renderer, fps, log, status_every=STATUS_EVERY)
        self.face = face
        face.ready, face.log = self._step_began, log

    def _step_began(self) -> None:
        """The session's worker began a step (on its thread): the pump draws it now, not next tick."""
        loop = self.loop
        if loop is not None:
            with contextlib.suppress(RuntimeError):  # the loop has closed: the server stopped
                loop.call_soon_threadsafe(self.pump.wake)

    def routes(self) -> list:
        return [
            Route("/api/state", self.state),
            Route("/api/event", self.event, methods=["POST"]),
            Route("/api/touch", self.touch, methods=["POST"]),
            Mount("/static/screen", StaticFiles(directory=str(STATIC), check_dir=False), name="screen"),
            *self.face_routes(),
        ]

    def take(self, text: str) -> Dict[str, Any]:
        try:
            return self.face.command(text)
        except Refused as e:
            raise Busy(str(e)) from None

    def opened(self) -> None:
        self.face.open()

    def fire(self, event: n.Event, source: str) -> Dict[str, Any]:
        return self.face.post(event, source)

    async def firing(self, event: n.Event, source: str) -> Dict[str, Any]:
        """Waited for in the loop, holding no thread: a storm of events while a handler's `say` is
        compiled must not take the threads the frames are drawn in."""
        try:
            moved = await asyncio.wrap_future(self.face.posting(event, source))
        except Refused as e:
            raise Busy(str(e)) from None
        return {"event": in_words(event), **moved}

    @answered
    async def state(self, request: Request) -> Response:
        state = await run_in_threadpool(self.face.state)
        return JSONResponse({**state, "screens": len(self.pages.open)})
