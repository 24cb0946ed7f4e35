"""The studio's HTTP API and WebSocket over a `Workspace`: one method a route.

Imported only once the `studio` extra is known to be there. A request that
goes wrong is answered in JSON with its error and logged in one line; the
server carries on.
"""

from __future__ import annotations

import asyncio
import json
import re
from pathlib import Path
from typing import Any, Awaitable, Callable, Dict, Optional

from starlette.applications import Starlette
from starlette.concurrency import run_in_threadpool
from starlette.exceptions import HTTPException
from starlette.requests import Request
from starlette.responses import FileResponse, JSONResponse, Response
from starlette.routing import Mount, Route, WebSocketRoute
from starlette.staticfiles import StaticFiles
from starlette.websockets import WebSocket, WebSocketDisconnect

from ..core.tables import LIMITS
from ..drawing.renderer import Renderer
from ..extras import MissingTool
from ..language.diagnostics import ScriptError, shortened
from .guard import Guard
from .pump import Frames, Pages, Pump, log
from .workspace import SaveConflict, Workspace, check_text, diagnostics_json

STATIC = Path(__file__).resolve().parent / "static"
SOUND_KEY = re.compile(r"[0-9a-f]{16}")  # as `preview.sound_key` makes them
TRANSPORT_ACTIONS = ("play", "pause", "seek", "loop")
HEAVY_WAITING = 16  # scripts waiting to be parsed before more are refused
LOGGED = 300  # characters of an error's reason the log keeps: one line, whatever was sent
Handler = Callable[[Any, Request], Awaitable[Response]]


def create_app(workspace: Workspace, renderer: Renderer, fps: float = 30.0, token: Optional[str] = None):
    """The studio's ASGI application, behind its guard (loopback, same site, the token)."""
    api = StudioApi(workspace, renderer, fps)
    app = Starlette(routes=api.routes(), exception_handlers={HTTPException: _not_here})
    return Guard(app, token, log)


class TooLarge(Exception):
    pass


class BadRequest(Exception):
    pass


class Busy(Exception):
    pass


class Heavy:
    """Parsing and compiling scripts, one at a time, with a bounded queue.

    They are pure Python and hold the GIL: run side by side, a flood of them
    took the frame pump's turns and the preview stopped for seconds. One at a
    time, the pump gets the GIL back within a switch interval; past
    `HEAVY_WAITING` requests waiting, more are refused (429) rather than queued.
    """

    def __init__(self) -> None:
        self._one: Optional[asyncio.Semaphore] = None  # made in the server's loop (Python 3.8)
        self.waiting = 0

    async def run(self, work: Callable[..., Any], *args: Any) -> Any:
        if self._one is None:
            self._one = asyncio.Semaphore(1)
        if self.waiting >= HEAVY_WAITING:
            raise Busy(f"busy: {self.waiting} scripts are waiting to be checked; try again in a moment")
        self.waiting += 1
        try:
            async with self._one:
                return await run_in_threadpool(work, *args)
        finally:
            self.waiting -= 1


def answered(handler: Handler) -> Handler:
    """A route whose failures are answered in JSON and logged, never raised to the server."""

    async def wrapped(self: StudioApi, request: Request) -> Response:
        self.pump.start()
        try:
            response = await handler(self, request)
        except Busy as e:
            response = JSONResponse({"error": str(e)}, 429, headers={"retry-after": "1"})
        except TooLarge:
            response = JSONResponse({"error": f"too large: the limit is {LIMITS.max_bytes} bytes"}, 413)
        except BadRequest as e:
            response = JSONResponse({"error": str(e)}, 400)
        except Exception as e:  # logged and answered; the studio carries on
            response = JSONResponse({"error": f"{type(e).__name__}: {e}"}, 500)
        if response.status_code >= 400:
            log(f"{request.method} {request.url.path}: {response.status_code} {_reason(response)}")
        return response

    return wrapped


