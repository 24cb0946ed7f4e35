"""The studio: its session, preview and panel without the web, then a real server over HTTP."""

from __future__ import annotations

import io
import json
import os
import re
import signal
import socket
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from baxterface_cli.engine.compiler import compile_script
from baxterface_cli.engine.log_replay import read_log, run_log
from baxterface_cli.language.diagnostics import ScriptError
from baxterface_cli.language.parser import parse
from baxterface_cli.studio.panel import DEFAULT_PANEL, PanelError, load_panel
from baxterface_cli.studio.preview import SCRIPT, SESSION, Transport
from baxterface_cli.studio.workspace import Workspace, check_text
from studio_server import baxterface, running_studio

REPO = Path(__file__).resolve().parents[2]
PRESSES = [  # (seconds after the first, command): overlapping and not, legacy and new
    (0.0, "happy"),
    (0.9, "look left in 2s ease-in-out"),
    (1.6, "sad"),  # while the look is under way: the eyes go on
    (2.2, "look_20_40_0.5"),  # takes the eyes over from where they got to
    (5.0, "blink"),
    (5.05, "wobble 0.4 in 1s"),
    (7.3, "angry\nnod"),
    (9.0, "follow human"),
    (9.4, "look up in 0.3s"),
]


def performed(folder, presses, script="", seed=11):
    """A studio (without the web) on `script`, `presses` pressed at their times (seconds from the
    first, on its clock), looked at as the page does meanwhile, 30 times a second between frames:
    the workspace, and what the preview showed at each position."""
    (folder / "show.face").write_text(script)
    now = [1000.0]
    workspace = Workspace(folder / "show.face", seed=seed, idle=False, clock=lambda: now[0])
    shown, pressed = [], 0
    end = presses[-1][0] + 3.0
    for t in [(i + 0.5) / 30 for i in range(int(end * 30))]:
        while pressed < len(presses) and presses[pressed][0] <= t:
            now[0] = 1000.0 + presses[pressed][0]
            workspace.press(presses[pressed][1])
            pressed += 1
        now[0] = 1000.0 + t
        shown.append(workspace.preview.at(now[0]))
    return workspace, shown


def replayed(folder, workspace):
    """The session's export, replayed as `render` replays it."""
    exported = folder / workspace.export_session()["path"]
    replay = read_log(str(exported))
    assert replay.notes == () and replay.seed == workspace.preview.seed
    return run_log(replay, replay.seed).timeline


def test_the_exported_session_replays_what_the_preview_showed(tmp_path):
    workspace, shown = performed(tmp_path, PRESSES)
    replay = replayed(tmp_path, workspace)
    # Each press took over the one session where the preview was: the export replays it, to the bit.
    assert [(replay.sample(t), replay.status(t)) for t, _, _ in shown] == [(f, r) for _, f, r in shown]
    # and the face did change at each press: the replay is not trivially equal
    eyes = {round(face.eye_x) for _, face, _ in shown}
    assert len(eyes) > 5
    assert {face.emotion for _, face, _ in shown} >= {"happy", "sad", "angry"}


def test_a_long_sessions_export_replays_what_the_preview_showed(tmp_path):
    presses = [(i * 0.7, ["angry", "look left in 1s", "confused", "happy", "sad"][i % 5]) for i in range(60)]
    workspace, shown = performed(tmp_path, presses, "happy\nwait 2s\n")
    replay = replayed(tmp_path, workspace)
    assert [(replay.sample(t), replay.status(t)) for t, _, _ in shown] == [(f, r) for _, f, r in shown]
    assert {face.emotion for _, face, _ in shown} >= {"angry", "confused", "happy", "sad"}


def test_a_press_is_at_the_previews_position_and_the_session_goes_on_with_the_clock(tmp_path):
    (tmp_path / "show.face").write_text("")
    now = [50.0]
    workspace = Workspace(tmp_path / "show.face", seed=1, idle=False, clock=lambda: now[0])
    assert workspace.press("happy") == {"at": 0.0}  # the preview stood at 0
    now[0] = 51.2345
    assert workspace.press("sad") == {"at": 1.234}  # live since: as long after it as it came
    presses = workspace.session()["presses"]
    assert [(p["at"], p["command"]) for p in presses] == [(0.0, "happy"), (1.234, "sad")]
    assert workspace.status(60.0)["mode"] == SESSION and workspace.status(60.0)["t"] == pytest.approx(10.0)


