"""The web API a face is shown through, shared by the studio and the screen.

The page itself, commands (`POST /api/command`, and the same path for a
command heard elsewhere, as on ROS), the frame now, the sounds of what is
said, and the WebSocket that pushes frames and status to every open page.
Imported only once the `studio` extra is known to be there. A request that
goes wrong is answered in JSON with its error and logged in one line; the
server carries on.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import json
import threading
import time
from pathlib import Path
from typing import Any, Awaitable, Callable, Dict, List, Optional, Tuple

from starlette.applications import Starlette
from starlette.concurrency import run_in_threadpool
from starlette.exceptions import HTTPException
from starlette.requests import Request
from starlette.responses import FileResponse, JSONResponse, Response
from starlette.routing import Mount, Route, WebSocketRoute
from starlette.staticfiles import StaticFiles
from starlette.websockets import WebSocket, WebSocketDisconnect

from ..core.face_constants import LIMITS
from ..drawing.renderer import Renderer
from ..extras import MissingTool
from ..language import syntax_tree as n
from ..language.diagnostics import ScriptError, shortened
from ..language.event_line import read_event_line
from ..language.source import decode
from .answers import diagnostics_json, problem
from .frame_pump import STATUS_EVERY, Frames, Pump, Shown
from .pages import BINARY, TEXT, Pages, message, transport_of
from .refusal_log import RefusalLog, echoed
from .request_guard import Guard
from .sounds import SOUND_KEY

HEAVY_WAITING = 16  # scripts waiting to be parsed before more are refused
LOGGED = 300  # characters of an error's reason the log keeps: one line, whatever was sent
HANDED_OVER = 30.0  # seconds a command from another thread waits to be taken
Handler = Callable[[Any, Request], Awaitable[Response]]


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

    async def wrapped(self: FaceApi, request: Request) -> Response:
        self.start()
        try:
            response = await handler(self, request)
        except Busy as e:
            response = JSONResponse({"error": str(e)}, 429, headers={"retry-after": "1"})
        except TooLarge:
            response = JSONResponse({"error": f"too large: the limit is {LIMITS.max_bytes} bytes"}, 413)
        except BadRequest as e:
            response = JSONResponse({"error": str(e)}, 400)
        except Exception as e:  # logged and answered; the server carries on
            response = JSONResponse({"error": f"{type(e).__name__}: {e}"}, 500)
        if response.status_code >= 400:
            said = f"{echoed(request.method)} {echoed(request.url.path)}: {response.status_code}"
            self.refused(f"{said} {_reason(response)}")
        return response

    return wrapped


class FaceApi:
    """The routes every page that shows a face needs, over what it shows (`shown`).

    A subclass adds its own routes (`routes`), says what a command does
    (`take`, in a worker thread; `told`, in the loop once it is taken), and
    what a page opening means (`opened`).
    """

    page: Path  # the page's HTML
    own_static: Optional[Path] = None  # the page's own files, served at /static before the shared ones

    def __init__(
        self,
        shown: Shown,
        renderer: Renderer,
        fps: float,
        log: Callable[[str], None],
        status_every: float = STATUS_EVERY,
        watch: Optional[Callable[[], List[Dict[str, Any]]]] = None,
    ) -> None:
        self.shown = shown
        self.log = log
        self.refused = RefusalLog(log)
        self.frames = Frames(renderer)
        self.pages = Pages()
        self.pump = Pump(shown, self.frames, self.pages, fps, log, status_every, watch)
        self.heavy = Heavy()
        self.loop: Optional[asyncio.AbstractEventLoop] = None
        self.serving = threading.Event()
        self.closing = threading.Event()

    def app(self, token: Optional[str] = None) -> Guard:
        """The ASGI application, behind its guard (loopback, same site, the token)."""
        app = Starlette(routes=self.routes(), exception_handlers={HTTPException: self.not_here})
        return Guard(app, token, self.log)

    def routes(self) -> list:
        return self.face_routes()

    def face_routes(self) -> list:
        return [
            Route("/", self.index),
            Route("/api/command", self.command, methods=["POST"]),
            Route("/api/frame.jpg", self.frame),
            Route("/api/sound/{key}.wav", self.sound),
            WebSocketRoute("/api/live", self.live),
            Mount("/static", self.static_files(), name="static"),
        ]

    def static_files(self) -> StaticFiles:
        """`/static`: the page's own files, then those every face page loads (static/sound.js and
        static/tap.js)."""
        own = None if self.own_static is None else str(self.own_static)
        return StaticFiles(directory=own, packages=[(__package__, "static")], check_dir=False)

    def start(self) -> None:
        """In the server's loop: the pump runs, and other threads may hand commands over."""
        if self.loop is None:
            self.loop = asyncio.get_running_loop()
            self.serving.set()
        self.pump.start()

    def stop_taking(self) -> None:
        """The server is stopping: commands from other threads are let go, not started. (While
        it stops, its loop still runs; a flood handed over then kept it from ever stopping.)"""
        self.closing.set()

    # -- what a subclass says

    def take(self, text: str) -> Dict[str, Any]:
        """Play a command (in a worker thread): the answer, or ScriptError."""
        raise NotImplementedError

    def told(self, answer: Dict[str, Any]) -> None:
        """A command was taken (in the loop)."""

    def opened(self) -> None:
        """A page opened its live connection."""

    def fire(self, event: n.Event, source: str) -> Dict[str, Any]:
        """An event for the face's handlers (in a worker thread): what it did, or ScriptError."""
        raise NotImplementedError

    async def firing(self, event: n.Event, source: str) -> Dict[str, Any]:
        """Where `fire` runs: a worker thread of the pool (the studio's waits in its editing line)."""
        return await run_in_threadpool(self.fire, event, source)

    # -- events: `POST /api/event` on every page that has one, and what a page raises itself

    @answered
    async def event(self, request: Request) -> Response:
        """One event line, as an events file's without its time (`signal poke`), to the handlers."""
        text = await body_text(request)
        try:
            event = read_event_line(text, "event")
        except ScriptError as e:
            return JSONResponse({"diagnostics": diagnostics_json(e.diagnostics)}, 400)
        return await self.raised(event, "POST /api/event")

    @answered
    async def touch(self, request: Request) -> Response:
        """A tap on the page's face, at `x` and `y`: fractions of the frame's width and height (the
        page knows where it drew the frame; what is drawn there is found here, at this moment).
        Raises `touch` with the place it landed on, or a bare `touch` anywhere else."""
        body = await body_json(request)
        where = [body.get(k) for k in ("x", "y")]
        usage = 'a touch is JSON with x and y, fractions of the frame: {"x": 0.3, "y": 0.4}'
        if not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in where):
            raise BadRequest(usage)
        try:
            x, y = (float(v) for v in where)
        except OverflowError:  # an integer of hundreds of digits: JSON has no bound on them
            raise BadRequest(usage) from None
        # The frame last drawn is what was tapped on: where the tap lands is read from its places
        # here, no face computed again, and the event goes straight to what shows the face.
        drawn = self.frames.drawn if self.pages.open else None
        if drawn is not None:
            place = drawn.place(x, y)
        else:  # no page open (a tap posted by hand): on the face now
            place = await run_in_threadpool(lambda: self.frames.place(self.face_now(), x, y))
        return await self.raised(n.Event("touch", place), "a tap on the page")

    async def raised(self, event: n.Event, source: str) -> Response:
        try:
            answer = await self.firing(event, source)
        except ScriptError as e:  # a statement of the handler found bad only in saying it
            return JSONResponse({"diagnostics": diagnostics_json(e.diagnostics)}, 400)
        except MissingTool as e:  # `say` with no speech engine here
            return JSONResponse({"diagnostics": [problem(str(e))]}, 400)
        self.pump.wake()
        return JSONResponse(answer)

    # -- commands: one path, whether they come over HTTP or from another thread

    async def perform(self, text: str) -> Tuple[int, Dict[str, Any]]:
        """A command, as `POST /api/command` takes it: (status code, answer). Busy when too many wait."""
        if not text.strip():
            return 400, {"diagnostics": [problem("no command: the body is empty")]}
        try:
            answer = await self.heavy.run(self.take, text)
        except ScriptError as e:
            return 400, {"diagnostics": diagnostics_json(e.diagnostics)}
        except MissingTool as e:  # `say` with no speech engine here
            return 400, {"diagnostics": [problem(str(e))]}
        self.pump.wake()
        self.told(answer)
        return 200, answer

    def hand_over(self, text: str, source: str) -> None:
        """A command from another thread (a ROS subscriber's): played as `POST /api/command` plays
        it, a refusal logged in one line naming `source`. Returns once it is taken or refused, so
        commands from one thread keep their order."""
        loop = self.loop if self.serving.wait(HANDED_OVER) else None
        if loop is None or not loop.is_running() or self.closing.is_set():
            return
        taken = asyncio.run_coroutine_threadsafe(self._handed(text, source), loop)
        deadline = time.monotonic() + HANDED_OVER
        while True:
            try:
                taken.result(0.1)
                return
            except concurrent.futures.TimeoutError:
                if self.closing.is_set() or not loop.is_running():  # nothing will take it
                    taken.cancel()
                    return
                if time.monotonic() > deadline:
                    taken.cancel()
                    self.log(f"{source}: not taken: nothing answered in {HANDED_OVER:.0f} s")
                    return

    async def _handed(self, text: str, source: str) -> None:
        if self.closing.is_set():
            return
        try:
            code, answer = await self.perform(text)
        except Busy as e:
            code, answer = 429, {"error": str(e)}
        except Exception as e:  # logged; the server carries on
            code, answer = 500, {"error": f"{type(e).__name__}: {e}"}
        if code >= 400:
            self.log(f"{source}: {code} {reason_of(answer)}")

    # -- the routes

    @answered
    async def index(self, request: Request) -> Response:
        return FileResponse(self.page, headers={"cache-control": "no-store"})

    @answered
    async def command(self, request: Request) -> Response:
        code, answer = await self.perform(await body_text(request))
        return JSONResponse(answer, code)

    @answered
    async def frame(self, request: Request) -> Response:
        jpeg = await run_in_threadpool(lambda: self.frames.jpeg(self.face_now()))
        return Response(jpeg, media_type="image/jpeg", headers={"cache-control": "no-store"})

    @answered
    async def sound(self, request: Request) -> Response:
        key = request.path_params["key"]
        wav = await run_in_threadpool(self.shown.sound, key) if SOUND_KEY.fullmatch(key) else None
        if wav is None:
            return JSONResponse({"error": "no such sound in what the face says"}, 404)
        return Response(wav, media_type="audio/wav", headers={"cache-control": "private, max-age=3600"})

    async def live(self, websocket: WebSocket) -> None:
        """A page's connection: the frame and status now, then whatever the pump sends, until it closes."""
        self.start()
        await websocket.accept()
        self.opened()
        transport = transport_of(websocket.scope)
        sent = self.pages.frames_sent
        jpeg = await run_in_threadpool(lambda: self.frames.jpeg(self.face_now()))
        # A frame the pump sent meanwhile is newer than this one: that one, then.
        first = self.pages.frame if self.pages.frames_sent != sent else message(BINARY, jpeg)
        if transport.is_closing():
            return
        transport.write(first)
        status = self.shown.status(self.shown.clock())
        transport.write(message(TEXT, json.dumps(status).encode("utf-8")))
        self.pages.add(transport)
        try:
            # A page that closes is noticed at once, not at the next message sent to it (the close
            # handshake waits for an answer: a page's tab closed, a screen reloaded).
            await _closed(websocket)
        finally:
            self.pages.remove(transport)

    def face_now(self) -> Any:
        """The face now, time passed to now first (with no page open, the pump lets none pass)."""
        now = self.shown.clock()
        self.shown.step(now)
        return self.shown.face(now)

    async def not_here(self, request: Request, exc: Exception) -> Response:
        """Starlette's own 404 and 405, answered in JSON like the rest and logged."""
        code = getattr(exc, "status_code", 404)
        why = f"{echoed(request.method)} is not taken here" if code == 405 else "nothing is here"
        self.log(f"{echoed(request.method)} {echoed(request.url.path)}: {code} {why}")
        return JSONResponse({"error": why}, code)