class StudioApi:
    def __init__(self, workspace: Workspace, renderer: Renderer, fps: float) -> None:
        self.workspace = workspace
        self.frames = Frames(renderer)
        self.pages = Pages()
        self.pump = Pump(workspace, self.frames, self.pages, fps)
        self.heavy = Heavy()

    def routes(self) -> list:
        return [
            Route("/", self.index),
            Route("/api/state", self.state),
            Route("/api/check", self.check, methods=["POST"]),
            Route("/api/script", self.script, methods=["POST"]),
            Route("/api/save", self.save, methods=["POST"]),
            Route("/api/command", self.command, methods=["POST"]),
            Route("/api/transport", self.transport, methods=["POST"]),
            Route("/api/robot", self.robot, methods=["POST"]),
            Route("/api/session/export", self.export, methods=["POST"]),
            Route("/api/session/clear", self.clear, methods=["POST"]),
            Route("/api/frame.jpg", self.frame),
            Route("/api/sound/{key}.wav", self.sound),
            WebSocketRoute("/api/live", self.live),
            Mount("/static", StaticFiles(directory=str(STATIC), check_dir=False), name="static"),
        ]

    @answered
    async def index(self, request: Request) -> Response:
        return FileResponse(STATIC / "index.html", headers={"cache-control": "no-store"})

    @answered
    async def state(self, request: Request) -> Response:
        return JSONResponse(await run_in_threadpool(self.workspace.state))

    @answered
    async def check(self, request: Request) -> Response:
        text = await _body_text(request)
        return JSONResponse(await self.heavy.run(check_text, text, self.workspace.name))

    @answered
    async def script(self, request: Request) -> Response:
        answer = await self.heavy.run(self.workspace.update, await _body_text(request))
        self.pump.wake()
        return JSONResponse(answer)

    @answered
    async def save(self, request: Request) -> Response:
        text = await _body_text(request)
        base = request.query_params.get("base")
        if request.query_params.get("force") == "1":
            base = None
        elif base is not None and not re.fullmatch(r"[0-9]{1,9}", base):
            raise BadRequest(f"base must be a version number, not {base[:20]!r}")
        try:
            saved = await run_in_threadpool(self.workspace.save, text, None if base is None else int(base))
        except SaveConflict as e:  # the page asks before it overwrites
            return JSONResponse({"error": str(e), "conflict": True, "version": e.version}, 409)
        except OSError as e:
            return JSONResponse({"error": f"cannot save {self.workspace.name}: {e.strerror or e}"}, 500)
        return JSONResponse(saved)

    @answered
    async def command(self, request: Request) -> Response:
        text = await _body_text(request)
        if not text.strip():
            return JSONResponse({"diagnostics": [_problem("no command: the body is empty")]}, 400)
        try:
            at = await self.heavy.run(self.workspace.command, text)
        except ScriptError as e:
            return JSONResponse({"diagnostics": diagnostics_json(e.diagnostics)}, 400)
        except MissingTool as e:  # `say` with no speech engine here
            return JSONResponse({"diagnostics": [_problem(str(e))]}, 400)
        self.pump.wake()
        session = self.workspace.session()
        self.pages.send({"kind": "session", "session": session})
        return JSONResponse({"at": at, "session": session})

    @answered
    async def transport(self, request: Request) -> Response:
        body = await _body_json(request)
        action, on = body.get("action"), body.get("on", False)
        if action not in TRANSPORT_ACTIONS:
            raise BadRequest(
                f"'action' must be one of {', '.join(TRANSPORT_ACTIONS)}, not {json.dumps(action)}"
            )
        if action == "seek" and not _is_number(body.get("t")):
            raise BadRequest(f"'seek' needs 't', the script time in seconds, not {json.dumps(body.get('t'))}")
        if action == "loop" and not isinstance(on, bool):
            raise BadRequest(f"'loop' needs 'on', true or false, not {json.dumps(on)}")
        status = self.workspace.transport(action, float(body.get("t") or 0.0), on)
        self.pump.wake()
        return JSONResponse(status)

    @answered
    async def robot(self, request: Request) -> Response:
        body = await _body_json(request)
        return JSONResponse(await run_in_threadpool(self.workspace.robot.switch, bool(body.get("on"))))

    @answered
    async def export(self, request: Request) -> Response:
        try:
            return JSONResponse(await run_in_threadpool(self.workspace.export_session))
        except OSError as e:
            return JSONResponse({"error": f"cannot write the session: {e.strerror or e}"}, 500)

    @answered
    async def clear(self, request: Request) -> Response:
        session = self.workspace.clear_session()
        self.pages.send({"kind": "session", "session": session})
        self.pump.wake()
        return JSONResponse(session)

    @answered
    async def frame(self, request: Request) -> Response:
        jpeg = await run_in_threadpool(self.frames.jpeg, self.workspace.face())
        return Response(jpeg, media_type="image/jpeg", headers={"cache-control": "no-store"})

    @answered
    async def sound(self, request: Request) -> Response:
        key = request.path_params["key"]
        wav = await run_in_threadpool(self.workspace.sound, key) if SOUND_KEY.fullmatch(key) else None
        if wav is None:
            return JSONResponse({"error": "no such sound in the script or the session"}, 404)
        return Response(wav, media_type="audio/wav", headers={"cache-control": "private, max-age=3600"})

    async def live(self, websocket: WebSocket) -> None:
        """A page's connection: the frame and status now, then whatever the pump sends."""
        self.pump.start()
        await websocket.accept()
        queue = self.pages.add()
        try:
            await websocket.send_bytes(await run_in_threadpool(self.frames.jpeg, self.workspace.face()))
            await websocket.send_text(json.dumps(self.workspace.status()))
            while True:
                item = await queue.get()
                if isinstance(item, bytes):
                    await websocket.send_bytes(item)
                else:
                    await websocket.send_text(json.dumps(item))
        except (WebSocketDisconnect, RuntimeError, OSError):
            pass
        finally:
            self.pages.remove(queue)