def test_the_export_is_the_sessions_log_each_press_a_command_at_its_time(tmp_path):
    workspace, _ = performed(tmp_path, [(0.0, "happy"), (2.0, "look left in 0.5s")], "sad\n", seed=1)
    records = [json.loads(line) for line in workspace.export_session()["text"].splitlines()]
    assert records[0]["type"] == "start" and records[0]["settings"] == {"end": "studio", "seed": 1}
    assert [(r["type"], r.get("at"), r["text"]) for r in records[1:]] == [
        ("script", None, "sad\n"),
        ("script", 0.0, "happy"),
        ("script", 2.0, "look left in 0.5s"),
    ]
    assert all(r.get("press") is True for r in records[2:])


def test_a_bad_press_changes_nothing_and_says_why(tmp_path):
    (tmp_path / "show.face").write_text("")
    workspace = Workspace(tmp_path / "show.face", seed=1, idle=False, clock=lambda: 0.0)
    workspace.press("happy")
    with pytest.raises(ScriptError) as e:
        workspace.press("hapy")
    assert "did you mean 'happy'" in e.value.diagnostics[0].message
    with pytest.raises(ScriptError) as e:  # a handler is the script's, from its start: alone
        workspace.press("on signal x { blink }\nnod")
    assert "press a handler alone" in e.value.diagnostics[0].message
    with pytest.raises(ScriptError) as e:
        workspace.press("define x { blink }")
    assert "a definition alone does nothing" in e.value.diagnostics[0].message
    assert workspace.session()["count"] == 1 and len(workspace.preview.inputs) == 1
    workspace.press("define x { blink }\nx")  # a definition with what calls it: a command like any
    assert workspace.session()["count"] == 2


def test_a_press_that_fails_midway_leaves_the_session_as_it_was(tmp_path):
    # Its first step plays; its second, a recording outside the script's folder, fails as the run
    # goes on to its end: what the first added to the kept run is taken back.
    (tmp_path / "show.face").write_text("happy\n")
    now = [0.0]
    workspace = Workspace(tmp_path / "show.face", seed=7, idle=False, clock=lambda: now[0])
    workspace.press("sad")
    now[0] = 1.0
    run = workspace.preview.run
    kept = (list(run.played), list(run.lines))
    with pytest.raises(ScriptError, match="outside"):
        workspace.press('look left in 1s\nsay file "../outside.wav"')
    assert workspace.preview.run is run and (run.played, run.lines) == kept
    now[0] = 2.0
    workspace.press("look right in 0.5s")
    replay = replayed(tmp_path, workspace)
    shown = workspace.preview.animation.timeline
    frames = [i / 30 for i in range(int(shown.duration * 30) + 1)]
    assert [replay.sample(t) for t in frames] == [shown.sample(t) for t in frames]
    assert [p["command"] for p in workspace.session()["presses"]] == ["sad", "look right in 0.5s"]


def test_the_transport_plays_pauses_seeks_and_loops():
    transport = Transport()
    assert transport.position(10.0, 4.0) == 0.0
    transport.play(10.0, 4.0)
    assert transport.position(11.5, 4.0) == 1.5
    transport.pause(12.0, 4.0)
    assert transport.position(20.0, 4.0) == 2.0
    transport.seek(3.0, 20.0, 4.0)
    transport.play(20.0, 4.0)
    assert transport.position(25.0, 4.0) == 4.0  # held at the end
    transport.settle(25.0, 4.0)
    assert not transport.playing
    transport.play(26.0, 4.0)  # play at the end starts again
    transport.set_loop(True, 26.0, 4.0)
    assert transport.position(31.0, 4.0) == pytest.approx(1.0)


