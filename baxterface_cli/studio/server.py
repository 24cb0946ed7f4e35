"""The studio on the web: Starlette routes over a `Workspace`, frames pushed over a WebSocket.

A frame pump draws the preview with the project's renderer whenever the face
changes (at most `fps` times a second, and at once after a press), encodes
it as JPEG and hands it to every open page; it also watches the script and
the panel on disk. A request that goes wrong is logged in one line and
answered with its error; the server carries on.
"""

from __future__ import annotations

import asyncio
import contextlib
import io
import json
import re
import sys
import threading
import time
from pathlib import Path
from typing import Any, Awaitable, Callable, Dict, Optional, Set

from ..core.tables import LIMITS
from ..drawing.renderer import Renderer
from ..extras import MissingTool
from ..language.diagnostics import ScriptError
from .guard import Guard
from .workspace import SaveConflict, Workspace, diagnostics_json

STATIC = Path(__file__).resolve().parent / "static"
STATUS_EVERY = 0.1  # seconds between status messages to the page
DISK_EVERY = 0.5  # seconds between looks at the script and the panel on disk
JPEG_QUALITY = 85
SOUND_KEY = re.compile(r"[0-9a-f]{16}")  # as `preview.sound_key` makes them


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


def create_app(workspace: Workspace, renderer: Renderer, fps: float = 30.0, token: Optional[str] = None):
    """The studio's ASGI application."""
    from starlette.applications import Starlette
    from starlette.concurrency import run_in_threadpool
    from starlette.exceptions import HTTPException
    from starlette.requests import Request
    from starlette.responses import FileResponse, JSONResponse, Response
    from starlette.routing import Mount, Route, WebSocketRoute
    from starlette.staticfiles import StaticFiles
    from starlette.websockets import WebSocket, WebSocketDisconnect

    frames = Frames(renderer)
    pages = Pages()
    pump: Dict[str, Any] = {}  # the frame pump's task and the event that wakes it, made in the server's loop

    def wake() -> None:
        if "wake" in pump:
            pump["wake"].set()

    async def body_text(request: Request) -> str:
        data = b""
        async for chunk in request.stream():
            data += chunk
            if len(data) > LIMITS.max_bytes + 1024:
                raise TooLarge()
        return data.decode("utf-8", "replace")

    async def body_json(request: Request) -> Dict[str, Any]:
        try:
            value = json.loads(await body_text(request) or "{}")
        except ValueError as e:
            raise BadRequest(f"the body must be JSON: {e}") from None
        if not isinstance(value, dict):
            raise BadRequest("the body must be a JSON object")
        return value

    def endpoint(
        handler: Callable[[Request], Awaitable[Response]],
    ) -> Callable[[Request], Awaitable[Response]]:
        async def wrapped(request: Request) -> Response:
            start_pump()
            try:
                response = await handler(request)
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

    @endpoint
    async def index(request: Request) -> Response:
        return FileResponse(STATIC / "index.html", headers={"cache-control": "no-store"})

    @endpoint
    async def state(request: Request) -> Response:
        return JSONResponse(await run_in_threadpool(workspace.state))

    @endpoint
    async def check(request: Request) -> Response:
        from .workspace import check_text

        text = await body_text(request)
        return JSONResponse(await run_in_threadpool(check_text, text, workspace.name))

    @endpoint
    async def script(request: Request) -> Response:
        text = await body_text(request)
        answer = await run_in_threadpool(workspace.update, text)
        wake()
        return JSONResponse(answer)

    @endpoint
    async def save(request: Request) -> Response:
        text = await body_text(request)
        base = request.query_params.get("base")
        if request.query_params.get("force") == "1":
            base = None
        elif base is not None and not re.fullmatch(r"[0-9]{1,9}", base):
            return JSONResponse({"error": f"base must be a version number, not {base[:20]!r}"}, 400)
        try:
            return JSONResponse(
                await run_in_threadpool(workspace.save, text, None if base is None else int(base))
            )
        except SaveConflict as e:  # the page asks before it overwrites
            return JSONResponse({"error": str(e), "conflict": True, "version": e.version}, 409)
        except OSError as e:
            return JSONResponse({"error": f"cannot save {workspace.name}: {e.strerror or e}"}, 500)

    @endpoint
    async def command(request: Request) -> Response:
        text = await body_text(request)
        if not text.strip():
            return JSONResponse({"diagnostics": [_problem("no command: the body is empty")]}, 400)
        try:
            at = await run_in_threadpool(workspace.command, text)
        except ScriptError as e:
            return JSONResponse({"diagnostics": diagnostics_json(e.diagnostics)}, 400)
        except MissingTool as e:  # `say` with no speech engine here
            return JSONResponse({"diagnostics": [_problem(str(e))]}, 400)
        wake()
        session = workspace.session()
        pages.send({"kind": "session", "session": session})
        return JSONResponse({"at": at, "session": session})

    @endpoint
    async def transport(request: Request) -> Response:
        body = await body_json(request)
        action, on = body.get("action"), body.get("on", False)
        if action not in TRANSPORT_ACTIONS:
            raise BadRequest(
                f"'action' must be one of {', '.join(TRANSPORT_ACTIONS)}, not {json.dumps(action)}"
            )
        if action == "seek" and not _is_number(body.get("t")):
            raise BadRequest(f"'seek' needs 't', the script time in seconds, not {json.dumps(body.get('t'))}")
        if action == "loop" and not isinstance(on, bool):
            raise BadRequest(f"'loop' needs 'on', true or false, not {json.dumps(on)}")
        status = workspace.transport(action, float(body.get("t") or 0.0), on)
        wake()
        return JSONResponse(status)

    @endpoint
    async def robot(request: Request) -> Response:
        body = await body_json(request)
        return JSONResponse(await run_in_threadpool(workspace.robot.switch, bool(body.get("on"))))

    @endpoint
    async def export(request: Request) -> Response:
        try:
            return JSONResponse(await run_in_threadpool(workspace.export_session))
        except OSError as e:
            return JSONResponse({"error": f"cannot write the session: {e.strerror or e}"}, 500)

    @endpoint
    async def clear(request: Request) -> Response:
        session = workspace.clear_session()
        pages.send({"kind": "session", "session": session})
        wake()
        return JSONResponse(session)

    @endpoint
    async def frame(request: Request) -> Response:
        jpeg = await run_in_threadpool(frames.jpeg, workspace.face())
        return Response(jpeg, media_type="image/jpeg", headers={"cache-control": "no-store"})

    @endpoint
    async def sound(request: Request) -> Response:
        key = request.path_params["key"]
        wav = await run_in_threadpool(workspace.sound, key) if SOUND_KEY.fullmatch(key) else None
        if wav is None:
            return JSONResponse({"error": "no such sound in the script or the session"}, 404)
        return Response(wav, media_type="audio/wav", headers={"cache-control": "private, max-age=3600"})

    async def live(websocket: WebSocket) -> None:
        start_pump()
        await websocket.accept()
        queue = pages.add()
        try:
            await websocket.send_bytes(await run_in_threadpool(frames.jpeg, workspace.face()))
            await websocket.send_text(json.dumps(workspace.status()))
            while True:
                item = await queue.get()
                if isinstance(item, bytes):
                    await websocket.send_bytes(item)
                else:
                    await websocket.send_text(json.dumps(item))
        except (WebSocketDisconnect, RuntimeError, OSError):
            pass
        finally:
            pages.remove(queue)

    async def run_pump() -> None:
        last_status = last_disk = 0.0
        shown: Any = None
        heard: Any = []
        while True:
            with contextlib.suppress(asyncio.TimeoutError):
                await asyncio.wait_for(pump["wake"].wait(), timeout=1.0 / fps)
            pump["wake"].clear()
            try:
                face = workspace.face()
                if pages.queues and face != shown:
                    pages.send(await run_in_threadpool(frames.jpeg, face))
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

    def start_pump() -> None:
        if "task" not in pump:
            pump["wake"] = asyncio.Event()  # Python 3.8 ties an Event to the loop it is made in
            pump["task"] = asyncio.get_running_loop().create_task(run_pump())

    routes = [
        Route("/", index),
        Route("/api/state", state),
        Route("/api/check", check, methods=["POST"]),
        Route("/api/script", script, methods=["POST"]),
        Route("/api/save", save, methods=["POST"]),
        Route("/api/command", command, methods=["POST"]),
        Route("/api/transport", transport, methods=["POST"]),
        Route("/api/robot", robot, methods=["POST"]),
        Route("/api/session/export", export, methods=["POST"]),
        Route("/api/session/clear", clear, methods=["POST"]),
        Route("/api/frame.jpg", frame),
        Route("/api/sound/{key}.wav", sound),
        WebSocketRoute("/api/live", live),
        Mount("/static", StaticFiles(directory=str(STATIC), check_dir=False), name="static"),
    ]

    async def not_here(request: Request, exc: Exception) -> Response:
        """Starlette's own 404 and 405, answered in JSON like the rest and logged."""
        code = getattr(exc, "status_code", 404)
        why = f"{request.method} is not taken here" if code == 405 else "nothing is here"
        log(f"{request.method} {request.url.path}: {code} {why}")
        return JSONResponse({"error": why}, code)

    return Guard(Starlette(routes=routes, exception_handlers={HTTPException: not_here}), token, log)


