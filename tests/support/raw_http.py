"""Requests as a hostile client sends them: exactly the Host and Origin given, raw WebSocket upgrades.

Shared by the guard's tests (studio and screen) and bench/bench_hostile_web.py.
"""

from __future__ import annotations

import base64
import http.client
import json
import os
import socket
from typing import Optional, Tuple

# What a page on another site sends once its name points at 127.0.0.1, and other Hosts that are not
# this server: each must be refused, whatever it asks, with or without a matching Origin.
HOSTILE_HOSTS = [
    "127.attacker.example:{port}",
    "127.0.0.1.nip.io:{port}",
    "127.0.0.1.attacker.example:{port}",
    "127.0.0.1.:{port}",
    "127.1:{port}",
    "127.0.0.1@evil.example:{port}",
    "127.0.0.1@evil.example",
    "localhost:9999",  # another port: another server's pages
    "localhost",  # a browser leaves the port out only for port 80
    "127.0.0.1:{port}:{port}",
    "127.000.000.001:{port}",
    "[::1:{port}",
    "[::1",
    "[",
    "LOCALHOST:{port}x",
    "",
]


def ask(
    port: int, method: str, path: str, host: str, origin: Optional[str] = None, body: bytes = b""
) -> Tuple[int, dict]:
    """(status, JSON answer or {}) of one request to 127.0.0.1:`port` with exactly this Host (and
    Origin); (0, {}) when the connection failed."""
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
    try:
        connection.putrequest(method, path, skip_host=True, skip_accept_encoding=True)
        connection.putheader("Host", host)
        if origin is not None:
            connection.putheader("Origin", origin)
        connection.putheader("Content-Length", str(len(body)))
        connection.endheaders(body)
        response = connection.getresponse()
        data = response.read()
        try:
            answer = json.loads(data)
        except ValueError:
            answer = {}
        return response.status, answer if isinstance(answer, dict) else {}
    except (OSError, http.client.HTTPException):
        return 0, {}
    finally:
        connection.close()


def upgrade(port: int, host: str, origin: Optional[str] = None, path: str = "/api/live") -> int:
    """The status code a WebSocket upgrade gets (101 taken, 403 refused; 0: closed without one)."""
    lines = [
        f"GET {path} HTTP/1.1",
        f"Host: {host}",
        "Upgrade: websocket",
        "Connection: Upgrade",
        f"Sec-WebSocket-Key: {base64.b64encode(os.urandom(16)).decode()}",
        "Sec-WebSocket-Version: 13",
    ]
    if origin is not None:
        lines.append(f"Origin: {origin}")
    with socket.create_connection(("127.0.0.1", port), timeout=30) as sock:
        sock.sendall(("\r\n".join(lines) + "\r\n\r\n").encode("latin-1"))
        head = b""
        while b"\r\n" not in head:
            got = sock.recv(4096)
            if not got:
                return 0
            head += got
    return int(head.split(b" ", 2)[1])


def closed_by_server(sock: socket.socket) -> bool:
    """Whether the other end has closed `sock` (a read gets the end, or a reset, at once)."""
    sock.setblocking(False)
    try:
        return sock.recv(1) == b""
    except BlockingIOError:
        return False
    except OSError:
        return True


def answered(port: int) -> bool:
    """Whether the server on 127.0.0.1:`port` answers `GET /api/state` with 200 (False when the
    connection fails or is cut)."""
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=5)
    try:
        connection.request("GET", "/api/state")
        return connection.getresponse().status == 200
    except (OSError, http.client.HTTPException):
        return False
    finally:
        connection.close()
