"""The screen's face without the web: a script first, from the first page; then commands take over."""

from __future__ import annotations

import io
import wave

import numpy as np
import pytest

from baxterface_cli.core.face_state import FaceState
from baxterface_cli.language.diagnostics import ScriptError
from baxterface_cli.language.parser import parse
from baxterface_cli.screen.screen_face import ScreenFace
from tests.support.waiting import caught_up


class Clock:
    def __init__(self, now: float = 100.0) -> None:
        self.now = now

    def __call__(self) -> float:
        return self.now


def passing(face: ScreenFace, clock: Clock, seconds: float) -> None:
    """`seconds` pass on the screen's clock: the session's worker begins the steps due by then."""
    clock.now += seconds
    caught_up(face.intake, clock.now)


def test_the_script_waits_for_the_first_page_then_plays_from_its_start():
    clock = Clock()
    face = ScreenFace(parse("sad\nlook left in 1s", "first.face"), seed=1, idle=False, clock=clock)
    clock.now += 30  # nobody watching yet: the script waits
    waiting = face.face(clock.now)
    assert (waiting.emotion, waiting.eye_x, waiting.skin) == (None, 0, FaceState().skin)
    assert face.state()["waiting"]
    face.open()
    assert not face.state()["waiting"]
    passing(face, clock, 0.3)  # sad takes 0.3 s
    assert face.face(clock.now).emotion == "sad" and face.face(clock.now).eye_x == pytest.approx(0, abs=1e-6)
    passing(face, clock, 0.5)
    halfway = face.face(clock.now).eye_x
    passing(face, clock, 1.0)
    assert halfway > 0 and face.face(clock.now).eye_x > halfway  # looking left (+x), further than halfway
    face.open()  # a second page joins the face as it is: nothing starts again
    assert face.face(clock.now).eye_x > halfway and face.state()["t"] == pytest.approx(31.8)


def test_a_command_takes_over_from_the_face_as_it_is_and_the_script_never_comes():
    clock = Clock()
    face = ScreenFace(parse("sad", "first.face"), seed=1, idle=False, clock=clock)
    assert face.command("look left in 1s") == {"installed": [], "handlers": 0}
    assert face.state()["playing"]
    passing(face, clock, 0.5)
    where = face.face(clock.now).eye_x
    assert where > 0  # on the way left
    face.command("look right in 1s")
    assert face.face(clock.now).eye_x == pytest.approx(where)  # from where the eyes had got to
    passing(face, clock, 1.0)
    assert face.face(clock.now).eye_x < 0 and not face.state()["playing"]
    face.open()  # the command came first: the script is dropped, as a take-over drops what plays
    passing(face, clock, 1.0)
    assert face.face(clock.now).emotion != "sad" and not face.state()["waiting"]


def test_a_bad_command_says_where_and_changes_nothing():
    clock = Clock()
    face = ScreenFace(seed=1, idle=False, clock=clock)
    face.command("happy")
    passing(face, clock, 1)
    before = face.face(clock.now)
    with pytest.raises(ScriptError) as e:
        face.command("look 40 -20 in 0.5s eas-in")
    assert e.value.diagnostics[0].message.startswith("unknown easing 'eas-in'")
    assert (e.value.diagnostics[0].line, e.value.diagnostics[0].column) == (1, 21)
    passing(face, clock, 1)
    assert face.face(clock.now) == before


def test_idle_life_goes_on_between_commands():
    clock = Clock()
    face = ScreenFace(seed=3, idle=True, clock=clock)
    face.command("happy")
    lids = []
    for _ in range(30 * 20):  # 20 s at 30 fps: blinks come every 3 to 8 s
        clock.now += 1 / 30
        lids.append(face.face(clock.now).eyelids)
    assert min(lids) < 0.2 and lids[-1] == 1.0


def test_what_is_said_is_listed_while_it_is_heard_and_its_sound_is_served(engine):
    clock = Clock()
    face = ScreenFace(seed=1, idle=False, clock=clock)
    said = "Hello from the screen."
    face.command(f'happy\nsay "{said}"')
    passing(face, clock, 0.4)  # the say begins as happy ends, at 0.3 s
    (heard,) = face.status(clock.now)["sounds"]
    assert heard["at"] == pytest.approx(0.3) and face.status(clock.now)["t"] == pytest.approx(0.4)
    assert face.state()["saying"] == said
    with wave.open(io.BytesIO(face.sound(heard["key"]))) as w:
        samples = np.frombuffer(w.readframes(w.getnframes()), "<i2")
    assert np.array_equal(samples, engine.say(said).samples)
    passing(face, clock, engine.say(said).duration)
    assert face.status(clock.now)["sounds"] == [] and face.state()["saying"] is None
    assert not face.state()["playing"]
    assert face.sound("0123456789abcdef") is None


def test_reading_the_face_moves_no_clock_and_takes_no_cue_and_a_step_does():
    clock = Clock()
    face = ScreenFace(seed=1, idle=True, clock=clock)
    face.command("follow face")  # a cue for the robot, handed out at its time
    clock.now += 0.5
    session_clock = face.session.clock
    shown = [face.face(clock.now) for _ in range(3)]
    assert shown[0] == shown[1] == shown[2]  # one time, one face, however often it is read
    assert face.session.clock == session_clock and face.live.robot.following is None  # nothing moved
    face.step(clock.now)
    assert face.session.clock == clock.now and face.live.robot.following == "face"  # the cue taken