class TooLarge(Exception):
    pass


class BadRequest(Exception):
    pass


TRANSPORT_ACTIONS = ("play", "pause", "seek", "loop")


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and abs(value) < float("inf")


def _reason(response: Any) -> str:
    """What an error answer says, for the log: its error, or its first diagnostic."""
    try:
        answer = json.loads(bytes(response.body))
        if "diagnostics" in answer:
            first = answer["diagnostics"][0]
            place = f"{first['line']}:{first['column']}: " if first["line"] else ""
            return f"{place}{first['message']}"
        return str(answer["error"])
    except (ValueError, KeyError, IndexError, TypeError, AttributeError):
        return "(no reason given)"


def _problem(message: str) -> Dict[str, Any]:
    """A diagnostic with no place in the text."""
    return {"line": 0, "column": 0, "severity": "error", "message": message}


def serve(app: Any, sock: Any, ready: Callable[[], None]) -> Optional[int]:
    """Run `app` on the bound socket until Ctrl-C or SIGTERM; returns the signal that stopped it.

    `ready` is called once the server answers. A signal never interrupts the
    set-up (under Python 3.8, Ctrl-C inside logging's set-up broke a lock): one
    that comes before uvicorn takes the signals over is kept, and stops the
    server as soon as it is up; uvicorn hands back the ones it caught the same way.
    """
    import signal

    import uvicorn

    stops: list = []

    def keep(signum: int, frame: Any) -> None:
        stops.append(signum)

    handled = (signal.SIGINT, signal.SIGTERM)
    before = {signum: signal.signal(signum, keep) for signum in handled}

    class Server(uvicorn.Server):
        async def startup(self, sockets: Any = None) -> None:
            await super().startup(sockets=sockets)
            if stops:
                self.should_exit = True
            elif not self.should_exit:
                ready()

    try:
        config = uvicorn.Config(app, log_level="warning", lifespan="off", ws_max_size=4 * 1024 * 1024)
        Server(config).run(sockets=[sock])
    finally:
        for signum, handler in before.items():
            signal.signal(signum, handler)
    return stops[0] if stops else None


def bind(host: str, port: int) -> Any:
    """A listening socket on host:port (port 0: any free one); OSError when it is taken."""
    import socket

    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    # Frames go out at once, not held back for the page's acknowledgement (Nagle's delay);
    # the connections accepted inherit it.
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    try:
        sock.bind((host, port))
    except OSError:
        sock.close()
        raise
    sock.set_inheritable(True)
    return sock


def this_machine() -> str:
    """This machine's address on its network (where its default route leaves), else its name."""
    import socket

    try:
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
            probe.connect(("192.0.2.1", 9))  # a documentation address: connecting UDP sends nothing
            address = probe.getsockname()[0]
    except OSError:  # no route at all
        address = ""
    return address if address and not address.startswith(("127.", "0.")) else socket.gethostname()


def url_for(host: str, port: int, token: Optional[str]) -> str:
    """The address to open; serving on every address, the one the lab's other machines reach."""
    if host in ("0.0.0.0", "::", ""):
        host = this_machine()
    shown = f"[{host}]" if ":" in host else host
    return f"http://{shown}:{port}/" + (f"?token={token}" if token else "")
