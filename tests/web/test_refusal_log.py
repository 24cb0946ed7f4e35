"""A flood of one bad request is a few log lines with counts, never a line each; different
mistakes are each logged as they come (web/refusal_log.py, on a clock the test gives)."""

from __future__ import annotations

from baxterface_cli.web.refusal_log import RefusalLog


def test_one_refusal_repeated_is_logged_once_a_second_with_the_count_between():
    lines, now = [], [0.0]
    log = RefusalLog(lines.append, clock=lambda: now[0])
    bad = "POST /api/touch: 400 a touch is JSON with x and y"
    for _ in range(1000):  # a thousand in 0.5 s
        log(bad)
        now[0] += 0.0005
    assert lines == [bad]
    now[0] = 1.2
    log(bad)
    assert lines == [bad, bad + " (999 more like it before)"]


def test_different_refusals_are_each_logged_at_once():
    lines = []
    log = RefusalLog(lines.append, clock=lambda: 5.0)
    for text in (
        "POST /api/event: 400 1:8: unknown button 'okk'",
        "POST /api/event: 400 1:1: unknown event 'x'",
    ):
        log(text)
    assert len(lines) == 2


def test_a_refusal_of_any_length_is_logged_in_at_most_a_few_hundred_characters():
    lines = []
    log = RefusalLog(lines.append, clock=lambda: 5.0)
    log("POST /api/command: 400 unknown command " + "x" * 262_209)
    assert len(lines) == 1 and len(lines[0]) < 600
    assert lines[0].endswith(f"... ({262_209 + 39:,} characters)")
