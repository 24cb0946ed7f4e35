"""The studio's events: fired by hand at the script the editor plays, as `render --events` plays
them; `POST /api/event` on a real studio over loopback; a session with events exports as the
script plus its events file, which `explain --events` replays."""

from __future__ import annotations

import re
import subprocess

from baxterface_cli.engine.log_replay import read_log, run_log
from baxterface_cli.engine.session_run import run_over
from baxterface_cli.language.event_line import read_event_line
from baxterface_cli.language.event_trace import parse_trace
from baxterface_cli.language.parser import parse
from baxterface_cli.studio.workspace import Workspace
from studio_server import baxterface, running_studio

GREETER = "sad\nwait 1s\non signal poke {\n  happy\n  wait 1s\n}\non touch left eye {\n  angry\n}\nwait 3s\n"


class Clock:
    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def test_the_preview_shows_what_render_with_the_fired_events_would(tmp_path):
    path = tmp_path / "greeter.face"
    path.write_text(GREETER)
    clock = Clock()
    workspace = Workspace(path, seed=7, idle=False, clock=clock)
    assert workspace.update(GREETER)["diagnostics"] == []  # no longer refused
    assert workspace.timeline()["listens"] == ["signal poke", "touch left eye"]
    workspace.transport("seek", 0.5)
    answer = workspace.event(read_event_line("signal poke"))
    assert answer["event"] == "signal poke" and answer["at"] == 0.5 and answer["runs"] == 1
    trace = parse_trace("0.5 signal poke\n", "e")
    expected = run_over(parse(GREETER, "greeter.face"), trace, seed=7).timeline
    for t in (0.2, 0.6, 1.0, 2.0, 3.0):
        clock.now = 100.0 + (t - 0.5)  # the preview plays on from the event
        assert workspace.face(workspace.clock()) == expected.sample(t), t
    clock.now = 100.0 + 0.3
    assert workspace.face(workspace.clock()).emotion == "happy"
    workspace.clear_session()
    assert workspace.timeline()["fired"] == 0
    assert workspace.face(workspace.clock()).emotion == "sad"  # the script as it plays without any event


def test_events_fired_at_a_real_studio_play_and_export_with_the_script(tmp_path):
    script = tmp_path / "greeter.face"
    script.write_text(GREETER)
    with running_studio(script, "--no-idle") as studio:
        status, state = studio.json("GET", "/api/state")
        assert status == 200 and state["timeline"]["listens"] == ["signal poke", "touch left eye"]
        assert studio.json("POST", "/api/transport", {"action": "pause"})[0] == 200
        assert studio.json("POST", "/api/transport", {"action": "seek", "t": 0.2})[0] == 200
        status, answer = studio.json("POST", "/api/event", "signal poke")
        assert status == 200 and answer["event"] == "signal poke" and answer["runs"] == 1, answer
        assert answer["at"] == 0.2 and studio.json("GET", "/api/state")[1]["status"]["playing"]
        assert studio.json("POST", "/api/transport", {"action": "pause"})[0] == 200
        assert studio.json("POST", "/api/transport", {"action": "seek", "t": 3.0})[0] == 200
        status, answer = studio.json("POST", "/api/event", "touch left eye")
        assert status == 200 and answer["runs"] == 1 and answer["at"] == 3.0, answer
        status, answer = studio.json("POST", "/api/event", "signal")
        assert status == 400 and answer["diagnostics"][0]["line"] == 1, answer
        status, answer = studio.json("POST", "/api/event", "signal a\nsignal b")
        assert status == 400 and answer["diagnostics"][0]["line"] == 2, answer
        assert studio.json("GET", "/api/state")[1]["timeline"]["fired"] == 2
        status, exported = studio.json("POST", "/api/session/export")
        assert status == 200, exported
    assert (tmp_path / exported["events_path"]).read_text() == exported["events_text"]
    lines = exported["events_text"].splitlines()
    assert [line.split(" ", 1)[1] for line in lines] == ["signal poke", "touch left eye"]
    replayed = tmp_path / exported["script_path"]
    assert GREETER in replayed.read_text()
    command = re.search(r"replays exactly with: baxterface (.*)", replayed.read_text()).group(1).split()
    assert command[:2] == ["render", replayed.name] and "--events" in command and "--out" in command
    done = subprocess.run(
        [baxterface(), "explain", str(replayed), "--events", str(tmp_path / exported["events_path"])]
        + ["--seed", "7"],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    assert "'on signal poke' runs" in done.stdout and "'on touch left eye' runs" in done.stdout


def test_a_press_that_reacts_takes_over_the_one_session_and_the_export_replays_it(tmp_path):
    path = tmp_path / "greeter.face"
    path.write_text(GREETER)
    clock = Clock()
    workspace = Workspace(path, seed=7, idle=False, clock=clock)
    workspace.transport("seek", 0.5)
    assert workspace.press("wait until signal go\none of {\n  angry\n  |\n  happy\n}") == {"at": 0.5}
    clock.now += 1.0
    assert workspace.face(clock.now).emotion != "angry"  # it waits, as a command on the node would
    answer = workspace.event(read_event_line("signal go"))  # the event ends the pressed command's wait
    assert answer["at"] == 1.5 and workspace.timeline()["fired"] == 1
    clock.now += 1.0
    assert workspace.face(clock.now).emotion in ("angry", "happy")
    exported = workspace.export_session()
    assert "script_path" not in exported  # no events file holds a command: the session's log does
    replay = read_log(str(tmp_path / exported["path"]))
    run = run_log(replay, replay.seed).timeline
    shown = workspace.preview.animation.timeline
    assert run.duration == shown.duration
    frames = [i / 30 for i in range(int(shown.duration * 30) + 1)]
    assert [run.sample(t) for t in frames] == [shown.sample(t) for t in frames]
