"""`baxterface play`: in a terminal, in a window, and keeping time."""

from __future__ import annotations

import os
import random
import re
import shutil
import subprocess
import sys
import time
from typing import List

import numpy as np
import pexpect
import pytest

from baxterface_cli import parse
from baxterface_cli.drawing.renderer import Renderer
from baxterface_cli.drawing.theme import Theme
from baxterface_cli.engine.live_session import LiveSession
from baxterface_cli.play.live_player import LivePlayer
from baxterface_cli.play.screens import TerminalScreen
from baxterface_cli.speech.sound_device import START_AHEAD, SoundOut
from conftest import ROOT, baxterface
from playing import FakeClock, spawn_play

SCRIPT = "happy; look 40 -20 in 0.5s; wobble 0.3; enable; follow human dynamic; wait 0.3s"


def test_play_in_a_terminal_draws_truecolor_half_blocks_and_a_status_line():
    child = spawn_play("-e", SCRIPT)
    child.expect(pexpect.EOF)
    screen = child.before
    assert screen.count("\u2580") > 1000  # half-block cells
    assert "\x1b[38;2;" in screen and ";48;2;" in screen  # 24-bit colours, upper and lower pixel
    assert "head +0.30 rad" in screen and "enabled" in screen and "following human (dynamic)" in screen
    assert "(terminal)" in screen
    child.close()
    assert child.exitstatus == 0


def test_ctrl_c_says_how_far_it_got_and_exits_130():
    child = spawn_play("-e", "look left in 10s")
    child.expect(r"/10\.0s")  # the status line: it is playing
    time.sleep(0.5)
    child.sendintr()
    child.expect(pexpect.EOF)
    child.close()
    assert child.exitstatus == 130
    found = re.search(r"interrupted at (\d+\.\d\d) s of 10\.00 s of script, after ([\d.]+) s", child.before)
    assert found, child.before[-300:]
    reached, after = map(float, found.groups())
    assert 0.0 < reached < 10.0 and reached <= after  # part of the way, no further than time allowed


def test_the_terminal_picture_keeps_the_faces_shape():
    screen = TerminalScreen(columns=100, rows=32)
    width, height = screen.fit((1024, 600))
    assert width <= 100 and height // 2 <= 31
    assert abs(width / height - 1024 / 600) < 0.1


def test_play_watch_keeps_the_last_good_version_on_errors(tmp_path):
    script = tmp_path / "w.face"
    script.write_text("look left in 1s; look right in 1s\n", encoding="utf-8")
    child = spawn_play("--watch", "--loop", str(script))
    child.expect("2.0s")  # playing the 2 s script
    script.write_text("look left in 1s; mouth smil\n", encoding="utf-8")
    child.expect("kept the last good version: line 1: unknown mouth 'smil'", timeout=10)
    script.write_text("look up in 3s\n", encoding="utf-8")
    child.expect("/3.0s", timeout=10)  # the new version plays
    child.sendintr()
    child.expect(pexpect.EOF)
    child.close()


def test_play_watch_plays_each_version_of_a_script_that_reacts_over_its_events(tmp_path):
    script = tmp_path / "r.face"
    script.write_text("wait until button ok\nlook up in 2s\n", encoding="utf-8")
    events = tmp_path / "r.events"
    events.write_text("0.5 button ok\n", encoding="utf-8")
    child = spawn_play("--watch", "--events", str(events), str(script))
    child.expect("/2.5s")  # the look, after the event half a second in
    script.write_text("wait until button ok\nlook down in 4s\n", encoding="utf-8")
    child.expect("/4.5s", timeout=10)  # the new version, from its start, over the same events
    child.sendintr()
    child.expect(pexpect.EOF)
    child.close()
    assert child.exitstatus == 130


def test_play_watch_does_not_go_with_listening(tmp_path):
    (tmp_path / "s.face").write_text('on word "hello" { happy }\n', encoding="utf-8")
    for option in ("--listen", "--hear=said.wav"):
        run = baxterface("play", "--terminal", "--watch", option, "s.face", cwd=tmp_path)
        assert (
            run.code == 2 and run.err.strip() == "baxterface play: --watch goes without --hear and --listen"
        )