async def _body_text(request: Request) -> str:
    """The body as text, read no further than the largest script the studio takes."""
    chunks, size = [], 0
    async for chunk in request.stream():
        chunks.append(chunk)
        size += len(chunk)
        if size > LIMITS.max_bytes + 1024:
            raise TooLarge()
    return b"".join(chunks).decode("utf-8", "replace")


async def _body_json(request: Request) -> Dict[str, Any]:
    try:
        value = json.loads(await _body_text(request) or "{}")
    except ValueError as e:
        raise BadRequest(f"the body must be JSON: {e}") from None
    if not isinstance(value, dict):
        raise BadRequest("the body must be a JSON object")
    return value


async def _not_here(request: Request, exc: Exception) -> Response:
    """Starlette's own 404 and 405, answered in JSON like the rest and logged."""
    code = getattr(exc, "status_code", 404)
    why = f"{request.method} is not taken here" if code == 405 else "nothing is here"
    log(f"{request.method} {request.url.path}: {code} {why}")
    return JSONResponse({"error": why}, code)


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and abs(value) < float("inf")


def _reason(response: Any) -> str:
    """What an error answer says, for the log: its error, or its first diagnostic."""
    try:
        answer = json.loads(bytes(response.body))
        if "diagnostics" in answer:
            first = answer["diagnostics"][0]
            place = f"{first['line']}:{first['column']}: " if first["line"] else ""
            return shortened(f"{place}{first['message']}", LOGGED)
        return shortened(str(answer["error"]), LOGGED)
    except (ValueError, KeyError, IndexError, TypeError, AttributeError):
        return "(no reason given)"


def _problem(message: str) -> Dict[str, Any]:
    """A diagnostic with no place in the text."""
    return {"line": 0, "column": 0, "severity": "error", "message": message}
