"""The screen's web API: the face routes every page has (web/face_api.py) over a `ScreenFace`, and
`GET /api/state`.

`/` is the screen's page (static/screen.html): the face alone, filling the
window. Imported only once the `studio` extra is known to be there.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Callable, Dict

from starlette.concurrency import run_in_threadpool
from starlette.requests import Request
from starlette.responses import JSONResponse, Response
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles

from ..drawing.renderer import Renderer
from ..web.face_api import FaceApi, answered
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

    def routes(self) -> list:
        return [
            Route("/api/state", self.state),
            Mount("/static/screen", StaticFiles(directory=str(STATIC), check_dir=False), name="screen"),
            *self.face_routes(),
        ]

    def take(self, text: str) -> Dict[str, Any]:
        return self.face.command(text)

    def opened(self) -> None:
        self.face.open()

    @answered
    async def state(self, request: Request) -> Response:
        state = await run_in_threadpool(self.face.state)
        return JSONResponse({**state, "screens": len(self.pages.queues)})