def test_a_press_takes_over_the_script_where_the_preview_is_and_play_goes_back_to_the_transport(tmp_path):
    (tmp_path / "show.face").write_text("look left in 1s\nwait 2s")
    now = [0.0]
    workspace = Workspace(tmp_path / "show.face", seed=3, idle=False, clock=lambda: now[0])
    workspace.transport("play")
    assert workspace.status(0.5)["mode"] == SCRIPT and workspace.face(0.5).eye_x != 0
    now[0] = 0.6
    assert workspace.press("sad") == {"at": 0.6}  # the script taken over at 0.6, as on the node
    assert workspace.status(1.5)["mode"] == SESSION
    assert workspace.face(1.5).emotion == "sad"
    assert workspace.preview.duration < 1.5  # the script's `wait 2s` was let go
    now[0] = 2.0
    status = workspace.transport("play")  # back on the transport: at the run's end, from its start
    assert status["mode"] == SCRIPT and status["t"] == 0.0
    assert status["duration"] == round(workspace.preview.duration, 3)
    assert workspace.face(2.3).eye_x != 0 and workspace.face(2.3).emotion != "sad"
    assert workspace.face(2.8).emotion == "sad"  # the press, in the run the transport plays


def test_the_session_clock_never_runs_past_the_session_length_it_shows(tmp_path):
    (tmp_path / "show.face").write_text("look left in 1s\nwait 8s")
    now = [0.0]
    workspace = Workspace(tmp_path / "show.face", seed=3, idle=False, clock=lambda: now[0])
    assert workspace.status(0.0)["duration"] == 9.0
    workspace.transport("play")
    now[0] = 10.0
    assert workspace.press("happy") == {"at": 9.0}  # the script had played out
    early = workspace.status(10.2)
    assert early["mode"] == SESSION and early["t"] == 9.2
    assert early["duration"] == round(workspace.preview.duration, 3) > early["t"]
    late = workspace.status(32.21)  # long after the press's face has settled: the session goes on
    assert late["t"] == late["duration"] == 31.21
    now[0] = 33.0
    assert workspace.transport("pause")["duration"] == round(workspace.preview.duration, 3)  # the run's


def test_a_press_compiles_without_holding_the_preview_still(tmp_path, monkeypatch):
    """The frame pump reads the face many times a second: a slow press must not stop it."""
    import threading

    from baxterface_cli.studio import event_run

    (tmp_path / "show.face").write_text("happy\n")
    workspace = Workspace(tmp_path / "show.face", idle=False)
    compiling, finish = threading.Event(), threading.Event()
    slow = event_run.EventRun.with_input

    def with_input(self, item):
        compiling.set()
        assert finish.wait(30)  # a long run going on
        return slow(self, item)

    monkeypatch.setattr(event_run.EventRun, "with_input", with_input)
    press = threading.Thread(target=workspace.press, args=("sad",))
    press.start()
    assert compiling.wait(30)
    shown = []
    reader = threading.Thread(
        target=lambda: shown.extend([workspace.face(workspace.clock()), workspace.status(workspace.clock())])
    )
    reader.start()
    reader.join(10)
    try:
        assert len(shown) == 2  # answered while the press was still compiling
    finally:
        finish.set()
        press.join(30)
    assert [p["command"] for p in workspace.session()["presses"]] == ["sad"]


def test_the_preview_says_what_is_heard_while_it_plays(engine, tmp_path):
    script = 'happy\nwait 1s\ntogether {\n  say "Hello there."\n  say "Yes." voice en-gb\n}'
    (tmp_path / "show.face").write_text(script)
    now = [0.0]
    workspace = Workspace(tmp_path / "show.face", seed=3, idle=False, clock=lambda: now[0])
    preview = workspace.preview
    assert preview.sounds(0.0) == []  # not playing
    preview.play(0.0)
    start = preview.animation.timeline.speech[0].at  # after happy's crossfade and the wait
    assert preview.sounds(start - 0.01) == []
    hello, yes = preview.sounds(start + 0.1)
    assert hello["at"] == yes["at"] == round(start, 3) and hello["key"] != yes["key"]
    assert preview.utterance(hello["key"]).text == "Hello there."
    assert preview.utterance(yes["key"]).voice == "en-gb"
    preview.pause(start + 0.2)
    assert preview.sounds(start + 0.3) == []  # paused: silent
    now[0] = 5.0
    workspace.press('say "Yes." voice en-gb')  # takes over where the preview stood: the same sound
    assert preview.sounds(5.01) == [{"key": yes["key"], "at": round(start + 0.2, 3)}]
    assert preview.sounds(9.0) == []  # said
    assert preview.utterance("0123456789abcdef") is None