def test_no_display_and_no_terminal_says_to_render():
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    proc = subprocess.run(
        [sys.executable, "-m", "baxterface_cli", "play", "-e", "happy"],
        cwd=str(ROOT),
        capture_output=True,
        text=True,
        env=env,
        timeout=60,
    )
    assert proc.returncode == 1
    assert "no display and no terminal" in proc.stderr and "baxterface render" in proc.stderr


def free_display() -> int:
    for n in range(90, 140):
        if not os.path.exists(f"/tmp/.X11-unix/X{n}") and not os.path.exists(f"/tmp/.X{n}-lock"):
            return n
    raise RuntimeError("no free X display number")


@pytest.fixture
def xvfb():
    if shutil.which("Xvfb") is None:
        if os.environ.get("CI"):
            pytest.fail("Xvfb is missing: make test installs it")
        pytest.skip("Xvfb is not installed (make test installs it)")
    n = free_display()
    proc = subprocess.Popen(["Xvfb", f":{n}", "-screen", "0", "1280x800x24", "-nolisten", "tcp"])
    deadline = time.monotonic() + 20
    while not os.path.exists(f"/tmp/.X11-unix/X{n}"):
        assert proc.poll() is None and time.monotonic() < deadline, "Xvfb did not start"
        time.sleep(0.05)
    yield f":{n}"
    proc.terminate()
    proc.wait(timeout=10)


def test_play_in_a_window_under_xvfb(xvfb):
    env = dict(os.environ, DISPLAY=xvfb)
    proc = subprocess.run(
        [sys.executable, "-m", "baxterface_cli", "play", "--no-idle", "-e", "happy; look 40 -20 in 0.5s"],
        cwd=str(ROOT),
        capture_output=True,
        text=True,
        env=env,
        timeout=60,
    )
    assert proc.returncode == 0, proc.stderr
    assert "(window)" in proc.stderr
    # How many of its 30 frames a second a window shows depends on the machine; that it plays
    # the script whole, in at least its own time, showing its first frame and its last, does not.
    played = re.search(r"played ([0-9.]+) s of script in ([0-9.]+) s: (\d+) frames", proc.stderr)
    assert played, proc.stderr
    length, took, frames = float(played[1]), float(played[2]), int(played[3])
    assert length == pytest.approx(0.8)  # happy's lids (0.3 s), then the look (0.5 s)
    assert took >= length
    assert frames >= 2


class CostlyScreen:
    """A screen where showing a frame takes time (a slow terminal, say)."""

    name = "fake"

    def __init__(self, clock: FakeClock, cost) -> None:
        self.clock, self.cost, self.shown = clock, cost, []

    def show(self, frame, status) -> None:
        self.shown.append(status.split("/")[0].strip())
        self.clock.now += self.cost()

    def alive(self) -> bool:
        return True


def playing(text: str, screen, clock: FakeClock, **options) -> LivePlayer:
    """A player of `text` on `clock`, as `play` makes one: its session, and a fresh one each lap."""
    script = parse(text)

    def fresh() -> LiveSession:
        return LiveSession(script, seed=0, idle=False)

    renderer = Renderer(Theme.default().layers((64, 40)))
    return LivePlayer(fresh(), renderer, screen, 30, clock=clock, sleep=clock.sleep, fresh=fresh, **options)


def test_looping_a_script_that_takes_no_time_holds_it_without_spinning():
    clock = FakeClock()
    screen = CostlyScreen(clock, lambda: 0.0)
    screen.alive = lambda: len(screen.shown) < 90  # about three seconds, then the user closes it
    player = playing("enable", screen, clock)
    played = player.run(loop=True)
    assert player.length() == 0
    assert played == pytest.approx(3.0, abs=0.1)  # it slept between frames: one frame per 1/30 s


def test_looping_starts_the_script_again_at_its_end_from_its_first_face():
    clock = FakeClock()
    frames = []

    class Screen(CostlyScreen):
        def show(self, frame, status) -> None:
            frames.append(np.array(frame))
            super().show(frame, status)

    screen = Screen(clock, lambda: 0.0)
    screen.alive = lambda: len(screen.shown) < 50  # a lap is 0.8 s: 24 frames
    player = playing("happy; look 40 -20 in 0.5s", screen, clock)
    player.run(loop=True)
    # 24 frames, to 0.77 s (shown as 0.8): then the next lap's first, at its end.
    laps = [i for i in range(1, 50) if screen.shown[i] == "0.0" and screen.shown[i - 1] == "0.8"]
    assert laps == [24, 48] and clock.now - 100.0 == pytest.approx(50 / 30, abs=1 / 30)
    again = laps[0]
    assert np.array_equal(frames[again], frames[0])  # a fresh session: the first face, not the last
    assert not np.array_equal(frames[again - 1], frames[0])


