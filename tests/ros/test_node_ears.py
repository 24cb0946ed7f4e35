"""The node's ears (ros/node_ears.py) without ROS: a recording played into the spotter as a
microphone gives it, the phrases taken from the live session as handlers come and go."""

from __future__ import annotations

import shutil
import subprocess
import time

import pytest

from baxterface_cli.engine.live_session import LiveSession
from baxterface_cli.language.parser import parse
from baxterface_cli.ros.node_ears import Ears, words_listened
from baxterface_cli.speech import listening
from waiting import eventually


@pytest.fixture(scope="module")
def robot_wav(tmp_path_factory):
    pytest.importorskip("pocketsphinx")
    if shutil.which("espeak-ng") is None:
        pytest.skip("espeak-ng is not installed")
    path = tmp_path_factory.mktemp("ears") / "that.wav"
    subprocess.run(["espeak-ng", "-v", "en-us", "-w", str(path), "look at that robot"], check=True)
    return path


def test_the_phrases_are_the_handlers_and_the_waits_of_what_runs():
    session = LiveSession(now=0.0)
    assert words_listened(session) == []
    session.run(parse('on word "hello" { happy }\non button ok { wait until word "yes please" }'), 0.0)
    session.run(parse('wait until word "Good  Night"\nsad'), 0.1)
    assert words_listened(session) == ["hello", "yes please", "good night"]


def test_a_recording_plays_once_a_word_is_listened_for_and_its_word_is_heard(robot_wav):
    session = LiveSession(now=time.monotonic())
    heard, said = [], []
    ears = Ears(
        session,
        lambda event, at: heard.append((event.kind, event.arg, at)),
        str(robot_wav),
        log=lambda *a: said.append(a),
    )
    assert ears.start() is None
    try:
        session.run(parse('on word "robot" { happy }'), time.monotonic())  # sent live: the ears follow
        kind, word, at = eventually(lambda: heard and heard[0], timeout=30)
        assert (kind, word) == ("word", "robot") and at <= time.monotonic()
        assert any(level == "info" and text.startswith('heard word "robot", ') for level, text in said)
        if listening.default_method() == listening.MOONSHINE:  # the whole utterance too
            assert eventually(lambda: heard[1:] and heard[1][:2], timeout=30) == (
                "heard",
                "look at that robot",
            )
    finally:
        ears.close()


def test_ears_that_cannot_hear_say_why_in_one_line(tmp_path):
    pytest.importorskip("pocketsphinx")  # without it, that is what they say
    bad = tmp_path / "not.wav"
    bad.write_text("not a sound")
    ears = Ears(LiveSession(), lambda event, at: None, str(bad))
    problem = ears.start()
    assert problem.startswith(f"cannot read {bad}") and "\n" not in problem
    ears.close()
