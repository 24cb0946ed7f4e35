"""Lines the screen and the studio log from several threads at once are each read back whole.

Standard error is a real file here, behind a stream that gives the other threads their turn after
every write (as a pipe that fills does), so that lines written in pieces would interleave.
"""

from __future__ import annotations

import sys
import threading
import time

from baxterface_cli.web.server import logger

THREADS = 8
LINES = 300


class Yielding:
    """A text stream onto a real file that records each write and lets other threads run after it."""

    def __init__(self, file) -> None:
        self.file = file
        self.writes: list = []

    def write(self, text: str) -> int:
        self.writes.append(text)
        written = self.file.write(text)
        time.sleep(0)  # the other threads' turn, in the middle of a line if it comes in pieces
        return written

    def flush(self) -> None:
        self.file.flush()


def test_lines_logged_from_many_threads_at_once_are_each_whole(tmp_path, monkeypatch):
    path = tmp_path / "stderr.log"
    with open(path, "w", encoding="utf-8") as file:
        stream = Yielding(file)
        monkeypatch.setattr(sys, "stderr", stream)
        log = logger("screen")
        start = threading.Barrier(THREADS)

        def say(who: int) -> None:
            start.wait()
            for number in range(LINES):
                log(f"thread {who} line {number} " + "x" * (number % 50))

        threads = [threading.Thread(target=say, args=(who,)) for who in range(THREADS)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
        monkeypatch.undo()
    expected = {
        f"baxterface screen: thread {who} line {number} " + "x" * (number % 50)
        for who in range(THREADS)
        for number in range(LINES)
    }
    lines = path.read_text(encoding="utf-8").splitlines()
    assert len(lines) == THREADS * LINES
    assert set(lines) == expected
    assert all(text.count("\n") == 1 and text.endswith("\n") for text in stream.writes)  # one write a line
