"""A command that takes over lets what the face already began finish: its state tells what it shows."""

from __future__ import annotations

import pytest

from baxterface_cli.core.face_constants import EMOTIONS
from baxterface_cli.core.presets import emotion_preset
from baxterface_cli.engine.live_session import LiveSession
from baxterface_cli.engine.session_intake import SessionIntake
from live_commands import SessionFace, command
from tests.support.waiting import eventually


@pytest.mark.parametrize("seed", range(4))
def test_a_wink_just_after_an_emotion_lets_the_face_become_that_emotion(seed):
    live = SessionFace(idle=False, seed=seed)
    command(live, "happy", now=0.0)
    command(live, "sad", now=2.0)
    command(live, "wink left", now=2.1)  # while sad's lids move, before its mouth changes
    shown = live.state(5.0)
    assert shown.emotion == "sad"
    assert shown.skin == EMOTIONS["sad"].skin
    assert (shown.mouth, shown.brows) in EMOTIONS["sad"].variants
    sad_mouths = {emotion_preset("sad", v).mouth_curve for v in range(len(EMOTIONS["sad"].variants))}
    assert shown.expression.mouth_curve in sad_mouths
    assert live.state(2.2).expression.lid_left < 0.5  # and the wink winks
    assert shown.expression.lid_left == 1.0


def test_a_wink_still_reopens_when_a_command_comes_while_it_is_shut():
    live = SessionFace(idle=False, seed=1)
    command(live, "wink right", now=0.0)
    command(live, "happy", now=0.2)
    assert live.state(0.25).expression.lid_right == 0.0
    assert live.state(2.0).expression.lid_right == 1.0


def test_a_morph_under_way_finishes_under_a_command_that_moves_other_numbers():
    live = SessionFace(idle=False, seed=1)
    command(live, "mouth curve -1 in 1s", now=0.0)
    command(live, "brows height 1 in 1s", now=0.5)
    later = live.state(3.0).expression
    assert later.mouth_curve == pytest.approx(-1.0)
    assert later.brow_left_height == pytest.approx(1.0)


def test_a_command_moving_the_same_number_takes_over_from_where_it_has_got_to():
    live = SessionFace(idle=False, seed=1)
    command(live, "mouth curve -1 in 1s", now=0.0)  # from the default's 1
    command(live, "mouth curve 1 in 1s", now=0.5)
    assert live.state(0.5).expression.mouth_curve == pytest.approx(0.0)
    assert live.state(3.0).expression.mouth_curve == pytest.approx(1.0)


def test_statements_not_yet_begun_are_dropped():
    live = SessionFace(idle=False, seed=1)
    command(live, "wait 1s; look 40 0 in 0.5s; sad", now=0.0)
    command(live, "wink left", now=0.5)
    assert live.state(5.0).eye_x == 0.0
    assert live.state(5.0).emotion != "sad"


def test_the_node_intake_takes_over_the_same_way():
    now = [0.0]
    session = LiveSession(idle=False, seed=0, now=0.0)
    with SessionIntake(session, lambda: now[0], log=lambda level, text: pytest.fail(text)) as intake:

        def send(text):
            assert intake.submit(text) is None
            eventually(intake.idle, timeout=60)  # prepared on the intake's thread

        send("happy")
        now[0] = 2.0
        send("sad")
        now[0] = 2.1
        send("wink left")
        shown = session.face.state(5.0)
    assert shown.emotion == "sad" and shown.skin == EMOTIONS["sad"].skin
