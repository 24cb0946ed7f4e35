"""`--hear FILE.wav@2s`: a visitor's recording placed in time. Its words are events that much later,
and `render` mixes the visitor's voice into the sound beside the face's, so a rendered conversation
has both voices (read back with PyAV and sox)."""

from __future__ import annotations

import re
import subprocess

import numpy as np
import pytest
from spoken import spoken

from conftest import baxterface

pytest.importorskip("pocketsphinx")

SCRIPT = 'on word "robot" { say "Yes, I am here." }\n'
START = 2.0


@pytest.fixture
def said(tmp_path):
    """ "look at that robot" (en-us), from its first sample: the samples, their rate, the word's end."""
    path = tmp_path / "said.wav"
    samples, rate, word_end = spoken(path, "look at that robot")
    return path, samples, rate, word_end


def mono(data):
    """A decoded sound frame's samples, its channels (planar) averaged."""
    return data.mean(axis=0) if data.ndim == 2 else data


def where(track, voice, rate):
    """When `voice` starts in `track` (its best match), in seconds."""
    return int(np.argmax(np.correlate(track, voice, mode="valid"))) / rate


def test_the_words_are_heard_that_much_later(tmp_path, said):
    path, _, _, word_end = said
    (tmp_path / "robot.face").write_text(SCRIPT)
    run = baxterface("explain", "robot.face", "--hear", f"{path}@{START:g}s", cwd=tmp_path)
    assert run.code == 0, run.err
    ran = re.search(r"^\s*([0-9.]+) s\s+react line 1 'on word \"robot\"' runs$", run.out, re.M)
    assert ran and abs(float(ran.group(1)) - (START + word_end)) < 0.3, run.out
    assert f'event word "robot" (heard in {path}@2s)' in run.out


def test_render_mixes_the_visitors_voice_at_its_time_with_the_faces_reply(tmp_path, said):
    path, voice, rate, word_end = said
    (tmp_path / "robot.face").write_text(SCRIPT)
    out = tmp_path / "conversation.wav"
    run = baxterface("render", "robot.face", "--hear", f"{path}@2s", "--out", str(out), cwd=tmp_path)
    assert run.code == 0, run.err
    # sox reads the file back, as 16-bit samples at the visitor's rate
    raw = subprocess.run(
        ["sox", str(out), "-t", "raw", "-e", "signed", "-b", "16", "-c", "1", "-r", str(rate), "-"],
        capture_output=True,
        check=True,
    ).stdout
    track = np.frombuffer(raw, "<i2").astype(float)
    assert not np.abs(track[: round((START - 0.05) * rate)]).any()  # nothing before the visitor speaks
    near = track[round((START - 0.5) * rate) : round(START * rate) + len(voice) + rate // 2]
    assert START - 0.5 + where(near, voice, rate) == pytest.approx(START, abs=0.002)
    reply = track[round((START + word_end + 0.1) * rate) :]  # the face answers after the word
    assert reply.size > 0.3 * rate and np.abs(reply).max() > 3000


def test_a_video_carries_both_voices(tmp_path, said):
    av = pytest.importorskip("av")
    path, voice, rate, word_end = said
    (tmp_path / "robot.face").write_text(SCRIPT)
    out = tmp_path / "conversation.mp4"
    run = baxterface(
        "render", "robot.face", "--hear", f"{path}@2s", "--out", str(out), "--size", "256x150", cwd=tmp_path
    )
    assert run.code == 0, run.err
    with av.open(str(out)) as container:
        sound_rate = container.streams.audio[0].rate
        track = np.concatenate([mono(f.to_ndarray()) for f in container.decode(audio=0)])

    def loud(t0, t1):
        piece = track[round(t0 * sound_rate) : round(t1 * sound_rate)]
        return float(np.sqrt(np.mean(piece**2)))

    assert loud(0.2, START - 0.1) < 0.001  # quiet until the visitor speaks
    assert loud(START + 0.1, START + word_end - 0.1) > 0.02  # the visitor
    assert loud(START + word_end + 0.2, START + word_end + 0.8) > 0.02  # the face's reply


def test_a_start_past_the_limit_is_one_line(tmp_path, said):
    path, _, _, _ = said
    (tmp_path / "robot.face").write_text(SCRIPT)
    run = baxterface("explain", "robot.face", "--hear", f"{path}@99999s", cwd=tmp_path)
    assert run.code == 2 and run.err.count("\n") == 1 and "starts past the one-hour limit" in run.err
