"""`play` live: clicks in its window are touches (with their place), words heard are words, and
the script's handlers run on the live session as they come."""

from __future__ import annotations

import subprocess

import numpy as np
import pytest

from baxterface_cli import parse
from baxterface_cli.drawing.renderer import Renderer
from baxterface_cli.drawing.theme import Theme
from baxterface_cli.engine.live_session import LiveSession
from baxterface_cli.play.live_player import LivePlayer
from conftest import baxterface
from playing import FakeClock


class ClickingScreen:
    """A window that a test clicks on, at frame `at`, where it says; it closes after `frames`."""

    name = "fake"

    def __init__(self, frames: int, on_frame=None) -> None:
        self.frames, self.on_frame = frames, on_frame
        self.shown = []
        self.touch = None

    def on_click(self, touch) -> None:
        self.touch = touch

    def show(self, frame, status) -> None:
        self.shown.append(np.array(frame))
        if self.on_frame is not None:
            self.on_frame(len(self.shown), self)

    def alive(self) -> bool:
        return len(self.shown) < self.frames


def live(text: str, screen, **options) -> LivePlayer:
    clock = FakeClock()
    session = LiveSession(parse(text, "t.face"), seed=0, idle=False)
    renderer = Renderer(Theme.default().layers((256, 150)))
    return LivePlayer(session, renderer, screen, 30.0, clock=clock, sleep=clock.sleep, live=True, **options)


def logged(player: LivePlayer):
    return [line.text for line in player.session.log]


def test_a_click_on_the_robots_left_eye_runs_the_touch_left_eye_handler():
    def click(frame: int, screen) -> None:
        if frame == 5:
            screen.touch(0.7, 0.4)  # the robot's left eye is on the screen's right

    player = live(
        "on touch left eye { wink left }\non touch mouth { sad }\nforever { wait 1s }",
        ClickingScreen(40, click),
    )
    player.run()
    log = logged(player)
    assert "event touch left eye (window)" in log
    assert any("'on touch left eye' runs" in line for line in log)
    assert not any("'on touch mouth' runs" in line for line in log)
    assert not np.array_equal(player.screen.shown[5], player.screen.shown[12])  # the wink shows


def test_a_click_on_the_skin_is_a_touch_anywhere():
    def click(frame: int, screen) -> None:
        if frame == 3:
            screen.touch(0.02, 0.97)

    player = live(
        "on touch { happy }\non touch left eye { wink left }\nforever { wait 1s }", ClickingScreen(10, click)
    )
    player.run()
    log = logged(player)
    assert "event touch (window)" in log
    assert any("'on touch' runs" in line for line in log)


def test_a_word_heard_from_a_recording_runs_its_handler_in_time(tmp_path):
    ws = pytest.importorskip("baxterface_cli.speech.word_spotter")
    wav = tmp_path / "said.wav"
    subprocess.run(["espeak-ng", "-v", "en-us", "-w", str(wav), "look at that robot"], check=True)
    samples = np.concatenate(
        [np.zeros(8000, np.int16), ws.read_recording(str(wav)), np.zeros(16000, np.int16)]
    )
    block = ws.RATE // 30
    spotter = {}

    def microphone(frame: int, screen) -> None:  # a frame's worth of sound arrives with each frame
        piece = samples[(frame - 1) * block : frame * block]
        if len(piece):
            spotter["it"].feed(piece, end=frame / 30)

    player = live(
        'sleep\non word "robot" { wake up }\nforever { wait 1s }',
        ClickingScreen(len(samples) // block + 30, microphone),
    )
    spotter["it"] = ws.WordSpotter(["robot"], player.hear, speaking=player.speaking)
    player.run()
    log = logged(player)
    assert 'event word "robot" (microphone)' in log
    assert any("'on word \"robot\"' runs" in line for line in log)
    heard = spotter["it"].heard[0].at
    ran = next(line.at for line in player.session.log if "runs" in line.text)
    assert heard <= ran <= heard + 0.5  # posted at the next frame after the spotter told it


def test_the_face_is_speaking_while_its_say_plays():
    pytest.importorskip("baxterface_cli.speech.synthesis")
    seen = []

    def look(frame: int, screen) -> None:
        seen.append(player.speaking(frame / 30))

    player = live('say "hello there, robot"', ClickingScreen(30, look))
    player.run()
    assert any(seen) and not player.speaking(60.0)


def test_listen_without_a_word_to_hear_is_a_one_line_error():
    run = baxterface("play", "--terminal", "--listen", "-e", "on touch { happy }")
    assert run.code == 2
    assert run.err.strip().splitlines() == [
        "baxterface play: --listen: the script listens for no words ('on word \"hello\" { ... }')"
    ]


def test_barge_in_needs_listen():
    run = baxterface("play", "--terminal", "--barge-in", "-e", "happy")
    assert run.code == 2 and "--barge-in goes with --listen" in run.err


def test_a_live_play_with_a_log_keeps_its_script_events_lines_and_end(tmp_path):
    import json

    from baxterface_cli.engine.session_log_file import SessionLogFile
    from baxterface_cli.language.event_trace import parse_trace

    text = "on button ok { happy }\nforever { wait 1s }"
    path = tmp_path / "play.jsonl"
    record = SessionLogFile(str(path), 0.0, {"end": "play"})
    clock = FakeClock()
    session = LiveSession(None, seed=0, idle=False)
    record.watch(session.face)
    record.script(0.0, text, "t.face")
    session.run(parse(text, "t.face"), 0.0)
    renderer = Renderer(Theme.default().layers((256, 150)))
    trace = parse_trace("0.5 button ok", "t.events")
    player = LivePlayer(
        session,
        renderer,
        ClickingScreen(40),
        30.0,
        trace,
        clock=clock,
        sleep=clock.sleep,
        record=record,
        live=True,
    )
    player.run()
    record.close(player.position)
    got = [json.loads(line) for line in path.read_text().splitlines()]
    assert [r["type"] for r in got][:2] == ["start", "script"]
    (event,) = [r for r in got if r["type"] == "event"]
    assert event == {"type": "event", "t": 0.5, "event": "button ok", "source": "t.events:1"}
    assert [r["kind"] for r in got if r["type"] == "log"][:2] == ["event", "started"]
    assert got[-1] == {"type": "end", "t": round(player.position, 4)}