def test_the_mood_pad_and_the_slider_are_offered_what_the_language_takes(tmp_path):
    """The page's mood pad and intensity slider: their emotions and circle come from the tables,
    and what they send is a press like any other, logged as the line it was."""
    from baxterface_cli.core.face_constants import EMOTIONS
    from baxterface_cli.studio.page_tables import feelings
    from baxterface_cli.studio.workspace import Workspace

    offered = feelings()
    assert offered["emotions"][0] == "happy" and "wake_up" in offered["emotions"]
    assert "default" not in offered["emotions"]  # at any intensity, the neutral face
    for word in offered["emotions"]:
        parse(f"{word} 0.4 in 0.2s", "slider")
    assert {m["emotion"] for m in offered["mood_circle"]} <= set(EMOTIONS)
    (tmp_path / "show.face").write_text("happy\n")
    workspace = Workspace(tmp_path / "show.face", idle=False)
    assert workspace.state()["feelings"] == offered
    workspace.press("mood 0.6 -0.2 in 0.2s")
    workspace.press("sad 0.4 in 0.2s")
    assert [p["command"] for p in workspace.session()["presses"]] == [
        "mood 0.6 -0.2 in 0.2s",
        "sad 0.4 in 0.2s",
    ]
    for bad in ("mood 1.01 0 in 0.2s", "mood 0 -2 in 0.2s", "sad 1.5 in 0.2s"):
        with pytest.raises(ScriptError):
            workspace.press(bad)
    assert len(workspace.session()["presses"]) == 2


def test_the_default_panel_has_emotions_looks_actions_and_phrases():
    buttons = load_panel()
    groups = {b.group for b in buttons}
    assert groups == {"Emotions", "Looks", "Actions", "Say"}
    commands = {b.command for b in buttons}
    assert {"happy", "blink", "nod"} <= commands
    assert any(c.startswith("say ") for c in commands)
    keys = [b.key for b in buttons if b.key]
    assert len(keys) == len(set(keys))
    assert {"ArrowLeft", "1"} <= set(keys)  # key names and characters both load


def test_the_default_panels_head_shake_turns_both_ways_and_comes_back():
    shake = next(b for b in load_panel() if b.label == "Shake head")
    timeline = compile_script(parse(shake.command, "panel"), 1)
    pans = [timeline.sample(i / 50).head_pan for i in range(int(timeline.duration * 50) + 1)]
    assert max(pans) > 0.2 and min(pans) < -0.2
    assert timeline.sample(timeline.duration).head_pan == 0.0
    assert timeline.duration <= 1.5  # a shake, not a look around


def test_the_default_panels_comment_says_what_a_key_may_be():
    comment = json.loads(DEFAULT_PANEL.read_text())["_comment"]
    assert "single-character" not in comment and "ArrowLeft" in comment


@pytest.mark.parametrize(
    "buttons, message",
    [
        ([{"label": "Happy", "command": "hapy"}], "Happy"),
        (
            [{"label": "A", "command": "happy", "key": "a"}, {"label": "B", "command": "sad", "key": "a"}],
            "key 'a'",
        ),
        ([{"label": "A"}], "needs a command"),
        ("happy", 'a "buttons" list'),
        (
            [{"label": "Left", "command": "look left", "key": "Arrowleft"}],
            'key "Arrowleft" is not one character',
        ),
    ],
)
def test_a_bad_panel_is_refused_with_the_button_named(tmp_path, buttons, message):
    path = tmp_path / "panel.json"
    path.write_text(json.dumps({"buttons": buttons}))
    with pytest.raises(PanelError) as e:
        load_panel(path)
    assert str(e.value).startswith(str(path)) and message in str(e.value)


def test_the_default_panel_file_is_the_one_shipped():
    assert DEFAULT_PANEL.exists() and DEFAULT_PANEL.parent.name == "studio"


def test_check_text_says_what_check_says(tmp_path):
    script = tmp_path / "bad.face"
    script.write_text("happy\nmouth smil\nlook 200 0\nwiat 1s\n")
    done = subprocess.run([baxterface(), "check", str(script)], capture_output=True, text=True)
    heads = [line for line in done.stderr.splitlines() if line.startswith(str(script))]
    ours = [
        f"{script}:{d['line']}:{d['column']}: {d['severity']}: {d['message']}"
        for d in check_text(script.read_text(), str(script))
    ]
    assert ours == heads and len(heads) == 4  # wiat 1s: the unknown command and the 1s after it
    assert "unknown command 'wiat'; did you mean 'wait'?" in heads[2]


