"""Log lines written off the caller's thread: a slow log never stalls the frame loop."""

from __future__ import annotations

import threading

from baxterface_cli.engine.log_backlog import Backlog


def test_logging_returns_at_once_while_the_writer_is_stuck_and_every_line_comes_out_in_order():
    release = threading.Event()
    written = []

    def write(level, text):
        release.wait(30)  # a log that takes as long as we like
        written.append((level, text))

    log = Backlog(write)
    log.error("bad command 1")
    log.warn("refused a queued script")
    log.info("registering again")
    assert written == []  # the caller got on with its work
    release.set()
    assert log.flush(timeout=30)
    assert written == [
        ("error", "bad command 1"),
        ("warn", "refused a queued script"),
        ("info", "registering again"),
    ]


def test_a_flood_beyond_the_backlog_is_counted_in_one_line_not_kept():
    started, release = threading.Event(), threading.Event()
    written = []

    def write(level, text):
        started.set()
        release.wait(30)
        written.append(text)

    log = Backlog(write, max_waiting=5)
    log.error("first")
    assert started.wait(30)  # the writer holds "first"; 5 more may wait
    for k in range(100):
        log.error(f"bad command {k}")
    release.set()
    assert log.flush(timeout=30)
    assert written == ["first"] + [f"bad command {k}" for k in range(5)] + [
        "95 more log lines were skipped: too many at once"
    ]


def test_a_write_that_fails_does_not_end_logging():
    written = []

    def write(level, text):
        if text == "boom":
            raise OSError("disk full")
        written.append(text)

    log = Backlog(write)
    log.error("boom")
    log.error("after")
    assert log.flush(timeout=30)
    assert written == ["after"]