REACTING = """\
happy; look 40 -20 in 0.5s; one of { wink left | nod | sad }
wait until button ok
repeat 3 { blink; look left in 0.3s; look right in 0.2s }
on touch { surprise; look up in 0.4s }
wobble 0.3
"""


@pytest.mark.parametrize("seed", [1, 3])
def test_play_shows_the_frames_render_makes_and_ends_where_its_run_does(seed):
    from baxterface_cli.engine.animation import Animation
    from baxterface_cli.engine.session_run import run_over
    from baxterface_cli.language.event_trace import parse_trace

    trace = parse_trace("1.2 button ok\n2.0 touch\n", "t.events")
    recorded = Animation(run_over(parse(REACTING), trace, seed).timeline, idle=False)
    clock, shown = FakeClock(), []

    class Screen:
        name = "fake"

        def show(self, frame, status) -> None:
            shown.append((player.position, np.array(frame)))

        def alive(self) -> bool:
            return True

    layers = Theme.default().layers((128, 75))
    session = LiveSession(parse(REACTING), seed=seed, idle=False)
    player = LivePlayer(session, Renderer(layers), Screen(), 30, trace, clock=clock, sleep=clock.sleep)
    player.run()
    assert player.position == pytest.approx(recorded.duration) and len(shown) > 100
    drawn = Renderer(layers)
    assert all(np.array_equal(frame, drawn.render(recorded.sample(t))) for t, frame in shown)


def test_a_forever_with_no_events_goes_round_until_the_screen_closes():
    clock = FakeClock()
    screen = CostlyScreen(clock, lambda: 0.0)
    screen.alive = lambda: len(screen.shown) < 150  # five seconds: two and a half rounds
    player = playing("forever { look left in 1s; look right in 1s }", screen, clock)
    assert player.run() == pytest.approx(5.0, abs=0.1)
    assert player.length() == pytest.approx(5.0)  # as far as it is known: its third round's first look


@pytest.mark.parametrize("cost", [0.002, 0.02, 0.07])
def test_playback_keeps_time_without_drift_dropping_frames_when_late(cost):
    clock = FakeClock()
    rng = random.Random(1)
    screen = CostlyScreen(clock, lambda: cost * rng.uniform(0.5, 1.5))
    player = playing("look 40 0 in 5s; look 0 0 in 5s", screen, clock)
    played = player.run()
    assert player.position == 10.0  # its last frame is its end
    assert abs(played - 10.0) <= 1 / 30 + 1.5 * cost  # the last frame's own cost may add
    if cost < 1 / 30:
        assert len(screen.shown) >= 300  # every frame shown
    else:
        assert len(screen.shown) < 300  # frames dropped, time kept


# -- speech: the sound on the picture's clock ---------------------------------


def fake_speak(text, voice, rate):
    from baxterface_cli.speech.synthesis import Utterance

    return Utterance(
        text, voice or "en", rate or 175, np.full(int(22050 * 0.4), 1000, np.int16), 22050, (), ()
    )


class FakeSound(SoundOut):
    """A device that notes when each sound would be heard."""

    available = True

    def __init__(self, clock: FakeClock, latency: float) -> None:
        self.clock, self.latency = clock, latency
        self.heard: List[float] = []  # when each sound's first sample would be heard
        self.cut: List[float] = []
        self.stops = 0

    def play(self, samples, rate, skip=0.0):
        self.heard.append(self.clock() + self.latency - skip)
        self.cut.append(max(0.0, skip))

    def stop(self):
        self.stops += 1


class SayingScreen(CostlyScreen):
    """Notes when the status line first says each thing."""

    def __init__(self, clock: FakeClock, cost) -> None:
        super().__init__(clock, cost)
        self.first_said: List[float] = []
        self.saying = ""

    def show(self, frame, status) -> None:
        found = re.search(r'saying "([^"]*)"', status)
        said = found.group(1) if found else ""
        if said and said != self.saying:
            self.first_said.append(self.clock.now)
        self.saying = said
        super().show(frame, status)


