"""Ten minutes of random events on a fast clock, through the session's log file as the live ends
keep it (bench/bench_log_soak.py runs the hour, and measures memory): the log complete, every
event and every handler's start, drop, queue and end in it, checked by replaying it: the
replay's log is the live one, line for line, at the same times."""

from __future__ import annotations

import json
from collections import Counter

from log_soak import soak

from baxterface_cli.engine.log_replay import read_log, run_log

MINUTES = 10


def test_ten_minutes_of_random_events_are_all_in_the_log_and_its_replay_is_the_live_session(tmp_path):
    path = tmp_path / "soak.jsonl"
    seconds = MINUTES * 60.0
    got = soak(str(path), seconds, sample=60.0)
    session, events = got["session"], got["events"]
    records = [json.loads(line) for line in path.read_text(encoding="utf-8").splitlines()]
    assert not [r for r in records if r["type"] == "skipped"]
    assert sum(r["type"] == "event" for r in records) == sum(got["posted"].values()) == events
    lines = [(r["t"], r["kind"], r["text"]) for r in records if r["type"] == "log"]
    assert len(lines) == session.logged  # every line the session logged
    assert lines[-len(session.log) :] == [(line.at, line.kind, line.text) for line in session.log]
    kinds = Counter(kind for _, kind, _ in lines)
    assert kinds["event"] == events and kinds["started"] > 200 and kinds["dropped"] > 20
    assert kinds["queued"] > 5 and kinds["interrupted"] > 5 and kinds["ended"] > 200

    replay = read_log(str(path))
    assert replay.notes == () and len(replay.trace.events) == events
    run = run_log(replay, replay.seed, duration=seconds)
    assert [(line.at, line.kind, line.text) for line in run.log] == lines
