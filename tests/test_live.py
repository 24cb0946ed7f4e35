"""The live face behind the node: commands take over or queue, actions fall due once."""

from __future__ import annotations

import pytest

from baxterface_cli import ScriptError
from baxterface_cli.live import LiveFace, sleep_face


def test_it_starts_asleep_and_a_command_takes_over_from_where_the_face_is():
    live = LiveFace(start=sleep_face(), idle=False, seed=1)
    assert live.state(0.0).eyelids == 0.0
    live.command("look 40 0 in 1s", now=10.0)
    live.command("look 0 0 in 1s", now=10.5)  # halfway through the first
    assert live.state(10.5).eye_x == pytest.approx(20)
    assert live.state(11.0).eye_x == pytest.approx(10)
    assert live.state(11.5).eye_x == pytest.approx(0)


def test_queued_scripts_wait_for_what_is_playing():
    live = LiveFace(idle=False, seed=1)
    live.command("look 40 0 in 1s", now=0.0)
    live.command("look -40 0 in 1s", now=0.2, queue=True)
    assert len(live.queue) == 1
    assert live.state(1.0).eye_x == pytest.approx(40)
    assert live.state(1.5).eye_x == pytest.approx(0)  # the queued one began at 1.0
    assert live.state(2.0).eye_x == pytest.approx(-40)


def test_actions_are_handed_out_once_when_due():
    live = LiveFace(idle=False, seed=1)
    live.command("wait 1s; enable; follow human; wobble 0.3", now=0.0)
    assert live.due(0.5) == []
    kinds = [a.kind for a in live.due(1.0)]
    assert kinds == ["enable", "follow", "head"]
    assert live.due(2.0) == []
    assert live.following == ("human", False)


def test_a_new_command_drops_the_old_ones_pending_actions():
    live = LiveFace(idle=False, seed=1)
    live.command("wait 5s; wobble 1", now=0.0)
    live.command("happy", now=1.0)
    assert all(a.kind != "head" for a in live.due(10.0))


def test_bad_commands_raise_and_change_nothing():
    live = LiveFace(idle=False, seed=1)
    live.command("look 40 0 in 0s", now=0.0)
    with pytest.raises(ScriptError):
        live.command("look_a_b", now=1.0)
    assert live.state(2.0).eye_x == pytest.approx(40)


def test_idle_blinks_go_on_long_after_the_last_command():
    live = LiveFace(idle=True, seed=2)
    live.command("default", now=0.0)
    closed = [t / 10 for t in range(0, 6000) if live.state(t / 10).eyelids < 0.05]
    assert closed and max(closed) > 500  # still blinking ten minutes on


def test_exit_marks_the_face_as_finished_on_the_sleep_face():
    live = LiveFace(idle=False, seed=1)
    live.command("happy; exit", now=0.0)
    end = live.timeline.duration
    assert not live.exited and live.due(end - 0.01) == []
    assert [a.kind for a in live.due(end)] == ["exit"] and live.exited
    assert live.state(end).skin == sleep_face().skin
