"""Recordings of nothing, and files that are not recordings (issue 43, 8 and low).

A WAV file of zero bytes in 8-bit samples (or mu-law, A-law) is a constant at full scale: silence to
the ear, which the listener looked at every 0.15 s and the recogniser heard piece by piece, for
minutes (ten minutes took 217 s with `--hear` and 57 s with `say file` here; the read itself, under a
second). A file that errs when read (/proc/self/mem) is one line, and speaking leaves nothing of
PulseAudio's behind where nothing plays.

Real WAV files, real hama, pocketsphinx and espeak-ng, the real `baxterface`.
"""

from __future__ import annotations

import os
import wave

import pytest

from baxterface_cli import parse
from conftest import baxterface


def zero_bytes(path, seconds: float, rate: int = 8000) -> None:
    """A WAV file of 8-bit samples, all zero bytes: -128, the lowest, for `seconds`."""
    with wave.open(str(path), "wb") as w:
        w.setnchannels(1), w.setsampwidth(1), w.setframerate(rate)
        w.writeframes(bytes(int(seconds * rate)))


def test_the_listener_does_not_look_at_a_recording_of_zero_bytes(tmp_path, monkeypatch):
    pytest.importorskip("pocketsphinx")
    from baxterface_cli.speech import listening, phoneme_recogniser, phrase_ctc, word_spotter

    if not phoneme_recogniser.available():
        pytest.skip("hama's recogniser does not run here: pocketsphinx listens, at 0.03 of real time")
    zero_bytes(tmp_path / "zeros.wav", 60)
    looks = []
    frames = phrase_ctc.PhraseScorer.frames
    monkeypatch.setattr(phrase_ctc.PhraseScorer, "frames", lambda self, s: looks.append(1) or frames(self, s))
    samples = word_spotter.read_recording(str(tmp_path / "zeros.wav"))
    assert len(set(samples.tolist())) == 1  # a constant, at full scale
    assert listening.spot_samples(samples, ["hello"], method="spotter").words == []
    # only until a window of it is known to be quiet, as for any silence; before: 400, each 0.15 s
    assert len(looks) <= 10


def test_a_recording_of_zero_bytes_is_said_at_rest_without_recognising_it(tmp_path, monkeypatch):
    pytest.importorskip("pocketsphinx")
    pytest.importorskip("av")
    from baxterface_cli.speech import phoneme_recogniser, phones_heard
    from baxterface_cli.speech.recordings import Recordings

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    zero_bytes(tmp_path / "zeros.wav", 120)
    pieces = []
    recognise = phoneme_recogniser.recognise
    monkeypatch.setattr(
        phoneme_recogniser, "recognise", lambda *a, **k: pieces.append(1) or recognise(*a, **k)
    )
    loop = phones_heard._phone_loop
    monkeypatch.setattr(phones_heard, "_phone_loop", lambda data: pieces.append(1) or loop(data))
    recital = Recordings(tmp_path).recite(parse('say file "zeros.wav"').body[0])
    assert abs(recital.utterance.duration - 120) < 0.01
    # before: six pieces of 20 s, each recognised; without hama, the phoneme loop over all of it
    assert pieces == []
    assert all(p.name.startswith("_") for p in recital.utterance.phonemes)  # the mouth at rest


def test_ten_minutes_of_zero_bytes_are_said_and_heard_by_the_command_line(tmp_path):
    pytest.importorskip("pocketsphinx")
    pytest.importorskip("av")
    zero_bytes(tmp_path / "zeros.wav", 600)
    (tmp_path / "both.face").write_text('on word "hello" { happy }\nsay file "zeros.wav"\n')
    env = dict(os.environ, XDG_CACHE_HOME=str(tmp_path / "cache"))
    # before: killed by the helper's two minutes (57 s to say it, 217 s to hear it, here)
    run = baxterface("explain", "both.face", "--hear", "zeros.wav", cwd=tmp_path, env=env)
    assert run.code == 0, run.err
    assert 'robot say file "zeros.wav" (600.00 s, phonemes ' in run.out
    assert "event word" not in run.out


def test_a_file_that_errs_when_read_is_one_line(tmp_path):
    (tmp_path / "mem.face").write_text('say file "/proc/self/mem"\n')
    for command in ("check", "explain"):
        run = baxterface(command, "mem.face", cwd=tmp_path)
        assert run.code == 1 and "internal error" not in run.err
        assert run.err.splitlines()[0] == (
            "mem.face:1:10: error: cannot read recording '/proc/self/mem': "
            "it cannot be read (input/output error)"
        )
    pytest.importorskip("pocketsphinx")
    (tmp_path / "hello.face").write_text('on word "hello" { happy }\n')
    run = baxterface("explain", "hello.face", "--hear", "/proc/self/mem", cwd=tmp_path)
    assert (run.code, run.err) == (
        1,
        "baxterface explain: --hear: /proc/self/mem: it cannot be read (input/output error)\n",
    )


def test_speaking_where_nothing_plays_leaves_nothing_of_pulseaudio(tmp_path):
    home, tmp = tmp_path / "home", tmp_path / "tmp"
    home.mkdir(), tmp.mkdir()
    env = dict(os.environ, HOME=str(home), TMPDIR=str(tmp), XDG_CACHE_HOME=str(tmp_path / "cache"))
    env.pop("XDG_RUNTIME_DIR", None)  # where libpulse would otherwise keep its runtime folder
    for args in (("explain", "-e", 'say "Hello there"'), ("render", "-e", 'say "Hi"', "--out", "hi.wav")):
        run = baxterface(*args, cwd=tmp_path, env=env)
        assert run.code == 0, run.err
    # before: ~/.config/pulse/<machine>-runtime and $TMPDIR/pulse-XXXX, made by espeak-ng's start
    assert sorted(p.name for p in home.rglob("*")) == []
    assert sorted(p.name for p in tmp.iterdir()) == []
