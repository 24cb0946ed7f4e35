"""`baxterface screen --log FILE`: the session's record of a real screen, its scripts, events,
handlers and end, as JSON Lines, written as it goes."""

from __future__ import annotations

import json

import pytest
from test_web import pages

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
