"""`baxterface studio --log FILE`: the studio's session in its log as every live end keeps one,
and a replay of it that shows what the preview showed, to the bit."""

from __future__ import annotations

import json

import pytest

from baxterface_cli.engine.log_replay import read_log, run_log
from baxterface_cli.engine.session_log_file import SessionLogFile
from baxterface_cli.language import syntax_tree as n
from baxterface_cli.studio.workspace import Workspace
from conftest import baxterface
from studio_server import running_studio
from waiting import eventually

SCRIPT = "sad\non signal poke {\n  happy\n  wait 1s\n}\non touch mouth { surprise }\nwait 6s\n"


def records(path):
    return [json.loads(line) for line in path.read_text(encoding="utf-8").splitlines()]


def test_the_log_replays_the_preview_the_studio_showed_after_edits_events_sought_back_and_a_clear(tmp_path):
    script = tmp_path / "greeter.face"
    script.write_text(SCRIPT)
    path = tmp_path / "studio.jsonl"
    now = [100.0]
    record = SessionLogFile(str(path), now[0], {"end": "studio", "seed": 11})
    studio = Workspace(script, seed=11, idle=False, clock=lambda: now[0], record=record)

    def fire(at, event):
        now[0] += 0.5  # the studio's clock goes on; the event is fired where the preview is put
        studio.transport("pause")
        studio.transport("seek", at)
        return studio.event(event, "POST /api/event")

    fire(1.0, n.Event("signal", "poke"))
    fire(4.0, n.Event("signal", "poke"))
    studio.clear_session()  # those two let go
    fire(3.0, n.Event("signal", "poke"))
    fire(1.5, n.Event("touch", "mouth"))  # sought back, before the other
    studio.update(SCRIPT.replace("happy", "angry"))  # the events run again over the edit
    fire(5.0, n.Event("signal", "poke"))
    now[0] += 0.5
    studio.transport("pause")
    studio.transport("seek", 2.2)
    assert studio.press("look left in 0.5s\nsurprise") == {"at": 2.2}  # a command: it takes over there
    record.close(now[0])

    got = records(path)
    assert got[0]["type"] == "start" and got[0]["settings"] == {"end": "studio", "seed": 11}
    assert [r["source"] for r in got if r["type"] == "script"] == ["greeter.face", "greeter.face", "panel"]
    assert [(r["at"], r["text"]) for r in got if r.get("press")] == [(2.2, "look left in 0.5s\nsurprise")]
    assert [(r["event"], r["at"]) for r in got if r["type"] == "event"] == [
        ("signal poke", 1.0), ("signal poke", 4.0), ("signal poke", 3.0), ("touch mouth", 1.5),
        ("signal poke", 5.0),
    ]  # fmt: skip
    assert sum(r["type"] == "cleared" for r in got) == 1
    started = [(r["at"], r["text"]) for r in got if r.get("kind") == "started"]
    assert (3.0, "line 2 'on signal poke' runs") in started and (
        1.5,
        "line 6 'on touch mouth' runs",
    ) in started
    times = [r["t"] for r in got]
    assert times == sorted(times) and got[-1]["type"] == "end"

    replay = read_log(str(path))
    assert replay.notes == () and replay.seed == 11
    assert [(e.at, e.event.kind) for e in replay.trace.events] == [
        (1.5, "touch"),
        (3.0, "signal"),
        (5.0, "signal"),
    ]
    pressed = [(later.at, later.script.source) for later in replay.later]
    assert pressed == [(2.2, "look left in 0.5s\nsurprise")]
    run = run_log(replay, replay.seed)
    preview = studio.preview.animation
    assert run.timeline.duration == pytest.approx(preview.duration)
    frames = [i / 30 for i in range(int(preview.duration * 30) + 1)]
    assert [run.timeline.sample(t) for t in frames] == [preview.timeline.sample(t) for t in frames]
    assert preview.timeline.sample(3.6).emotion == "angry"  # the edit's handler, at the event fired before it


def test_the_studio_keeps_its_log_with_the_seed_it_chose_and_explain_reads_it(tmp_path):
    (tmp_path / "greeter.face").write_text(SCRIPT)
    path = tmp_path / "studio.jsonl"
    words = ("--no-idle", "--log", str(path))
    with running_studio(tmp_path / "greeter.face", *words) as studio:
        assert studio.json("POST", "/api/transport", {"action": "seek", "t": 2.0})[0] == 200
        status, answer = studio.json("POST", "/api/event", "signal poke")
        assert status == 200 and answer["runs"] == 1, answer
        # Flushed as it goes: the event and its handler's run are in the file while the studio runs.
        eventually(lambda: any(r.get("kind") == "started" for r in records(path)))
        assert studio.stop() == 128 + 15  # stopped by SIGTERM, its log closed first
    got = records(path)
    assert got[0]["settings"]["end"] == "studio" and got[0]["settings"]["seed"] == 7
    event = next(r for r in got if r["type"] == "event")
    assert event["source"] == "POST /api/event" and 1.9 < event["at"] < 2.5
    assert got[-1]["type"] == "end"
    run = baxterface("explain", str(path))
    assert run.code == 0 and run.err == "", run.err
    assert "react line 2 'on signal poke' runs" in run.out
