"""Who may connect to a real screen on loopback, and what a hostile client can cost it.

The requests carry exactly the Host and Origin headers a rebinding page (or a
hostile client) sends, and the refusals are in the screen's own words; the
half-open connections are real sockets that never send a byte, against a
screen whose open files are limited; a flood of commands does not send a page
more frames than --fps.
"""

from __future__ import annotations

import contextlib
import http.client
import resource
import socket
import threading
import time

import pytest
from raw_http import HOSTILE_HOSTS, answered, ask, closed_by_server, upgrade

from studio_server import running_screen
from waiting import eventually


@pytest.fixture(scope="module")
def screen(tmp_path_factory):
    folder = tmp_path_factory.mktemp("screen-guard")
    with running_screen(folder, "--no-idle") as server:
        server.port = int(server.base.rsplit(":", 1)[1])
        yield server


@pytest.mark.parametrize("pattern", HOSTILE_HOSTS)
def test_a_host_that_is_not_this_screen_is_refused_in_the_screens_words(screen, pattern):
    host = pattern.format(port=screen.port)
    for origin in (None, f"http://{host}"):
        status, answer = ask(screen.port, "POST", "/api/command", host, origin, b"sad")
        assert status == 403, (host, origin, answer)
        assert answer["error"].startswith("this screen answers on loopback only")
        assert "studio" not in answer["error"]
        assert upgrade(screen.port, host, origin) == 403
    assert screen.json("GET", "/api/state")[1]["face"]["emotion"] != "sad"  # no command got through


def test_an_origin_that_does_not_parse_is_refused_not_a_traceback(screen):
    host = f"localhost:{screen.port}"
    for origin in ("http://[", "http://[::1", "null"):
        status, answer = ask(screen.port, "GET", "/api/state", host, origin)
        assert status == 403 and "other sites' pages are refused" in answer["error"]
        assert upgrade(screen.port, host, origin) == 403
    assert ask(screen.port, "GET", "/api/state", host, f"http://{host}")[0] == 200
    assert upgrade(screen.port, host, f"http://{host}") == 101
    logged = eventually(lambda: [line for line in screen.log() if "GET /api/state: 403" in line])
    assert logged[0].startswith("baxterface screen: GET /api/state: 403 requests from other sites'")
    assert not [line for line in screen.log() if "Traceback" in line or "studio" in line]


def test_silent_connections_do_not_keep_a_request_out(tmp_path):
    """300 connections that never send a byte, at a screen that may open 256 files: a request is
    answered all the same, and the log stays short."""
    with running_screen(tmp_path, "--no-idle") as server:
        port = int(server.base.rsplit(":", 1)[1])
        resource.prlimit(server.process.pid, resource.RLIMIT_NOFILE, (256, 256))
        silent = [socket.create_connection(("127.0.0.1", port), timeout=30) for _ in range(300)]
        try:
            assert eventually(lambda: answered(port), timeout=60)
            assert eventually(lambda: sum(map(closed_by_server, silent)) >= 300 - 128, timeout=60)
        finally:
            for sock in silent:
                sock.close()
        assert len(server.log()) < 20, server.log()[:20]


def test_a_flood_of_commands_sends_a_page_no_more_frames_than_fps_asks(tmp_path):
    from websockets.sync.client import connect

    fps, seconds = 5, 3.0
    with running_screen(tmp_path, "--no-idle", "--fps", str(fps)) as server:
        port = int(server.base.rsplit(":", 1)[1])
        with connect(f"ws://127.0.0.1:{port}/api/live") as page:
            while not isinstance(page.recv(timeout=30), bytes):  # the face as it was: not counted
                pass
            flooding = threading.Thread(target=_flood, args=(port, seconds))
            began = time.monotonic()
            flooding.start()
            frames = 0
            while flooding.is_alive() or time.monotonic() - began < seconds + 1.0:
                with contextlib.suppress(TimeoutError):
                    frames += isinstance(page.recv(timeout=0.2), bytes)
            flooding.join()
            waited = time.monotonic() - began
    assert frames > 1  # the commands did show
    assert frames <= fps * waited + 1, f"{frames} frames in {waited:.1f} s at --fps {fps}"


def _flood(port: int, seconds: float) -> None:
    """Commands back to back, each moving the face, for `seconds`."""
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
    began, sides = time.monotonic(), ("look left in 0.3s", "look right in 0.3s")
    k = 0
    while time.monotonic() - began < seconds:
        connection.request("POST", "/api/command", body=sides[k % 2].encode())
        assert connection.getresponse().read()
        k += 1
    connection.close()
