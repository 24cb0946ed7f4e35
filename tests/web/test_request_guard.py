"""Who may connect to a real studio on loopback: exact names and port only, and no half-open lock-out.

The requests carry exactly the Host and Origin headers a rebinding page (or a
hostile client) sends; the half-open connections are real sockets that never
send a byte, against a studio whose open files are limited.
"""

from __future__ import annotations

import asyncio
import json
import resource
import socket

import pytest
from raw_http import HOSTILE_HOSTS, answered, ask, closed_by_server, upgrade

from baxterface_cli.web.request_guard import Guard, authority, is_loopback
from studio_server import running_studio
from waiting import eventually

SCRIPT = "happy\nlook left in 1s\n"
GOOD_HOSTS = ["127.0.0.1:{port}", "localhost:{port}", "[::1]:{port}", "127.0.0.2:{port}", "LocalHost:{port}"]
BAD_ORIGINS = [
    "http://[",
    "http://[::1",
    "http://127.0.0.1:{port}@evil.example",
    "http://evil.example",
    "http://127.0.0.1.nip.io:{port}",
    "http://localhost:9999",
    "https://127.0.0.1:{port}",
    "null",
    "",
]


@pytest.fixture(scope="module")
def studio(tmp_path_factory):
    folder = tmp_path_factory.mktemp("guard")
    (folder / "show.face").write_text(SCRIPT)
    with running_studio(folder / "show.face") as server:
        server.folder = folder
        server.port = int(server.base.rsplit(":", 1)[1])
        yield server


@pytest.mark.parametrize("pattern", HOSTILE_HOSTS)
def test_a_host_that_is_not_this_studio_is_refused_everything(studio, pattern):
    host = pattern.format(port=studio.port)
    same_site = f"http://{host}"
    for origin in (None, same_site):
        status, answer = ask(studio.port, "GET", "/api/state", host, origin)
        assert status == 403, (host, origin, answer)
        assert "this studio answers on loopback only" in answer["error"]
        assert ask(studio.port, "POST", "/api/save", host, origin, b"sad\n")[0] == 403
        assert upgrade(studio.port, host, origin) == 403
    assert (studio.folder / "show.face").read_text() == SCRIPT  # the script was not overwritten


@pytest.mark.parametrize("pattern", GOOD_HOSTS)
def test_this_machines_names_at_the_studios_port_are_answered(studio, pattern):
    host = pattern.format(port=studio.port)
    assert ask(studio.port, "GET", "/api/state", host)[0] == 200
    assert ask(studio.port, "GET", "/api/state", host, f"http://{host.lower()}")[0] == 200
    assert upgrade(studio.port, host, f"http://{host.lower()}") == 101


@pytest.mark.parametrize("pattern", BAD_ORIGINS)
def test_an_origin_that_is_not_this_studio_or_does_not_parse_is_refused(studio, pattern):
    host, origin = f"127.0.0.1:{studio.port}", pattern.format(port=studio.port)
    status, answer = ask(studio.port, "POST", "/api/save", host, origin, b"sad\n")
    assert status == 403 and "other sites' pages are refused" in answer["error"]
    assert upgrade(studio.port, host, origin) == 403
    assert (studio.folder / "show.face").read_text() == SCRIPT


def test_refusals_are_one_line_each_and_never_a_traceback(studio):
    ask(studio.port, "GET", "/api/state", f"127.0.0.1:{studio.port}", "http://[")
    ask(studio.port, "GET", "/api/state", "[::1")
    logged = eventually(lambda: [line for line in studio.log() if "'http://['" in line or "'[::1'" in line])
    assert logged[-2].startswith("baxterface studio: GET /api/state: 403 requests from other sites' pages")
    assert logged[-1].startswith(
        "baxterface studio: GET /api/state: 403 this studio answers on loopback only"
    )
    assert not [line for line in studio.log() if "Traceback" in line or " 500 " in line]


@pytest.mark.parametrize(
    "header, expected",
    [
        ("localhost:8080", ("localhost", 8080)),
        ("[::1]:80", ("[::1]", 80)),
        ("127.0.0.1", ("127.0.0.1", None)),
        ("127.0.0.1.:8080", None),
        ("127.0.0.1@evil.example", None),
        ("a..b:1", None),
        ("host:0", None),
        ("host:65536", None),
        ("[::1]x:1", None),
        ("[fe80::1%eth0]:1", None),
        ("h\u00e9te:1", None),
    ],
)
def test_a_host_header_parses_strictly(header, expected):
    assert authority(header) == expected


