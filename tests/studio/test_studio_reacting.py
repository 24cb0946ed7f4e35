"""The studio's run over events fired by hand, continued rather than run again at each event, and
presses in its panel that react, taken as the face node takes them: on a real studio over
loopback, its export rendered by the real `baxterface render --events`, frame for frame."""

from __future__ import annotations

import io
import random

import numpy as np
from PIL import Image

from baxterface_cli.engine.animation import Animation
from baxterface_cli.engine.session_run import NeverRests, run_over
from baxterface_cli.language.event_line import read_event_line
from baxterface_cli.language.event_trace import Trace, read_trace
from baxterface_cli.language.parser import parse
from baxterface_cli.studio import reacting
from baxterface_cli.studio import workspace as workspace_module
from baxterface_cli.studio.event_run import WINDOW
from baxterface_cli.studio.workspace import Workspace
from conftest import baxterface as run_baxterface
from studio_server import running_studio

GREETER = (
    "sad\non signal poke {\n  happy\n  look left in 0.3s\n  wait 0.5s\n}\n"
    'on touch left eye queue {\n  angry\n  say "ow"\n  wait 0.2s\n}\n'
    "on button ok interrupt cooldown 1s {\n  nod\n  wink right\n}\n"
    "forever {\n  blink\n  wait 2s\n}\n"
)


class Clock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def rendered(script, events, seed, idle):
    """What `render --events` makes of them, as an animation (engine/session_run.py, as the CLI)."""
    trace = Trace(tuple(events), "e")
    try:
        run = run_over(script, trace, seed)
    except NeverRests:
        run = run_over(script, trace, seed, trace.end + WINDOW)
    return Animation(run.timeline, idle, seed), run


def test_hundreds_of_events_fired_and_some_sought_back_play_as_render_plays_them(tmp_path, monkeypatch):
    path = tmp_path / "greeter.face"
    path.write_text(GREETER)
    clock = Clock()
    workspace = Workspace(path, seed=3, idle=True, clock=clock)
    lines = [read_event_line(x) for x in ("signal poke", "touch left eye", "button ok")]
    rng = random.Random(5)
    for i in range(240):  # more than the 200 a session used to hold, and past chapters of 64
        if i % 25 == 24:  # seek back among the events fired before, and fire there
            workspace.transport("seek", rng.uniform(0, workspace.status(workspace.clock())["t"]))
        clock.now += rng.uniform(0.0, 1.2)
        workspace.event(lines[rng.randrange(3)])
    whole = workspace.timeline()["spans"]
    monkeypatch.setattr(workspace_module, "SHOWN_SPANS", 40)
    shown = workspace.timeline()  # the page lists the spans around the position, not the whole run
    assert len(shown["spans"]) == 40 < len(whole) and shown["spans_before"] > 0
    assert whole[shown["spans_before"] : shown["spans_before"] + 40] == shown["spans"]
    assert shown["spans"][0]["start"] <= workspace.status(workspace.clock())["t"] <= shown["spans"][-1]["end"]
    preview = workspace.preview
    expected, run = rendered(parse(GREETER, "greeter.face"), preview.inputs, 3, idle=True)
    assert preview.duration == expected.duration
    assert preview.counts == {
        key: sum(c[key] for c in run.session.counts().values()) for key in ("runs", "dropped", "queued")
    }
    for _ in range(3000):
        t = rng.uniform(0, expected.duration)
        assert preview.animation.sample(t) == expected.sample(t), t
        assert preview.animation.timeline.status(t) == expected.timeline.status(t), t
        assert preview.animation.timeline.sounding(t) == expected.timeline.sounding(t), t


def test_past_the_events_a_session_holds_firing_is_refused_with_the_reason(tmp_path, monkeypatch):
    path = tmp_path / "greeter.face"
    path.write_text(GREETER)
    clock = Clock()
    workspace = Workspace(path, seed=3, idle=False, clock=clock)
    assert reacting.MOST_EVENTS >= 10_000  # a bound for memory: 200 was one for time
    monkeypatch.setattr(reacting, "MOST_EVENTS", 3)
    for _ in range(3):
        clock.now += 0.5
        workspace.event(read_event_line("signal poke"))
    try:
        workspace.event(read_event_line("signal poke"))
    except reacting.TooManyEvents as e:
        assert "holds 3 events" in str(e) and "export it and clear it" in str(e)
    else:
        raise AssertionError("a fourth event was taken")
    assert workspace.timeline()["fired"] == 3


def preview_frame(studio, t):
    """The studio's preview at `t`, paused there, as its page gets it."""
    # Paused first: a fired event plays on from where it was fired, and a seek keeps playing, so
    # the frame would be some way past `t`, as far as a busy machine is slow to answer.
    assert studio.json("POST", "/api/transport", {"action": "pause"})[0] == 200
    status, shown = studio.json("POST", "/api/transport", {"action": "seek", "t": t})
    assert status == 200 and not shown["playing"] and shown["t"] == t, shown
    return np.asarray(Image.open(io.BytesIO(studio.frame())).convert("RGB"), dtype=np.int16)