# -- a real server


@pytest.fixture()
def folder(tmp_path):
    (tmp_path / "show.face").write_text("happy\nlook left in 1s\nwait 1s\nsad\n")
    return tmp_path


def decoded(jpeg: bytes) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(jpeg)).convert("RGB"), dtype=np.int16)


def test_the_api_checks_plays_commands_and_shows_the_frame(folder):
    with running_studio(folder / "show.face", "--no-idle") as studio:
        status, answer = studio.json("POST", "/api/check", "happy\nmouth smil\n")
        assert status == 200
        assert answer == [
            {
                "line": 2,
                "column": 7,
                "severity": "error",
                "message": "unknown mouth 'smil'; did you mean 'smile'?",
            }
        ]
        status, answer = studio.json("GET", "/api/state")
        assert [s["text"] for s in answer["timeline"]["spans"]][:2] == [
            "happy",
            "look 65 0 in 1s",
        ]  # as explain says it
        before = decoded(studio.frame())
        status, answer = studio.json("POST", "/api/command", "look_60_0_0")
        assert status == 200 and answer["at"] == 0.0
        assert answer["session"]["presses"] == [{"at": 0.0, "command": "look_60_0_0"}]
        after = decoded(studio.frame())
        assert np.abs(after - before).mean() > 1.0  # the eyes moved
        status, answer = studio.json("POST", "/api/command", "look 40 -20 in 0.5s eas-in")
        assert status == 400
        assert answer["diagnostics"][0]["message"].startswith("unknown easing 'eas-in'")
        status, answer = studio.json("GET", "/api/state")
        assert answer["script"] == {
            "name": "show.face",
            "text": (folder / "show.face").read_text(),
            "saved": True,
            "version": 0,
        }
        # The press took the script over where the preview stood: the run shows it.
        assert "look 60 0 in 0s" in [s["text"] for s in answer["timeline"]["spans"]]
        assert "happy" in answer["vocabulary"]["emotions"] and "look" in answer["vocabulary"]["keywords"]


def test_the_sound_of_what_is_said_is_served_as_wav(folder, engine):
    import wave

    with running_studio(folder / "show.face", "--no-idle") as studio:
        said = "Hello there, this is the studio speaking."  # long enough to be heard when asked
        assert studio.json("POST", "/api/command", f'say "{said}"')[0] == 200
        _, state = studio.json("GET", "/api/state")
        (heard,) = state["status"]["sounds"]
        code, wav = studio.request("GET", f"/api/sound/{heard['key']}.wav")
        assert code == 200
        with wave.open(io.BytesIO(wav)) as w:
            samples = np.frombuffer(w.readframes(w.getnframes()), "<i2")
            rate = w.getframerate()
        utterance = engine.say(said)
        assert rate == utterance.sample_rate and np.array_equal(samples, utterance.samples)
        for key in ("0123456789abcdef", "..%2F..%2Fetc%2Fpasswd", "x" * 16):
            assert studio.request("GET", f"/api/sound/{key}.wav")[0] == 404


def test_saving_writes_the_script_whole_and_nothing_else(folder):
    with running_studio(folder / "show.face") as studio:
        status, answer = studio.json("POST", "/api/save", "sad\nwait 2s\n")
        assert status == 200 and answer == {"saved": True, "name": "show.face", "version": 1}
        assert (folder / "show.face").read_text() == "sad\nwait 2s\n"
        assert sorted(p.name for p in folder.iterdir() if not p.name.startswith(".studio-")) == ["show.face"]