def _through(host: str, origin: str = "", query: bytes = b"") -> tuple:
    """(status, error) a request gets from a screen's guard, off loopback, in front of an app that
    answers 200."""
    sent: list = []

    async def app(scope, receive, send) -> None:
        await send({"type": "http.response.start", "status": 200, "headers": []})

    async def send(message) -> None:
        sent.append(message)

    headers = [(b"host", host.encode())] + ([(b"origin", origin.encode())] if origin else [])
    scope = {"type": "http", "method": "GET", "path": "/api/state", "headers": headers, "query_string": query}
    guard = Guard(app, "the-token-0123456789", lambda line: None).serving("screen", "0.0.0.0", 8081)
    asyncio.run(guard(scope, None, send))
    body = b"".join(m.get("body", b"") for m in sent[1:])
    return sent[0]["status"], json.loads(body)["error"] if body else None


def test_off_loopback_any_name_with_the_token_and_a_page_only_from_where_it_asked():
    token = b"token=the-token-0123456789"
    assert _through("robot.lab:8081", query=token)[0] == 200
    assert _through("192.168.1.20:8081", "http://192.168.1.20:8081", token)[0] == 200
    status, error = _through("robot.lab:8081", "http://evil.example", token)
    assert status == 403 and error.startswith("requests from other sites' pages are refused")
    status, error = _through("robot.lab:8081", "http://[", token)
    assert status == 403 and "other sites" in error
    status, error = _through("robot lab:8081", query=token)
    assert status == 403 and "is not a host name and port" in error
    status, error = _through("robot.lab:8081")
    assert status == 403 and error.startswith("a token is needed: open the address the screen printed")


def test_what_counts_as_serving_on_loopback():
    assert all(map(is_loopback, ["127.0.0.1", "127.3.2.1", "localhost", "::1", "[::1]"]))
    assert not any(map(is_loopback, ["0.0.0.0", "", "::", "127.attacker.example", "localhost.evil.example"]))


SILENT = 300
FILES = 256


def test_silent_connections_do_not_keep_a_request_out(tmp_path):
    """300 connections that never send a byte, at a studio that may open 256 files: a request is
    answered all the same, the silent ones are closed, and the log stays short."""
    (tmp_path / "show.face").write_text(SCRIPT)
    with running_studio(tmp_path / "show.face") as server:
        port = int(server.base.rsplit(":", 1)[1])
        resource.prlimit(server.process.pid, resource.RLIMIT_NOFILE, (FILES, FILES))
        silent = [socket.create_connection(("127.0.0.1", port), timeout=30) for _ in range(SILENT)]
        try:
            assert eventually(lambda: answered(port), timeout=60)
            # Past the head's deadline, the server has closed every one of them (the oldest at once).
            eventually(lambda: all(closed_by_server(sock) for sock in silent), timeout=60)
            assert answered(port)
        finally:
            for sock in silent:
                sock.close()
        assert len(server.log()) < 20, server.log()[:20]


def test_a_head_sent_a_byte_at_a_time_is_cut_off(studio):
    """A client that keeps a connection with a byte now and then (slowloris) is closed all the same."""
    sock = socket.create_connection(("127.0.0.1", studio.port), timeout=30)
    with sock:

        def cut_off() -> bool:
            try:
                sock.sendall(b"G")
            except OSError:
                return True
            return closed_by_server(sock)

        assert eventually(cut_off, timeout=60)


LONG = 4000  # characters of each long part: the whole head stays within uvicorn's 16 KiB


def _sent_whole(port: int, head: str) -> bytes:
    """The server's answer's first line to `head`, sent as it is on a socket of its own."""
    with socket.create_connection(("127.0.0.1", port), timeout=30) as sock:
        sock.sendall(head.encode("latin-1"))
        return sock.makefile("rb").readline()


def test_a_long_path_or_token_is_cut_short_in_the_log_with_its_length(studio):
    """A refusal repeats a path or token of thousands of characters as its first 80 and its length."""
    path = "/api/state/" + "p" * LONG
    token = "t" * LONG
    refused = (
        f"GET {path}?token={token} HTTP/1.1\r\nHost: evil.example:{studio.port}\r\n"
        f"X-Baxterface-Token: {token}\r\nCookie: baxterface_token={token}\r\nConnection: close\r\n\r\n"
    )
    assert b" 403 " in _sent_whole(studio.port, refused)
    not_here = (
        f"GET {path}?token={token} HTTP/1.1\r\nHost: 127.0.0.1:{studio.port}\r\nConnection: close\r\n\r\n"
    )
    assert b" 404 " in _sent_whole(studio.port, not_here)
    logged = eventually(lambda: [line for line in studio.log() if "/api/state/ppp" in line][-2:])
    cut = f"/api/state/{'p' * 69}... ({len(path):,} characters)"
    assert len(logged) == 2, logged
    assert logged[0].startswith(f"baxterface studio: GET {cut}: 403 this studio answers on loopback only")
    assert logged[1] == f"baxterface studio: GET {cut}: 404 nothing is here"
    assert max(len(line) for line in studio.log()) < 500
    assert not [line for line in studio.log() if "t" * 100 in line]