@pytest.fixture(autouse=True)
def fake_voice(monkeypatch):
    """Every `say` a 0.4 s utterance, made at once: the compiler's voice for these tests."""
    from baxterface_cli.engine import compiler

    monkeypatch.setattr(compiler, "engine_say", fake_speak)


def speaking_player(text, cost=0.002, latency=0.12, screen_class=SayingScreen):
    clock = FakeClock()
    screen = screen_class(clock, lambda: cost)
    sound = FakeSound(clock, latency)
    opened = []

    def open_sound():
        opened.append(clock.now)
        return sound

    player = playing(text, screen, clock, sound=open_sound, speaks="say" in text)
    return player, screen, sound, opened


@pytest.mark.parametrize("cost", [0.002, 0.05])
def test_each_utterance_is_heard_as_the_frame_that_starts_saying_it_is_shown(cost):
    player, screen, sound, opened = speaking_player('wait 0.5s; say "one"; wait 0.3s; say "two"', cost)
    begun = player.clock()
    player.run()
    assert opened == [begun]  # once, before the clock started
    assert len(sound.heard) == 2 and sound.cut == [0.0, 0.0]  # started ahead, so nothing is lost
    assert len(screen.first_said) == 2
    for heard, shown in zip(sound.heard, screen.first_said):
        assert 0.0 <= shown - heard <= 1 / 30 + 1.5 * cost  # the frame comes on its tick, after drawing
    # The picture waited out the device's latency (and a margin for its next block): script time 0
    # is heard that long after the start.
    assert sound.heard[0] == pytest.approx(begun + 0.12 + START_AHEAD + 0.5)
    assert sound.stops == 1  # at the start; the end lets the last words out


def test_an_utterance_started_late_skips_what_it_missed_and_keeps_to_the_script_clock():
    player, screen, sound, _ = speaking_player('wait 1s; say "one"')
    costs = iter([0.001] * 15 + [0.6])  # the frame at 0.5 s takes 0.6 s: the utterance is due meanwhile
    screen.cost = lambda: next(costs, 0.001)
    begun = player.clock()
    player.run()
    (cut,) = sound.cut
    assert cut == pytest.approx(0.5 + 0.6 - 1.0 + 0.12)  # how late, counting the device's latency
    assert sound.heard == [pytest.approx(begun + 0.12 + START_AHEAD + 1.0)]  # the rest where it belongs


def test_looping_says_it_again_each_time_round_and_stops_when_closed():
    player, screen, sound, _ = speaking_player('say "again"; wait 0.1s', cost=0.0)
    lead = 0.12 + START_AHEAD  # the session runs that far ahead of the picture, the next lap's too
    # Five laps: the sixth's session would start `lead` before the fifth's picture ends.
    screen.alive = lambda: screen.clock.now < 100.0 + 4 * 0.5 + 0.45
    player.run(loop=True)
    assert len(sound.heard) == 5 and sound.cut == [0.0] * 5  # each lap's words whole
    assert sound.heard[0] == pytest.approx(100.0 + lead)
    laps = np.diff(sound.heard)
    assert laps == pytest.approx([0.5] * 4)  # back to back, as the picture's laps
    assert sound.stops == 2  # at the start, and as the window closed: a lap does not cut the last


def test_a_script_that_says_nothing_opens_no_sound():
    player, _, sound, opened = speaking_player("look left in 0.3s")
    player.run()
    assert opened == [] and player.sound is None and sound.heard == []


def test_without_a_device_the_picture_keeps_its_own_time():
    player, screen, _, _ = speaking_player('say "hi"', cost=0.0)
    player.open_sound = SoundOut  # the silent one: no device
    begun = player.clock()
    played = player.run()
    assert player.lead == 0.0
    assert played == pytest.approx(0.4, abs=1 / 30)  # no lead for a latency there is not
    assert screen.first_said == [begun]


def test_a_reloaded_script_silences_the_old_one_and_speaks_from_its_start():
    player, screen, sound, _ = speaking_player('say "old"; wait 2s')
    fresh = LiveSession(parse('wait 0.1s; say "new"'), seed=0, idle=False)
    polls: List[float] = []

    def poll():
        polls.append(player.clock())
        return fresh if len(polls) == 10 else None

    player.run(poll=poll)
    assert sound.stops == 2  # the old words stop as the new script starts
    assert len(sound.heard) == 2
    assert sound.heard[-1] == pytest.approx(polls[9] + 0.12 + START_AHEAD + 0.1)  # from its own start
