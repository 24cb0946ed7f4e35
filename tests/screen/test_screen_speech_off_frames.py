"""A handler's `say` is synthesised off the screen's frames: a real `baxterface screen` keeps
sending a page its frames while espeak-ng works on a long sentence.

The speech process is made as slow as the test wants, and seen to be asked: it is stopped
(SIGSTOP) before the event, and the request waiting in its pipe shows the synthesis is under
way. Only then are frames asked for (`GET /api/frame.jpg`) and a second page opened: what they
get was drawn while the `say` was being prepared, which the stopped process cannot finish.
"""

from __future__ import annotations

import array
import fcntl
import os
import signal
import termios
import threading
from pathlib import Path
from typing import Optional

import pytest
from test_web import pages

from studio_server import running_screen
from waiting import eventually

pytestmark = pytest.mark.xdist_group("screen_speech")

LONG = (
    "Hello there, and welcome: this is a long sentence, said by a face on a screen, which takes "
    "espeak-ng a while to turn into sound, with every phoneme and word timed for the mouth, while "
    "the eyes go on moving across the screen as if nothing at all were happening behind them."
)
SCRIPT = f"""\
on signal talk {{ say "{LONG}" }}
say "Hi."
look left in 60s linear
"""


def speech_process(server: int) -> Optional[int]:
    """The screen's espeak-ng child (speech/espeak_process.py), once it has started."""
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            parent = int((entry / "stat").read_text().rsplit(")", 1)[1].split()[1])
            command = (entry / "cmdline").read_bytes()
        except (OSError, IndexError, ValueError):
            continue
        if parent == server and b"espeak_child" in command:
            return int(entry.name)
    return None


def asked(child: int) -> int:
    """Bytes of a request waiting in the speech process's pipe, unread: it is stopped."""
    requests = (Path(f"/proc/{child}/cmdline").read_bytes().rstrip(b"\0").split(b"\0"))[-2].decode()
    fd = os.open(f"/proc/{child}/fd/{requests}", os.O_RDONLY | os.O_NONBLOCK)
    try:
        waiting = array.array("i", [0])
        fcntl.ioctl(fd, termios.FIONREAD, waiting)
        return waiting[0]
    finally:
        os.close(fd)


def test_frames_keep_coming_while_a_handlers_long_say_is_synthesised(tmp_path, engine):
    (tmp_path / "talker.face").write_text(SCRIPT)
    screen_running = running_screen(tmp_path, str(tmp_path / "talker.face"), "--no-idle")
    with screen_running as screen, pages(screen):
        # The page opened: "Hi." started the speech process; then the eyes move for a minute.
        eventually(lambda: screen.json("GET", "/api/state")[1]["face"]["eye_x"] > 0)
        child = eventually(lambda: speech_process(screen.process.pid))
        answers = []
        event = lambda: answers.append(screen.json("POST", "/api/event", "signal talk"))  # noqa: E731
        talk = threading.Thread(target=event)
        os.kill(child, signal.SIGSTOP)
        try:
            talk.start()
            eventually(lambda: asked(child) > 0)  # the handler's `say` is being synthesised
            for _ in range(3):
                status, jpeg = screen.request("GET", "/api/frame.jpg")
                assert status == 200 and jpeg.startswith(b"\xff\xd8")
            with pages(screen) as (late,):  # opened now: every frame it gets is drawn from now on
                for _ in range(3):  # the pump sends a frame only when it changed: the eyes move
                    late.until(lambda m: isinstance(m, bytes))
            assert len(late.frames) >= 3 and asked(child) > 0 and not answers
        finally:
            os.kill(child, signal.SIGCONT)
        talk.join(60)
        assert answers == [(200, {"event": "signal talk", "runs": 1, "dropped": 0, "queued": 0})]
        eventually(lambda: screen.json("GET", "/api/state")[1]["saying"] == LONG)