async def _closed(websocket: WebSocket) -> None:
    """Returns once the page has closed its connection (what it sends is not listened to)."""
    try:
        while (await websocket.receive())["type"] != "websocket.disconnect":
            pass
    except (WebSocketDisconnect, RuntimeError, OSError):
        pass


async def body_bytes(request: Request) -> bytes:
    """The body, read no further than the largest script the server takes (and a little more, so
    that a script just over the limit is checked and told so, as `check` tells it)."""
    chunks, size = [], 0
    async for chunk in request.stream():
        chunks.append(chunk)
        size += len(chunk)
        if size > LIMITS.max_bytes + 1024:
            raise TooLarge()
    return b"".join(chunks)


async def body_text(request: Request) -> str:
    """The body as text: UTF-8 (a byte-order mark is dropped), else BadRequest naming the first
    byte that is not, as `check` reads a script."""
    data = await body_bytes(request)
    try:
        return decode(data, "the body")
    except ScriptError as e:
        raise BadRequest(e.summary()) from None


MOST_DIGITS = 100  # of an integer in a JSON body: far more than any number the API takes


def _integer(text: str) -> int:
    """A JSON integer, refused past `MOST_DIGITS`: Python 3.11 refused one past 4,300 digits with
    a hint about its own settings (set_int_max_str_digits), which went into the answer."""
    digits = len(text.lstrip("-"))
    if digits > MOST_DIGITS:
        raise BadRequest(f"the body has a number of {digits} digits; a number here has at most {MOST_DIGITS}")
    return int(text)


async def body_json(request: Request) -> Dict[str, Any]:
    try:
        value = json.loads(await body_text(request) or "{}", parse_int=_integer)
    except ValueError as e:
        raise BadRequest(f"the body must be JSON: {e}") from None
    except RecursionError:  # nested deeper than Python's parser goes
        raise BadRequest("the body must be JSON nested at most a few hundred levels deep") from None
    if not isinstance(value, dict):
        raise BadRequest("the body must be a JSON object")
    return value


def reason_of(answer: Dict[str, Any]) -> str:
    """What an error answer says, for the log: its error, or its first diagnostic."""
    try:
        if "diagnostics" in answer:
            first = answer["diagnostics"][0]
            place = f"{first['line']}:{first['column']}: " if first["line"] else ""
            return shortened(f"{place}{first['message']}", LOGGED)
        return shortened(str(answer["error"]), LOGGED)
    except (KeyError, IndexError, TypeError):
        return "(no reason given)"


def _reason(response: Any) -> str:
    try:
        return reason_of(json.loads(bytes(response.body)))
    except (ValueError, AttributeError):
        return "(no reason given)"
