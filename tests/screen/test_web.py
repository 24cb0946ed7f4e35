"""The screen over HTTP and its WebSocket: a real `baxterface screen`, one for the module.

It serves off loopback with the token it was given, so every request here carries it.
"""

from __future__ import annotations

import contextlib
import io
import json
import socket
import threading
import time
import wave
from contextlib import ExitStack, contextmanager
from typing import Iterator, List, Optional

import numpy as np
import pytest

from studio_server import running_screen
from waiting import eventually

pytestmark = pytest.mark.xdist_group("screen_web")
TOKEN = "screen-test-token-0123456789"


@pytest.fixture(scope="module")
def screen(tmp_path_factory):
    import os

    folder = tmp_path_factory.mktemp("screen")
    (folder / "first.face").write_text("sad\nlook left in 0.3s\n")
    env = dict(os.environ, BAXTERFACE_TOKEN=TOKEN)
    args = (str(folder / "first.face"), "--no-idle", "--host", "0.0.0.0")
    with running_screen(folder, *args, env=env) as server:
        server.before = server.json("GET", "/api/state")[1]  # before any page has opened
        server.base = "http://127.0.0.1:" + server.base.rsplit(":", 1)[1]
        yield server


def decoded(jpeg: bytes) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(jpeg)).convert("RGB"), dtype=np.int16)


class Page:
    """A page's live connection, as the screen's page opens it: frames and status messages."""

    def __init__(self, ws) -> None:
        self.ws = ws
        self.frames = []
        self.statuses = []

    def next(self, timeout: float = 30.0):
        message = self.ws.recv(timeout=timeout)
        if isinstance(message, bytes):
            self.frames.append(message)
        else:
            self.statuses.append(json.loads(message))
        return message

    def until(self, test, timeout: float = 30.0):
        deadline = time.monotonic() + timeout
        while True:
            message = self.next(max(0.01, deadline - time.monotonic()))
            if test(message):
                return message


@contextmanager
def pages(screen, count: int = 1) -> Iterator[List[Page]]:
    """`count` pages connected to the screen, until the block ends."""
    from websockets.sync.client import connect

    url = screen.base.replace("http://", "ws://") + "/api/live"
    with ExitStack() as stack:
        opened = []
        for _ in range(count):
            ws = stack.enter_context(connect(url, additional_headers={"X-Baxterface-Token": TOKEN}))
            stack.callback(closed, ws)  # before the context's own close
            opened.append(Page(ws))
        yield opened


def closed(ws) -> None:
    """Close a page's connection, taking what still comes meanwhile: the websockets of Python 3.8
    (13) reads no further frame, the answer to the close among them, until the last message is
    taken, and would wait out its 10 s close timeout."""

    def take() -> None:
        with contextlib.suppress(Exception):
            while True:
                ws.recv()

    reader = threading.Thread(target=take, daemon=True)
    reader.start()
    ws.close()
    reader.join(timeout=30)


def test_off_loopback_every_request_needs_the_token_it_was_given(screen):
    assert screen.token == TOKEN  # BAXTERFACE_TOKEN's: a restart keeps the pages' address good
    status, answer = screen.request("GET", "/api/state", headers={"X-Baxterface-Token": "wrong"})
    assert status == 403 and json.loads(answer)["error"].startswith("the token is wrong")
    status, answer = screen.request("GET", "/", headers={"X-Baxterface-Token": ""})
    assert status == 403 and json.loads(answer)["error"].startswith("a token is needed")
    status, page = screen.request("GET", f"/?token={TOKEN}", headers={"X-Baxterface-Token": ""})
    assert status == 200 and b"/static/screen/screen.js" in page
    assert screen.request("GET", "/static/sound.js")[0] == screen.request("GET", "/static/tap.js")[0] == 200
    assert screen.request("GET", "/static/screen/screen.css")[0] == 200
    assert screen.request("GET", "/static/app.js")[0] == 404  # the studio's editor is the studio's alone


def test_the_script_waits_for_the_first_page(screen):
    assert screen.before["waiting"] and screen.before["script"].endswith("first.face")
    with pages(screen) as (page,):
        page.until(lambda m: isinstance(m, bytes))
        assert not screen.json("GET", "/api/state")[1]["waiting"]


def test_a_command_changes_the_frame_and_a_bad_one_gets_a_400_with_diagnostics(screen):
    assert screen.json("POST", "/api/command", "look_-60_0_0")[0] == 200  # the old node's: at once
    # What the first script began (sad's mouth after its lids) finishes first; at rest, a look is at once.
    eventually(lambda: not screen.json("GET", "/api/state")[1]["playing"])
    before = decoded(screen.frame())
    status, answer = screen.json("POST", "/api/command", "look_60_0_0")
    assert status == 200 and answer == {"installed": [], "handlers": 0}
    assert np.abs(decoded(screen.frame()) - before).mean() > 1.0  # the eyes moved
    asked = [
        ("hapy", "unknown command 'hapy'; did you mean 'happy'?", "1:1: "),
        ("look 40 -20 in 0.5s eas-in", "unknown easing 'eas-in'", "1:21: "),
        ("mood 1.2 0", "valence must be from -1 to 1, not 1.2", "1:6: "),
        ("  ", "no command: the body is empty", ""),
    ]
    for text, message, _ in asked:
        status, answer = screen.json("POST", "/api/command", text)
        assert status == 400 and answer["diagnostics"][0]["message"].startswith(message)
    logged = [line for line in screen.log() if "POST /api/command" in line]
    for (_, message, place), line in zip(asked, logged[-len(asked) :]):
        assert line.startswith(f"baxterface screen: POST /api/command: 400 {place}{message}")


