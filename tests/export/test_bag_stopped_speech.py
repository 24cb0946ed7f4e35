"""A `say` stopped before its end goes into a bag as far as it was heard, read back by Debian's
real rosbag: sound_play is asked for the words said, and told to stop where the speech stopped
(an `interrupt` handler's event, the end of the run), as the face node tells it live."""

from __future__ import annotations

import os
import re

import pytest

from conftest import baxterface

pytestmark = [pytest.mark.ros, pytest.mark.xdist_group("bag")]

START = 1_700_000_000
NS = 1_000_000_000
SOUND = "/robotsound"
SAY, PLAY_ONCE, PLAY_STOP = -3, 1, 0
SENTENCE = "Hello there, this is a long sentence that the robot will not get to finish."
SCRIPT = f'on signal stop interrupt {{ sad }}\nsay "{SENTENCE}"\nhappy\n'


def sound_requests(path):
    """(seconds into the bag, sound, command, arg) of each sound_play request."""
    import rosbag

    with rosbag.Bag(str(path)) as bag:
        return [
            ((t.to_nsec() - START * NS) / NS, msg.sound, msg.command, msg.arg)
            for _, msg, t in bag.read_messages(topics=[SOUND])
        ]


def run(folder, *args):
    done = baxterface(*args, cwd=folder, env=dict(os.environ, SOURCE_DATE_EPOCH=str(START)))
    assert done.code == 0, done.err
    return done.out


def words_before(explained: str, t: float):
    return [
        m.group(2)
        for m in re.finditer(r"^\s*([\d.]+) s\s+word\s+(\S+)\s*$", explained, re.MULTILINE)
        if float(m.group(1)) < t
    ]


def test_a_say_an_interrupt_stops_is_asked_as_far_as_it_was_heard_then_stopped(tmp_path):
    (tmp_path / "s.face").write_text(SCRIPT)
    (tmp_path / "s.events").write_text("1.2 signal stop\n")
    run(tmp_path, "render", "s.face", "--events", "s.events", "--out", "s.bag", "--size", "128x75", "-q")
    (first, stop, again) = sound_requests(tmp_path / "s.bag")
    heard = first[3]
    assert first[:3] == (0.0, SAY, PLAY_ONCE) and SENTENCE.startswith(heard) and len(heard) < len(SENTENCE)
    said = words_before(run(tmp_path, "explain", "s.face", "--events", "s.events"), 1.2)
    assert [w.strip(",") for w in heard.split()] == said  # the words the face's mouth said, no more
    assert stop[1:] == (SAY, PLAY_STOP, heard) and stop[0] == pytest.approx(1.2, abs=1e-6)
    assert again[1:] == (SAY, PLAY_ONCE, SENTENCE)  # said again, whole, once the handler is done


def test_a_say_the_run_ends_in_is_stopped_at_the_end(tmp_path):
    (tmp_path / "e.face").write_text(f'on signal stop {{ sad }}\nsay "{SENTENCE}"\n')
    run(tmp_path, "render", "e.face", "--duration", "1", "--out", "e.bag", "--size", "128x75", "-q")
    (first, stop) = sound_requests(tmp_path / "e.bag")
    assert first[2] == PLAY_ONCE and SENTENCE.startswith(first[3]) and len(first[3]) < len(SENTENCE)
    assert stop[1:] == (SAY, PLAY_STOP, first[3]) and stop[0] == pytest.approx(1.0, abs=1e-6)


def test_a_say_nothing_stops_is_asked_whole_and_never_stopped(tmp_path):
    run(tmp_path, "render", "-e", f'say "{SENTENCE}"', "--out", "w.bag", "--size", "128x75", "-q")
    assert sound_requests(tmp_path / "w.bag") == [(0.0, SAY, PLAY_ONCE, SENTENCE)]