def test_a_save_over_a_change_on_disk_is_refused_unless_forced(folder):
    script = folder / "show.face"
    with running_studio(script) as studio:
        assert studio.json("POST", "/api/save?base=0", "sad\n")[1]["version"] == 1
        script.write_text("angry\n")  # another editor saves: the page's version 1 is old now
        status, answer = studio.json("POST", "/api/save?base=1", "mine\n")
        assert status == 409 and answer["conflict"] and "changed on disk" in answer["error"]
        assert script.read_text() == "angry\n"  # untouched
        # Once the studio has seen the change, the page learns its version and can save over it.
        version = _version_once_seen(studio, "angry\n")
        assert studio.json("POST", f"/api/save?base={version}", "happy\n")[0] == 200
        script.write_text("bored\n")
        assert studio.json("POST", "/api/save?base=3", "happy\n")[0] == 409
        status, answer = studio.json("POST", "/api/save?force=1", "happy\n")
        assert status == 200 and script.read_text() == "happy\n"
        assert studio.json("POST", "/api/save?base=x1", "happy\n")[0] == 400


def _version_once_seen(studio, text, timeout=10.0):
    """The script's version once the studio has looked at the disk (every half second) and
    found `text` there. Not the first new version: a write that truncates, then writes, may be
    seen half done (an empty file), and counts as a version of its own."""
    import time

    deadline = time.monotonic() + timeout
    while True:
        script = studio.json("GET", "/api/state")[1]["script"]
        if script["text"] == text or time.monotonic() > deadline:
            return script["version"]
        time.sleep(0.05)


def test_a_new_script_is_made_on_first_save(tmp_path):
    with running_studio(tmp_path / "new.face") as studio:
        _, answer = studio.json("GET", "/api/state")
        assert answer["script"]["text"] == ""
        studio.json("POST", "/api/save", "happy\n")
    assert (tmp_path / "new.face").read_text() == "happy\n"


