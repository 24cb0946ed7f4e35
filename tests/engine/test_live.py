"""The face a live session plays on: a command takes over from the face as it is (as the screen's
do), actions fall due once."""

from __future__ import annotations

import pytest

from baxterface_cli import ScriptError
from baxterface_cli.engine import effects as fx
from baxterface_cli.engine.live_face import sleep_face
from live_commands import SessionFace, command


def test_it_starts_asleep_and_a_command_takes_over_from_where_the_face_is():
    live = SessionFace(start=sleep_face(), idle=False, seed=1)
    assert live.state(0.0).eyelids == 0.0
    command(live, "look 40 0 in 1s", now=10.0)
    command(live, "look 0 0 in 1s", now=10.5)  # halfway through the first
    assert live.state(10.5).eye_x == pytest.approx(20)
    assert live.state(11.0).eye_x == pytest.approx(10)
    assert live.state(11.5).eye_x == pytest.approx(0)


def test_actions_are_handed_out_once_when_due():
    live = SessionFace(idle=False, seed=1)
    command(live, "wait 1s; enable; follow human; wobble 0.3", now=0.0)
    assert live.due(0.5) == []
    effects = [c.effect for c in live.due(1.0)]
    assert effects[:2] == [fx.SetEnabled(True), fx.SetFollowing("human")]
    assert isinstance(effects[2], fx.HeadPan) and effects[2].target == pytest.approx(0.3)
    assert live.due(2.0) == []
    assert (live.robot.following, live.robot.follow_dynamic) == ("human", False)


def test_a_new_command_drops_the_old_ones_pending_actions():
    live = SessionFace(idle=False, seed=1)
    command(live, "wait 5s; wobble 1", now=0.0)
    command(live, "happy", now=1.0)
    assert not any(isinstance(c.effect, fx.HeadPan) for c in live.due(10.0))


def test_bad_commands_raise_and_change_nothing():
    live = SessionFace(idle=False, seed=1)
    command(live, "look 40 0 in 0s", now=0.0)
    with pytest.raises(ScriptError):
        command(live, "look_a_b", now=1.0)
    assert live.state(2.0).eye_x == pytest.approx(40)


def test_idle_blinks_go_on_long_after_the_last_command():
    live = SessionFace(idle=True, seed=2)
    command(live, "default", now=0.0)
    closed = [t / 10 for t in range(0, 6000) if live.state(t / 10).eyelids < 0.05]
    assert closed and max(closed) > 500  # still blinking ten minutes on


def test_exit_marks_the_face_as_finished_on_the_sleep_face():
    live = SessionFace(idle=False, seed=1)
    command(live, "happy; exit", now=0.0)
    happy = live.timeline.duration
    assert not live.exited and live.due(happy - 0.01) == []
    assert [c.effect for c in live.due(happy + 5)] == [fx.ShutDown()] and live.exited
    assert live.session.exited_at >= happy and live.state(happy + 5).skin == sleep_face().skin


def test_the_emotion_is_the_one_the_face_shows_now_not_the_scripts_last():
    live = SessionFace(start=sleep_face(), idle=False, seed=1)
    assert live.state(0.0).emotion == "sleep"
    command(live, "happy; wait 6; sad; wait 6; angry", now=10.0)
    assert live.state(12.0).emotion == "happy"
    assert live.state(18.0).emotion == "sad"
    assert live.state(25.0).emotion == "angry"
    command(live, "look left", now=30.0)  # a script with no emotion keeps the face's
    assert live.state(31.0).emotion == "angry"
