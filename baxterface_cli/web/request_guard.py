"""Who may talk to the studio (or the screen): this machine by default, or holders of its token.

Bound to loopback, the server answers only requests addressed to this
machine by a name no one else controls (`localhost`, `127.0.0.1`, another
`127.x.y.z` written in full, `[::1]`, or the --host given), at its own port:
a page on another site that rebinds its own name to 127.0.0.1 still sends
its own name as the Host, and is refused. It takes no request that another
site's page makes (its Origin is not one of those). Bound to any other
address, every request must carry the token: as `?token=`, the
`X-Baxterface-Token` header, or the cookie the page gets when it is opened
with the token; a page's Origin must then be the address it asked for.
A Host or Origin that does not parse is refused like a wrong one.
"""

from __future__ import annotations

import hmac
import ipaddress
import json
import re
from http.cookies import SimpleCookie
from typing import Any, Callable, Dict, List, Optional, Tuple
from urllib.parse import parse_qs

from .refusal_log import echoed

LOOPBACK_NAMES = ("localhost", "127.0.0.1", "[::1]")
COOKIE = "baxterface_token"
HTTP_PORT = 80  # the port a browser leaves out of the Host header

_LABEL = r"[a-z0-9](?:[a-z0-9-]{0,61}[a-z0-9])?"
# A name as a browser sends it (lower case, no trailing dot), or a bracketed IPv6 literal; then the port.
_AUTHORITY = re.compile(rf"(\[[0-9a-f:.]+\]|{_LABEL}(?:\.{_LABEL})*)(?::([0-9]{{1,5}}))?")
_OCTET = r"(?:25[0-5]|2[0-4][0-9]|1[0-9][0-9]|[1-9]?[0-9])"
# Other loopback addresses, only as a browser writes them (never `127.1`, never with leading zeros).
_LOOPBACK_QUAD = re.compile(rf"127\.{_OCTET}\.{_OCTET}\.{_OCTET}")


def is_loopback(host: str) -> bool:
    """Whether serving on `host` (as --host gives it) serves this machine alone."""
    if host.lower() == "localhost":
        return True
    try:
        return ipaddress.ip_address(host[1:-1] if host.startswith("[") else host).is_loopback
    except ValueError:
        return False


def authority(text: str) -> Optional[Tuple[str, Optional[int]]]:
    """(name, port) of a Host header (`name`, `name:port`, `[v6]:port`); None when it does not parse."""
    found = _AUTHORITY.fullmatch(text.lower())
    if found is None:
        return None
    name, port = found.group(1), found.group(2)
    if name.startswith("["):
        try:
            ipaddress.IPv6Address(name[1:-1])
        except ValueError:
            return None
    if port is not None and not 0 < int(port) < 65536:
        return None
    return name, None if port is None else int(port)


def origin_authority(origin: str) -> Optional[Tuple[str, Optional[int]]]:
    """(name, port) of an Origin header, `http://` and a Host; None for anything else (`null` too)."""
    if not origin.lower().startswith("http://"):
        return None
    return authority(origin[len("http://") :])


def _shown(text: str) -> str:
    """A header as the refusal repeats it: short, and in ASCII (a WebSocket's close reason is bytes)."""
    return ascii(echoed(text))


class Guard:
    """ASGI middleware: refuses, with 403, what the rules above do not let through.

    The command that serves tells it (`serving`) its name, the --host it was
    given and the port it listens on; until then it names itself the studio
    and takes its port to be the one each request arrived at.
    """

    def __init__(self, app: Callable, token: Optional[str], log: Callable[[str], None]) -> None:
        self.app = app
        self.token = token
        self.log = log
        self.name = "studio"
        self.named: Optional[str] = None
        self.port: Optional[int] = None

    def serving(self, name: str, host: str, port: int) -> Guard:
        """The server's name (for its refusals), the --host it was given, and its port."""
        self.name, self.port = name, port
        self.named = f"[{host}]" if ":" in host and not host.startswith("[") else host.lower()
        return self

    async def __call__(self, scope: Dict[str, Any], receive: Callable, send: Callable) -> None:
        if scope["type"] not in ("http", "websocket"):
            return await self.app(scope, receive, send)
        why = self.refusal(scope)
        if why is not None:
            method, path = echoed(scope.get("method", "WEBSOCKET")), echoed(scope.get("path", ""))
            self.log(f"{method} {path}: 403 {why}")
            return await _refuse(scope, receive, send, why)
        if self.token is not None and scope["type"] == "http" and self._query_token(scope):

            async def with_cookie(message: Dict[str, Any]) -> None:
                if message["type"] == "http.response.start":
                    cookie = f"{COOKIE}={self.token}; Path=/; HttpOnly; SameSite=Strict"
                    message["headers"] = [*message.get("headers", []), (b"set-cookie", cookie.encode())]
                await send(message)

            return await self.app(scope, receive, with_cookie)
        return await self.app(scope, receive, send)

    def refusal(self, scope: Dict[str, Any]) -> Optional[str]:
        """Why this request is refused, or None."""
        headers = _headers(scope)
        hosts, origins = headers.get("host", []), headers.get("origin", [])
        if len(hosts) != 1 or len(origins) > 1:
            return "a request needs one Host header and at most one Origin header"
        host = authority(hosts[0])
        if self.token is None:
            own = self.port if self.port is not None else (scope.get("server") or ("", 0))[1]
            if host is None or not self._serves(host, own):
                at = ", ".join(f"{name}:{own}" for name in LOOPBACK_NAMES)
                return f"this {self.name} answers on loopback only, at {at}; not at Host {_shown(hosts[0])}"
            if origins and not self._serves(origin_authority(origins[0]), own):
                return f"requests from other sites' pages are refused (Origin {_shown(origins[0])})"
            return None
        if host is None:
            return f"the Host header {_shown(hosts[0])} is not a host name and port"
        if origins and origin_authority(origins[0]) != host:
            return f"requests from other sites' pages are refused (Origin {_shown(origins[0])})"
        offered = self._query_token(scope) or _first(headers, "x-baxterface-token") or _cookie(headers)
        if not offered:
            return f"a token is needed: open the address the {self.name} printed, with its ?token="
        if not hmac.compare_digest(offered.encode("utf-8", "replace"), self.token.encode()):
            return f"the token is wrong: open the address the {self.name} printed, with its ?token="
        return None

    def _serves(self, host: Optional[Tuple[str, Optional[int]]], own: int) -> bool:
        """Whether `host`, (name, port), is this server, at port `own`, on loopback."""
        if host is None:
            return False
        name, port = host
        if name not in LOOPBACK_NAMES and name != self.named and not _LOOPBACK_QUAD.fullmatch(name):
            return False
        return port == own or (port is None and own == HTTP_PORT)  # a browser leaves out port 80

    @staticmethod
    def _query_token(scope: Dict[str, Any]) -> Optional[str]:
        values = parse_qs(scope.get("query_string", b"").decode("latin-1")).get("token")
        return values[0] if values else None


def _headers(scope: Dict[str, Any]) -> Dict[str, List[str]]:
    headers: Dict[str, List[str]] = {}
    for key, value in scope.get("headers", []):
        headers.setdefault(key.decode("latin-1").lower(), []).append(value.decode("latin-1"))
    return headers


def _first(headers: Dict[str, List[str]], name: str) -> Optional[str]:
    values = headers.get(name)
    return values[0] if values else None


def _cookie(headers: Dict[str, List[str]]) -> Optional[str]:
    cookie = SimpleCookie()
    try:
        cookie.load("; ".join(headers.get("cookie", [])))
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