def test_the_session_exports_beside_the_script_and_replays(folder):
    with running_studio(folder / "show.face", "--no-idle") as studio:
        for command in ("happy", "look left in 0.3s", "blink"):
            assert studio.json("POST", "/api/command", command)[0] == 200
        status, answer = studio.json("POST", "/api/session/export")
        assert status == 200
    exported = folder / answer["path"]
    assert exported.parent == folder and exported.read_text() == answer["text"]
    done = subprocess.run([baxterface(), "explain", str(exported)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    said = [m.group(1) for m in re.finditer(r" line \d+ +(.*)", done.stdout)]
    # Back to back, each press took over from the one before, as on the robot: so the replay.
    pressed = [text.replace(" (stopped)", "") for text in said if not text.startswith("wait")]
    assert pressed[-3:] == ["happy", "look 65 0 in 0.3s", "blink"]


def test_the_studio_refuses_other_hosts_and_other_sites(folder):
    with running_studio(folder / "show.face") as studio:
        assert studio.request("GET", "/api/state", headers={"Host": "evil.example:80"})[0] == 403
        origin = {"Origin": "http://evil.example"}
        assert studio.request("POST", "/api/save", "x", headers=origin)[0] == 403
        assert (folder / "show.face").read_text().startswith("happy")
        same = {"Origin": studio.base}
        assert studio.request("POST", "/api/check", "happy", headers=same)[0] == 200
        # no route takes a path: a climb out of the static folder finds nothing
        for path in ("/static/../workspace.py", "/static/%2e%2e/workspace.py", "/static/..%2fworkspace.py"):
            assert studio.request("GET", path)[0] == 404


def test_every_file_the_page_names_is_served_under_static(folder):
    # The studio's own files and the sound player every face page shares (web/static) sit side by
    # side at /static, where the page has always asked for them.
    with running_studio(folder / "show.face") as studio:
        status, page = studio.request("GET", "/")
        named = re.findall(r'(?:src|href)="(/static/[^"]+)"', page.decode("utf-8"))
        assert status == 200 and {"/static/app.js", "/static/sound.js", "/static/studio.css"} <= set(named)
        assert {path: studio.request("GET", path)[0] for path in named} == {path: 200 for path in named}


def test_off_loopback_every_request_needs_the_token(folder):
    with running_studio(folder / "show.face", "--host", "0.0.0.0") as studio:
        assert studio.token and len(studio.token) >= 20
        assert not studio.base.startswith(("http://0.0.0.0", "http://127."))  # an address others can reach
        studio.base = "http://127.0.0.1:" + studio.base.rsplit(":", 1)[1]
        status, answer = studio.request("GET", "/api/state", headers={"X-Baxterface-Token": "wrong"})
        assert status == 403 and json.loads(answer)["error"].startswith("the token is wrong")
        status, answer = studio.request("GET", "/static/app.js", headers={"X-Baxterface-Token": ""})
        assert status == 403 and json.loads(answer)["error"].startswith("a token is needed")
        assert studio.request("GET", "/api/state")[0] == 200
        status, _ = studio.request("GET", f"/?token={studio.token}", headers={"X-Baxterface-Token": ""})
        assert status == 200


def test_bad_requests_are_answered_in_json_and_logged_in_one_line_each(folder):
    with running_studio(folder / "show.face") as studio:
        asked = [
            ("POST", "/api/command", "hapy", {}, 400, "unknown command 'hapy'"),
            ("GET", "/api/check", None, {}, 405, "GET is not taken here"),
            ("GET", "/api/nothing", None, {}, 404, "nothing is here"),
            ("POST", "/api/transport", {"action": "seek", "t": "x"}, {}, 400, "'seek' needs 't'"),
            ("POST", "/api/transport", {"action": "seek"}, {}, 400, "'seek' needs 't'"),
            ("POST", "/api/transport", {}, {}, 400, "'action' must be one of play, pause, seek, loop"),
            ("POST", "/api/transport", {"action": "loop", "on": "yes"}, {}, 400, "'loop' needs 'on'"),
            ("GET", "/api/state", None, {"Host": "evil.example"}, 403, "loopback only"),
            ("POST", "/api/command", "x" * 200_000, {}, 400, "unknown command 'xxxxxxxxxx"),
        ]
        for method, path, body, headers, code, why in asked:
            status, answer = studio.request(method, path, body, headers)
            assert status == code, (path, answer)
            said = json.loads(answer)
            assert why in (said["diagnostics"][0]["message"] if "diagnostics" in said else said["error"])
        assert studio.json("POST", "/api/transport", {"action": "seek", "t": 0.5})[0] == 200  # still serving
        logged = [line for line in studio.log() if not line.startswith("baxterface studio: http")]
    assert len(logged) == len(asked)
    for line, (method, path, _, _, code, why) in zip(logged, asked):
        assert line.startswith(f"baxterface studio: {method} {path}: {code} ") and why in line
        assert len(line) < 400  # a huge bad command is not written to the log whole


def test_sigterm_stops_the_studio_as_ctrl_c_does_and_says_what_was_not_saved(folder):
    with running_studio(folder / "show.face") as studio:
        assert studio.json("POST", "/api/script", "sad\n")[0] == 200  # typed, not saved
        studio.process.send_signal(signal.SIGTERM)
        assert studio.process.wait(timeout=30) == 128 + signal.SIGTERM
        assert (
            studio.log()[-1]
            == "baxterface studio: stopped; the editor's last changes to show.face were not saved"
        )
    assert (folder / "show.face").read_text().startswith("happy")


def test_a_missing_extra_gives_one_line(tmp_path):
    code = (
        "import sys; sys.modules['starlette'] = None; from baxterface_cli.cli import main; main(['studio'])"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode == 1
    assert done.stderr.strip().splitlines() == [
        "baxterface studio: the studio needs the 'starlette' module: pip install 'baxterface[studio]'"
    ]


def test_a_taken_port_gives_one_line(folder):
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        done = subprocess.run(
            [baxterface(), "studio", str(folder / "show.face"), "--no-browser", "--port", str(port)],
            capture_output=True,
            text=True,
            timeout=60,
        )
    assert done.returncode == 1
    assert done.stderr.strip().splitlines() == [
        f"baxterface studio: cannot serve on 127.0.0.1:{port}: Address already in use"
    ]


def test_a_bad_panel_stops_the_studio_with_one_line(folder):
    panel = folder / "panel.json"
    panel.write_text('{"buttons": [{"label": "Hi", "command": "say \\"hi"}]}')
    done = subprocess.run(
        [baxterface(), "studio", str(folder / "show.face"), "--no-browser", "--buttons", str(panel)],
        capture_output=True,
        text=True,
        timeout=60,
        env=dict(os.environ),
    )
    assert done.returncode == 1
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(
        f"baxterface studio: {panel} (button 'Hi'):1:5: error: unterminated string"
    )


def test_the_docs_show_the_session_export_as_written(tmp_path):
    (tmp_path / "show.face").write_text("sad\nwait 3s\n")
    now = [10.0]
    workspace = Workspace(tmp_path / "show.face", seed=1234, idle=False, clock=lambda: now[0])
    workspace.transport("seek", 1.5)
    workspace.press("look left in 2s")
    now[0] += 0.5
    workspace.press("sad")
    doc = (REPO / "docs" / "studio.md").read_text(encoding="utf-8")
    shown = doc.split('```json\n{"type": "start"')[1].split("```")[0]
    assert '{"type": "start"' + shown == workspace.export_session()["text"]


def test_scripts_are_parsed_one_at_a_time_and_a_long_queue_is_refused():
    import asyncio
    import threading

    from baxterface_cli.web.face_api import HEAVY_WAITING, Busy, Heavy

    heavy, release = Heavy(), threading.Event()
    running, most = [0], [0]

    def work(n):
        running[0] += 1
        most[0] = max(most[0], running[0])
        release.wait(30)
        running[0] -= 1
        return n

    async def flood():
        jobs = [asyncio.ensure_future(heavy.run(work, n)) for n in range(HEAVY_WAITING)]
        while heavy.waiting < HEAVY_WAITING:
            await asyncio.sleep(0.01)
        with pytest.raises(Busy, match="busy: 16 scripts are waiting"):
            await heavy.run(work, -1)
        release.set()
        return await asyncio.gather(*jobs)

    assert asyncio.run(flood()) == list(range(HEAVY_WAITING))
    assert most[0] == 1  # never two at once: each holds the GIL the frame pump needs


def test_the_studio_says_recordings_from_its_scripts_folder_and_nowhere_else(tmp_path, engine):
    """The editor and the presses say a recording beside the script; one outside is an error there."""
    pytest.importorskip("av")
    import wave

    from baxterface_cli.speech.soundtrack import write_wav
    from baxterface_cli.studio.workspace import Workspace

    said = engine.say("Welcome to the lab.")
    (tmp_path / "studio").mkdir()
    write_wav(str(tmp_path / "studio" / "welcome.wav"), said.samples, said.sample_rate)
    write_wav(str(tmp_path / "outside.wav"), said.samples, said.sample_rate)
    workspace = Workspace(tmp_path / "studio" / "show.face", idle=False)
    checked = workspace.update('happy\nsay file "welcome.wav" language fr\n')
    assert checked["diagnostics"] == []
    (key,) = checked["timeline"]["sounds"]
    with wave.open(io.BytesIO(workspace.sound(key))) as w:
        assert np.array_equal(np.frombuffer(w.readframes(w.getnframes()), "<i2"), said.samples)
    checked = workspace.update('happy\nsay file "../outside.wav" language fr\nsay file "gone.wav"\n')
    assert [(d["line"], d["column"], d["severity"]) for d in checked["diagnostics"]] == [
        (2, 10, "error"),
        (3, 10, "error"),
    ]
    assert "is outside" in checked["diagnostics"][0]["message"]
    assert checked["diagnostics"][1]["message"] == "cannot read recording 'gone.wav': no such file"
    workspace.press('say file "welcome.wav" language fr')
    with pytest.raises(ScriptError, match="outside"):
        workspace.press(f'say file "{tmp_path / "outside.wav"}" language fr')
    assert [p["command"] for p in workspace.session()["presses"]] == ['say file "welcome.wav" language fr']


def test_without_pocketsphinx_the_editor_says_the_mouth_follows_the_sound(tmp_path, engine, monkeypatch):
    pytest.importorskip("av")
    from baxterface_cli.speech import phones_heard
    from baxterface_cli.speech.soundtrack import write_wav
    from baxterface_cli.studio.workspace import Workspace

    said = engine.say("Welcome.")
    write_wav(str(tmp_path / "welcome.wav"), said.samples, said.sample_rate)
    monkeypatch.setattr(phones_heard, "available", lambda: False)
    workspace = Workspace(tmp_path / "show.face", idle=False)
    (note,) = workspace.update('say file "welcome.wav"\n')["diagnostics"]
    assert note["severity"] == "warning" and "pip install 'baxterface[lipsync]'" in note["message"]
    assert workspace.update('say file "welcome.wav" language fr\n')["diagnostics"] == []
