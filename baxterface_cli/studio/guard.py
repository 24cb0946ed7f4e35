"""Who may talk to the studio: this machine by default, or holders of its token.

Bound to loopback, the studio answers only requests addressed to a loopback
name (a web page elsewhere cannot reach it by rebinding its own name to
127.0.0.1), and takes no request that another site's page makes (its Origin
differs). Bound to any other address, every request must carry the token:
as `?token=`, the `X-Baxterface-Token` header, or the cookie the page gets
when it is opened with the token.
"""

from __future__ import annotations

import hmac
import json
from http.cookies import SimpleCookie
from typing import Any, Callable, Dict, Optional
from urllib.parse import parse_qs, urlsplit

LOOPBACK_NAMES = ("127.0.0.1", "localhost", "::1", "[::1]")
COOKIE = "baxterface_token"


def is_loopback(host: str) -> bool:
    return host in LOOPBACK_NAMES or host.startswith("127.")


def _host_name(host: str) -> str:
    """`name` from a Host header's `name:port` (and `[::1]:port`)."""
    if host.startswith("["):
        return host[: host.find("]") + 1]
    return host.rsplit(":", 1)[0] if host.count(":") == 1 else host


class Guard:
    """ASGI middleware: refuses, with 403, what the rules above do not let through."""

    def __init__(self, app: Callable, token: Optional[str], log: Callable[[str], None]) -> None:
        self.app = app
        self.token = token
        self.log = log

    async def __call__(self, scope: Dict[str, Any], receive: Callable, send: Callable) -> None:
        if scope["type"] not in ("http", "websocket"):
            return await self.app(scope, receive, send)
        headers = {k.decode("latin-1").lower(): v.decode("latin-1") for k, v in scope.get("headers", [])}
        why = self.refusal(scope, headers)
        if why is not None:
            self.log(f"{scope.get('method', 'WEBSOCKET')} {scope.get('path', '')}: 403 {why}")
            return await _refuse(scope, receive, send, why)
        if self.token is not None and scope["type"] == "http" and self._query_token(scope):

            async def with_cookie(message: Dict[str, Any]) -> None:
                if message["type"] == "http.response.start":
                    cookie = f"{COOKIE}={self.token}; Path=/; HttpOnly; SameSite=Strict"
                    message["headers"] = [*message.get("headers", []), (b"set-cookie", cookie.encode())]
                await send(message)

            return await self.app(scope, receive, with_cookie)
        return await self.app(scope, receive, send)

    def refusal(self, scope: Dict[str, Any], headers: Dict[str, str]) -> Optional[str]:
        host = headers.get("host", "")
        origin = headers.get("origin")
        if origin is not None and urlsplit(origin).netloc != host:
            return "requests from other sites' pages are refused"
        if self.token is None:
            if not is_loopback(_host_name(host)):
                return "this studio answers on loopback only"
            return None
        offered = self._query_token(scope) or headers.get("x-baxterface-token") or _cookie(headers)
        if not offered:
            return "a token is needed: open the address the studio printed, with its ?token="
        if not hmac.compare_digest(offered.encode("utf-8", "replace"), self.token.encode()):
            return "the token is wrong: open the address the studio printed, with its ?token="
        return None

    @staticmethod
    def _query_token(scope: Dict[str, Any]) -> Optional[str]:
        values = parse_qs(scope.get("query_string", b"").decode("latin-1")).get("token")
        return values[0] if values else None


def _cookie(headers: Dict[str, str]) -> Optional[str]:
    cookie = SimpleCookie()
    try:
        cookie.load(headers.get("cookie", ""))
    except Exception:  # a malformed cookie header is no token
        return None
    morsel = cookie.get(COOKIE)
    return morsel.value if morsel else None


async def _refuse(scope: Dict[str, Any], receive: Callable, send: Callable, why: str) -> None:
    if scope["type"] == "websocket":
        await send({"type": "websocket.close", "code": 1008, "reason": why[:120]})
        return
    body = json.dumps({"error": why}).encode()
    await send(
        {
            "type": "http.response.start",
            "status": 403,
            "headers": [
                (b"content-type", b"application/json"),
                (b"content-length", str(len(body)).encode()),
            ],
        }
    )
    await send({"type": "http.response.body", "body": body})