def test_what_was_fired_and_pressed_exports_and_the_real_render_shows_the_preview(tmp_path):
    script = tmp_path / "greeter.face"
    script.write_text(GREETER)
    with running_studio(script, "--no-idle") as studio:
        assert studio.json("POST", "/api/transport", {"action": "pause"})[0] == 200
        for t, line in ((0.5, "signal poke"), (2.0, "button ok"), (1.0, "touch left eye")):
            assert studio.json("POST", "/api/transport", {"action": "seek", "t": t})[0] == 200
            status, answer = studio.json("POST", "/api/event", line)
            assert status == 200 and answer["at"] == t, answer
            assert studio.json("POST", "/api/transport", {"action": "pause"})[0] == 200
        # A handler pressed in the panel replaces the script's own, as the node's does.
        status, answer = studio.json(
            "POST", "/api/command", "on button ok interrupt {\n  confused\n  wink left\n}"
        )
        assert status == 200 and answer["replaced"] == ["button ok: its handler replaced"], answer
        assert studio.json("POST", "/api/transport", {"action": "seek", "t": 4.0})[0] == 200
        status, answer = studio.json("POST", "/api/command", "signal poke")
        assert status == 200 and answer["fired"][0]["event"] == "signal poke", answer
        times = (0.3, 1.1, 2.2, 2.6, 4.2, 4.9)
        frames = {}
        for t in times:
            frames[t] = preview_frame(studio, t)
        status, exported = studio.json("POST", "/api/session/export")
        assert status == 200, exported
    face, events = tmp_path / exported["script_path"], tmp_path / exported["events_path"]
    assert "on button ok interrupt {\n  confused" in face.read_text()
    lines = events.read_text().splitlines()
    assert [line.split(" ", 1)[1] for line in lines] == [
        "signal poke",
        "touch left eye",
        "button ok",
        "signal poke",
    ]
    unlike = []
    for t in times:
        png = tmp_path / f"at-{t}.png"
        args = ["--events", events.name, "--seed", "7", "--at", str(t), "--size", "512x300", "-q"]
        done = run_baxterface("render", face.name, *args, "--out", png.name, cwd=tmp_path)
        assert done.code == 0, done.err
        frame = np.asarray(Image.open(png).convert("RGB"), dtype=np.int16)
        assert frame.shape == frames[t].shape
        assert np.abs(frame - frames[t]).mean() < 2.0, t  # the page's frame is a JPEG of it
        unlike.append(np.abs(frame - frames[times[0]]).mean())
    assert max(unlike) > 5.0  # the frames compared do differ from one another: happy, confused, angry
    # And the state behind them, exactly: the export run by the engine `render` runs.
    expected, _ = rendered(parse(face.read_text(), face.name), read_trace(events).events, 7, idle=False)
    assert [expected.sample(t).emotion for t in (0.3, 1.1, 2.2, 4.2)] == ["sad", "happy", "confused", "happy"]


def test_presses_that_react_in_the_panel(tmp_path):
    script = tmp_path / "show.face"
    script.write_text("happy\n")
    with running_studio(script, "--no-idle") as studio:
        status, answer = studio.json("POST", "/api/command", "on signal poke {\n  sad\n}")
        assert status == 200 and answer["installed"] == ["signal poke"] and answer["replaced"] == [], answer
        state = studio.json("GET", "/api/state")[1]
        assert state["timeline"]["listens"] == ["signal poke"]  # the events bar offers it
        status, answer = studio.json("POST", "/api/command", "signal poke")
        assert status == 200 and answer["fired"][0]["runs"] == 1, answer
        assert studio.json("GET", "/api/state")[1]["status"]["face"]["emotion"] == "sad"
        # Anything else takes the run over where the preview is, as a command takes the node over.
        status, answer = studio.json("POST", "/api/command", "forever {\n  blink\n}")
        assert status == 200 and "at" in answer and answer["session"]["count"] == 1, answer
        status, answer = studio.json("POST", "/api/command", "on signal wave {\n  nod\n}\nangry")
        assert status == 400 and answer["diagnostics"][0]["line"] == 1, answer
        assert "press a handler alone" in answer["diagnostics"][0]["message"], answer
        status, answer = studio.json("POST", "/api/command", "define later {\n  wait until signal go\n}")
        assert status == 400 and "definition alone" in answer["diagnostics"][0]["message"], answer
        status, answer = studio.json("POST", "/api/command", "on signal poke { angry")
        assert status == 400 and answer["diagnostics"][0]["line"] == 1, answer
        # A press that defines what the editor then defines too: said, not placed in the editor's text.
        press = "define cheer {\n  happy\n}\non signal wave {\n  cheer\n}"
        assert studio.json("POST", "/api/command", press)[0] == 200
        status, answer = studio.json("POST", "/api/script", "define cheer {\n  sad\n}\nhappy\n")
        first = answer["diagnostics"][0]
        assert first["line"] == 0 and "pressed in the panel does not fit" in first["message"], answer
        # Clear drops what was pressed with the events.
        assert studio.json("POST", "/api/session/clear")[0] == 200
        assert studio.json("GET", "/api/state")[1]["timeline"]["listens"] == []


def test_a_tap_on_the_preview_raises_touch_with_the_place_it_landed_on(tmp_path):
    script = tmp_path / "show.face"
    script.write_text("on touch left eye {\n  wink left\n}\non touch mouth {\n  happy\n}\n")
    with running_studio(script, "--no-idle") as studio:
        # The robot's left eye is on the screen's right; the mouth below the middle.
        status, answer = studio.json("POST", "/api/touch", {"x": 0.7, "y": 0.4})
        assert status == 200 and answer["event"] == "touch left eye" and answer["runs"] == 1, answer
        assert studio.json("POST", "/api/touch", {"x": 0.02, "y": 0.97})[1]["event"] == "touch"
        status, answer = studio.json("POST", "/api/touch", {"x": "left"})
        assert status == 400 and "x and y" in answer["error"], answer
        assert studio.json("GET", "/api/state")[1]["timeline"]["fired"] == 2
