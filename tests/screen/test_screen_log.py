"""`baxterface screen --log FILE`: the session's record of a real screen, its scripts, events,
handlers and end, as JSON Lines, written as it goes."""

from __future__ import annotations

import json
import re

import pytest
from test_web import pages

from conftest import baxterface
from studio_server import running_screen
from waiting import eventually

pytestmark = pytest.mark.xdist_group("screen_log")

GREETER = """\
on signal poke { happy
  wait 0.3s }
on touch mouth { sad }
look left in 0.2s
"""


def records(path):
    return [json.loads(line) for line in path.read_text(encoding="utf-8").splitlines()]


@pytest.fixture(scope="module")
def logged(tmp_path_factory):
    """A session at the screen, with a few events and a command, and its log once it stopped."""
    folder = tmp_path_factory.mktemp("screen_log")
    (folder / "greeter.face").write_text(GREETER)
    path = folder / "session.jsonl"
    args = (str(folder / "greeter.face"), "--no-idle", "--log", str(path))
    with running_screen(folder, *args) as screen, pages(screen) as (page,):
        page.until(lambda m: isinstance(m, bytes))
        eventually(lambda: not screen.json("GET", "/api/state")[1]["waiting"])
        assert screen.json("POST", "/api/event", "signal poke")[0] == 200
        # Flushed as it goes: the event is in the file while the screen runs.
        eventually(lambda: any(r["type"] == "event" for r in records(path)))
        eventually(lambda: screen.json("GET", "/api/state")[1]["running"] is None)
        assert screen.json("POST", "/api/event", "touch mouth")[0] == 200
        eventually(lambda: screen.json("GET", "/api/state")[1]["running"] is None)
        assert screen.json("POST", "/api/command", "on signal poke { angry }")[0] == 200
        assert screen.json("POST", "/api/event", "signal poke")[0] == 200
        eventually(lambda: screen.json("GET", "/api/state")[1]["running"] is None)
    return folder, path, records(path)


def test_the_screens_log_has_its_start_scripts_events_handlers_and_end(logged):
    _, _, got = logged
    assert got[0]["type"] == "start" and got[0]["settings"]["end"] == "screen" and got[0]["version"] == 1
    scripts = [r for r in got if r["type"] == "script"]
    assert [s["text"] for s in scripts] == [GREETER, "on signal poke { angry }"]
    events = [(r["event"], r["source"]) for r in got if r["type"] == "event"]
    assert [e for e, _ in events] == ["signal poke", "touch mouth", "signal poke"]
    assert all(source for _, source in events)
    kinds = [r["kind"] for r in got if r["type"] == "log"]
    assert kinds.count("started") == 3 and "replaced" in kinds
    assert got[-1]["type"] == "end"
    times = [r["t"] for r in got]
    assert times == sorted(times)


def explained_starts(out: str):
    """(time, label) of each handler's start in `explain`'s lines."""
    found = re.findall(r"^\s+(\d+\.\d\d) s\s+react (line \d+ '[^']+') runs$", out, re.M)
    return [(float(t), label) for t, label in found]


def test_explain_of_the_log_runs_the_same_handlers_at_the_same_times(logged):
    _, path, got = logged
    run = baxterface("explain", str(path))
    assert run.code == 0, run.err
    assert run.err == ""
    first = next(r["t"] for r in got if r["type"] == "script")
    live = [(r["t"] - first, r["text"][: -len(" runs")]) for r in got if r.get("kind") == "started"]
    replayed = explained_starts(run.out)
    assert [label for _, label in replayed] == [label for _, label in live]
    assert all(abs(a - b) <= 0.01 for (a, _), (b, _) in zip(replayed, live))
    assert "react signal poke: its handler replaced" in run.out
    assert "react event touch mouth (POST /api/event)" in run.out
    # It lasts as the session did, from its script's start to its end.
    assert f": {got[-1]['t'] - first:.2f} s" in run.out.splitlines()[0]


def test_render_of_the_log_makes_the_video_of_what_the_face_showed(logged):
    folder, path, _ = logged
    out = folder / "session.mp4"
    run = baxterface("render", str(path), "--out", str(out), "--size", "256x150", "--fps", "10")
    assert run.code == 0, run.err
    assert out.stat().st_size > 0 and re.search(r"wrote .*session\.mp4 \(\d+ frames, \d+\.\d\d s\)", run.err)


def test_a_log_cut_short_is_read_up_to_its_last_good_record_and_says_where(logged, tmp_path):
    _, path, got = logged
    lines = path.read_text(encoding="utf-8").splitlines()
    cut = tmp_path / "cut.jsonl"
    cut.write_text("\n".join(lines[:-3] + [lines[-3][:20]]) + "\n", encoding="utf-8")
    run = baxterface("explain", str(cut))
    assert run.code == 0, run.err
    (said,) = run.err.splitlines()
    assert said.startswith(f"baxterface explain: {cut}:{len(lines) - 2}: not a record (")
    assert said.endswith("read up to the record before it")
    newer = tmp_path / "newer.jsonl"
    newer.write_text(
        "\n".join([lines[0].replace('"version": 1', '"version": 2'), *lines[1:]]), encoding="utf-8"
    )
    run = baxterface("explain", str(newer))
    assert run.code == 0 and "a log of version 2, newer than this baxterface's 1: read as 1" in run.err
    none = tmp_path / "none.jsonl"
    none.write_text(lines[0] + "\n", encoding="utf-8")
    run = baxterface("explain", str(none))
    assert run.code == 1 and run.err == f"baxterface explain: {none}: no script in it to replay\n"
