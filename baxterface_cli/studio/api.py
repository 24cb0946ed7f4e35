"""The studio's HTTP API and WebSocket over a `Workspace`: one method a route.

The routes every face page has (the page, commands, the frame, sounds, the
live WebSocket) are web/face_api.py's, shared with the screen; these are the
studio's own: the editor's checks and saves, the transport, the session, the
robot switch; `POST /api/event` is the screen's (web/face_api.py), its events fired at the
script the editor plays. Imported only once the `studio` extra is known to be there.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any, Dict, List, Optional

from starlette.concurrency import run_in_threadpool
from starlette.requests import Request
from starlette.responses import JSONResponse, Response
from starlette.routing import Route

from ..drawing.renderer import Renderer
from ..language.diagnostics import ScriptError
from ..language.syntax_tree import Event
from ..web.face_api import BadRequest, FaceApi, Heavy, answered, body_bytes, body_json
from ..web.request_guard import Guard
from ..web.server import logger
from .reacting import TooManyEvents
from .workspace import SaveConflict, TooLargeToSave, TooManySessions, Workspace

STATIC = Path(__file__).resolve().parent / "static"
TRANSPORT_ACTIONS = ("play", "pause", "seek", "loop")
log = logger("studio")


def create_app(
    workspace: Workspace, renderer: Renderer, fps: float = 30.0, token: Optional[str] = None
) -> Guard:
    """The studio's ASGI application, behind its guard (loopback, same site, the token)."""
    return StudioApi(workspace, renderer, fps).app(token)


class StudioApi(FaceApi):
    page = STATIC / "index.html"
    own_static = STATIC  # the editor, the studio's script and style, at /static as ever

    def __init__(self, workspace: Workspace, renderer: Renderer, fps: float) -> None:
        super().__init__(workspace, renderer, fps, log, watch=self._disk_changes)
        self.workspace = workspace
        # The editor's checks and scripts wait in a line of their own: reading a long recording or
        # synthesising a long `say` there must not hold up the presses (`self.heavy`).
        self.editing = Heavy()

    def routes(self) -> list:
        return [
            Route("/api/state", self.state),
            Route("/api/check", self.check, methods=["POST"]),
            Route("/api/script", self.script, methods=["POST"]),
            Route("/api/save", self.save, methods=["POST"]),
            Route("/api/transport", self.transport, methods=["POST"]),
            Route("/api/robot", self.robot, methods=["POST"]),
            Route("/api/event", self.event, methods=["POST"]),
            Route("/api/touch", self.touch, methods=["POST"]),
            Route("/api/session/export", self.export, methods=["POST"]),
            Route("/api/session/clear", self.clear, methods=["POST"]),
            *self.face_routes(),
        ]

    def take(self, text: str) -> Dict[str, Any]:
        """A press, taken by the session's run as the face node takes a command (and on the robot
        when switched on)."""
        try:
            return {**self.workspace.press(text), "session": self.workspace.session()}
        except TooManyEvents as e:  # a press past the inputs a session holds
            raise BadRequest(str(e)) from None

    def fire(self, event: Event, source: str) -> Dict[str, Any]:
        """An event fired by hand at the script the editor plays (studio/reacting.py)."""
        try:
            return self.workspace.event(event, source)
        except TooManyEvents as e:
            raise BadRequest(str(e)) from None

    async def firing(self, event: Event, source: str) -> Dict[str, Any]:
        # Each event runs the script again over all of them: in the editing line, bounded as the checks.
        answer = await self.editing.run(self.fire, event, source)
        self.pages.send({"kind": "timeline", "timeline": self.workspace.timeline()})
        return answer

    def told(self, answer: Dict[str, Any]) -> None:
        self.pages.send({"kind": "session", "session": answer["session"]})
        if answer.get("reacting"):  # the events bar and the timeline changed with the run
            self.pages.send({"kind": "timeline", "timeline": self.workspace.timeline()})
        # A command leaves the preview live, where the page hides the timeline: it is sent as the
        # preview goes back to the transport (`transport`), not at each press of a flood.

    def _disk_changes(self) -> List[Dict[str, Any]]:
        """What changed on disk, with the new timeline after the script itself changed."""
        changes = []
        for change in self.workspace.disk_changes():
            changes.append(change)
            if change["kind"] == "disk":
                changes.append({"kind": "timeline", "timeline": self.workspace.timeline()})
        return changes

    @answered
    async def state(self, request: Request) -> Response:
        return JSONResponse(await run_in_threadpool(self.workspace.state))

    @answered
    async def check(self, request: Request) -> Response:
        data = await body_bytes(request)
        return JSONResponse(await self.editing.run(self.workspace.check, data))

    @answered
    async def script(self, request: Request) -> Response:
        answer = await self.editing.run(self.workspace.update, await body_bytes(request))
        self.pump.wake()
        return JSONResponse(answer)

    @answered
    async def save(self, request: Request) -> Response:
        data = await body_bytes(request)
        base = request.query_params.get("base")
        if request.query_params.get("force") == "1":
            base = None
        elif base is not None and not re.fullmatch(r"[0-9]{1,9}", base):
            raise BadRequest(f"base must be a version number, not {base[:20]!r}")
        try:
            saved = await run_in_threadpool(self.workspace.save, data, None if base is None else int(base))
        except SaveConflict as e:  # the page asks before it overwrites
            return JSONResponse({"error": str(e), "conflict": True, "version": e.version}, 409)
        except TooLargeToSave as e:
            return JSONResponse({"error": str(e)}, 413)
        except ScriptError as e:  # not UTF-8: saved as it came, it would not load again
            raise BadRequest(f"not saved: {e.summary()}") from None
        except OSError as e:
            return JSONResponse({"error": f"cannot save {self.workspace.name}: {e.strerror or e}"}, 500)
        return JSONResponse(saved)

    @answered
    async def transport(self, request: Request) -> Response:
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
        was = self.workspace.preview.mode
        status = self.workspace.transport(action, float(body.get("t") or 0.0), on)
        if was != status["mode"]:  # back from live: the run the presses made, on the transport
            self.pages.send({"kind": "timeline", "timeline": self.workspace.timeline()})
        self.pump.wake()
        return JSONResponse(status)

    @answered
    async def robot(self, request: Request) -> Response:
        body = await body_json(request)
        return JSONResponse(await run_in_threadpool(self.workspace.robot.switch, bool(body.get("on"))))

    @answered
    async def export(self, request: Request) -> Response:
        try:
            return JSONResponse(await run_in_threadpool(self.workspace.export_session))
        except TooManySessions as e:
            return JSONResponse({"error": str(e)}, 429)
        except OSError as e:
            return JSONResponse({"error": f"cannot write the session: {e.strerror or e}"}, 500)

    @answered
    async def clear(self, request: Request) -> Response:
        session = await run_in_threadpool(self.workspace.clear_session)  # the script again, without events
        self.pages.send({"kind": "session", "session": session})
        self.pages.send({"kind": "timeline", "timeline": self.workspace.timeline()})
        self.pump.wake()
        return JSONResponse(session)


def _is_number(value: Any) -> bool:
    """A finite number a float holds (JSON's 400-digit integers do not)."""
    if not isinstance(value, (int, float)) or isinstance(value, bool):
        return False
    try:
        return abs(float(value)) < float("inf")
    except OverflowError:
        return False
