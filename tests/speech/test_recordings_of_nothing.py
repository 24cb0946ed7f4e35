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

from conftest import baxterface


def zero_bytes(path, seconds: float, rate: int = 8000) -> None:
    """A WAV file of 8-bit samples, all zero bytes: -128, the lowest, for `seconds`."""
    with wave.open(str(path), "wb") as w:
        w.setnchannels(1), w.setsampwidth(1), w.setframerate(rate)
        w.writeframes(bytes(int(seconds * rate)))


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
