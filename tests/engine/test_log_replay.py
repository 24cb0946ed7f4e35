"""A session's log run again: its first script, its events at their times from the first script's
start, later scripts as what they were (a take-over, or one sent to wait for the face to be free)."""

from __future__ import annotations

import json

import pytest

from baxterface_cli.engine.log_replay import LogError, read_log, run_log


def write(path, *records):
    path.write_text("".join(json.dumps(r) + "\n" for r in records), encoding="utf-8")
    return str(path)


START = {"type": "start", "t": 0.0, "version": 1, "settings": {"end": "node", "seed": 3}}


def test_later_scripts_take_over_or_wait_for_the_face_to_be_free(tmp_path):
    path = write(
        tmp_path / "s.jsonl",
        START,
        {"type": "script", "t": 1.0, "text": "on button ok { happy\n wait 1s }", "source": "display_chatter"},
        {"type": "event", "t": 2.0, "event": "button ok", "source": "/robot/navigators"},
        {"type": "script", "t": 2.5, "text": "sad", "source": "~queue", "queued": True},
        {"type": "script", "t": 6.0, "text": "look left in 0.5s", "source": "display_chatter"},
        {"type": "script", "t": 6.1, "text": "hapy", "source": "display_chatter"},
        {"type": "end", "t": 8.0},
    )
    replay = read_log(path)
    assert replay.seed == 3 and replay.end == 7.0
    assert replay.notes == (f"{path}: 1 command the face refused live left out",)
    run = run_log(replay, replay.seed)
    lines = [(round(line.at, 2), line.text) for line in run.log]
    assert (1.0, "event button ok (/robot/navigators)") in lines
    started = [at for at, _ in run.session.segments]
    # The handler at 1 s; the queued `sad` once it ends (after its 1 s wait); the take-over at 5 s.
    assert started[0] == 1.0 and any(2.2 < at < 2.5 for at in started) and started[-1] == 5.0
    assert run.timeline.duration == pytest.approx(7.0)


def test_a_part_after_a_rotation_or_a_file_of_no_log_is_refused_in_one_line(tmp_path):
    part = write(tmp_path / "p.jsonl", {"type": "continued", "t": 5.0, "version": 1, "part": 2})
    with pytest.raises(LogError, match=r"begins after a rotation \(part 2\)"):
        read_log(part)
    script = tmp_path / "a.jsonl"
    script.write_text("happy\n")
    with pytest.raises(LogError, match=r"a.jsonl:1: not a record \(.*\): not a session log$"):
        read_log(str(script))