def test_every_page_gets_each_changed_frame_and_none_while_the_face_is_still(screen):
    with pages(screen, 2) as watching:
        for page in watching:
            page.until(lambda m: isinstance(m, str))  # the frame now, then the status
        assert screen.json("GET", "/api/state")[1]["screens"] == 2
        for page in watching:
            page.frames.clear()
        screen.json("POST", "/api/command", "look right in 0.5s")
        at_rest = eventually(lambda: not_playing(screen))
        for page in watching:
            # Past the move's end by a status or two: the status goes on every second, frames do not.
            page.until(lambda m: isinstance(m, str) and json.loads(m)["t"] > at_rest + 1.2)
            assert len(page.frames) >= 5  # the move, frame by frame (30 a second at most)
            assert all(a != b for a, b in zip(page.frames, page.frames[1:]))  # each one a change
            ended = len(page.frames)
            page.until(lambda m: isinstance(m, str))  # a second more of a still face
            assert len(page.frames) == ended
        assert watching[0].frames[-1] == watching[1].frames[-1] == screen.frame()  # one face on both


def test_a_page_that_stops_reading_holds_up_no_other_and_is_sent_the_newest_frame(screen):
    stalled = socket.socket()
    stalled.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)  # its window fills at once
    stalled.settimeout(30)
    stalled.connect(("127.0.0.1", int(screen.base.rsplit(":", 1)[1])))
    with stalled, pages(screen) as (page,):
        stalled.sendall(
            b"GET /api/live HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
            b"Sec-WebSocket-Key: c3RhbGxlZCBwYWdlIGtleQ==\r\nSec-WebSocket-Version: 13\r\n"
            + f"X-Baxterface-Token: {TOKEN}\r\n\r\n".encode()
        )
        page.until(lambda m: isinstance(m, str))
        eventually(lambda: screen.json("GET", "/api/state")[1]["screens"] == 2)
        command = "repeat 4 { look left in 0.4s linear; look right in 0.4s linear }"
        page.frames.clear()
        screen.json("POST", "/api/command", command)
        ended = eventually(lambda: not_playing(screen))
        page.until(lambda m: isinstance(m, str) and json.loads(m)["t"] > ended + 1.2)
        assert len(page.frames) >= 20  # the other page got the move, frame by frame
        # Now the stalled page reads: whatever it skipped (the frames the kernel's buffers could
        # not hold), it is sent the face as it is now (a read that waits 30 s in vain fails).
        newest = page.frames[-1]
        assert newest == screen.frame()
        assert any(message == newest for message in messages(stalled))


def not_playing(screen) -> Optional[float]:
    """The screen's `t` once nothing plays (the command and what it began ended), else None."""
    state = screen.json("GET", "/api/state")[1]
    return None if state["playing"] else max(state["t"], 1e-9)


def messages(sock: socket.socket) -> Iterator[object]:
    """A raw WebSocket's messages from the server, after the handshake: bytes, or text as str."""
    data = b""
    while b"\r\n\r\n" not in data:
        data += sock.recv(65536)
    assert data.startswith(b"HTTP/1.1 101")
    data = data.split(b"\r\n\r\n", 1)[1]
    while True:
        while len(data) < 10:
            data += sock.recv(65536)
        size, at = data[1] & 0x7F, 2
        if size >= 126:
            at = 4 if size == 126 else 10
            size = int.from_bytes(data[2:at], "big")
        while len(data) < at + size:
            data += sock.recv(1 << 20)
        binary, payload, data = data[0] & 0x0F == 2, data[at : at + size], data[at + size :]
        yield payload if binary else payload.decode("utf-8")


def test_the_state_says_what_the_face_does_and_what_is_said_is_served_as_wav(screen, engine):
    said = "This is the screen speaking, slowly enough to be asked about."
    assert screen.json("POST", "/api/command", f'happy\nsay "{said}"')[0] == 200
    deadline = time.monotonic() + 30
    while not (state := screen.json("GET", "/api/state")[1])["sounds"]:
        assert time.monotonic() < deadline, state
        time.sleep(0.05)
    assert state["saying"] == said and state["face"]["emotion"] == "happy"
    code, wav = screen.request("GET", f"/api/sound/{state['sounds'][0]['key']}.wav")
    assert code == 200
    with wave.open(io.BytesIO(wav)) as w:
        samples = np.frombuffer(w.readframes(w.getnframes()), "<i2")
    assert np.array_equal(samples, engine.say(said).samples)
    assert screen.request("GET", "/api/sound/0123456789abcdef.wav")[0] == 404
