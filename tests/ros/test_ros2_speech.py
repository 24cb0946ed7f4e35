"""On ROS 2 the face speaks through this machine's sound device (the default there), heard whole.

The sound device is test_audio.py's pipe card (ALSA's file plugin into a named
pipe, emptied in real time): what the node plays through PortAudio is recorded
and compared, sample for sample, with what espeak-ng says. It hears real time,
so it runs alone after the parallel suites (marker `realtime`).
"""

from __future__ import annotations

import importlib.util
import json
import signal
import subprocess
import sys

import numpy as np
import pytest

from baxterface_cli.ros.connect import open_link
from conftest import ROOT
from ros2_world import Heard

pytestmark = [pytest.mark.ros2, pytest.mark.realtime]


def audio_helpers():
    spec = importlib.util.spec_from_file_location(
        "audio_helpers", ROOT / "tests" / "speech" / "test_audio.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture
def card(tmp_path):
    helpers = audio_helpers()
    helpers.have_sounddevice()
    made = helpers.PipeCard(tmp_path / "home")
    yield made, helpers
    made.stop()


def reading(msg):
    return json.loads(msg.data)


def test_say_is_heard_on_this_machine_s_sound_device_while_the_state_says_it(ros2, card, engine):
    card, helpers = card
    link = open_link(2, "pytest_ears", anonymous=True)
    state = Heard(
        link, "/baxter_face/state", "std_msgs/String", latched=True, keep=lambda m: json.loads(m.data)
    )
    node = subprocess.Popen(
        [sys.executable, "-m", "baxterface_cli", "node", "--ros", "2", "--ros-args", "-p", "idle:=false"],
        cwd=str(ROOT),
        env=card.env(),
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    try:
        state.wait_for(timeout=60)
        chatter = link.publisher("/display_chatter", "std_msgs/String")
        while chatter.listeners() == 0:
            assert node.poll() is None
        seen = state.count()
        chatter.publish(data='say "Hello there"')
        state.wait_for(lambda r: r["saying"] == "Hello there", after=seen)
        state.wait_for(lambda r: r["saying"] is None and not r["playing"], after=seen)
    finally:
        node.send_signal(signal.SIGTERM)
        out = node.communicate(timeout=30)[0]
        link.close()
    card.drain()
    recording = card.samples()
    utterance = helpers.spoken("Hello there")
    at = helpers.find(recording, utterance)
    assert np.array_equal(recording[at : at + len(utterance)], utterance)  # all of it, sample for sample
    assert node.returncode == 0 and "no sound device" not in out and "Traceback" not in out, out
