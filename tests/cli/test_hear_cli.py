"""`render`, `explain` and `play` with `--hear FILE.wav`, as a user runs them: the script's words
heard in a real espeak-ng recording become events at the times they end, merged with --events;
what cannot be heard is refused in one line."""

from __future__ import annotations

import re
import subprocess
import wave

import pytest
from spoken import spoken

from conftest import baxterface

pytest.importorskip("pocketsphinx")

SCRIPT = 'on word "robot" { happy }\n'
# How soon after its last word a phrase is told: the listener tells one that ends a sentence 0.15
# to 0.35 s after it (docs/speech.md), once a look has found it whole.
NEAR = 0.4


@pytest.fixture
def said(tmp_path):
    """A second of quiet, then "look at that robot" (en-us): the word's end, from the sound."""
    path = tmp_path / "said.wav"
    _, _, word_end = spoken(path, "look at that robot", quiet=1.0)
    return path, word_end


def test_explain_hears_the_word_and_runs_its_handler_near_its_end(tmp_path, said):
    path, word_end = said
    (tmp_path / "robot.face").write_text(SCRIPT)
    run = baxterface("explain", str(tmp_path / "robot.face"), "--hear", str(path))
    assert run.code == 0, run.err
    ran = re.search(r"^\s*([0-9.]+) s\s+react line 1 'on word \"robot\"' runs$", run.out, re.M)
    assert ran, run.out
    assert abs(float(ran.group(1)) - word_end) < NEAR
    assert re.search(r"^\s*[0-9.]+ -\s+[0-9.]+ s\s+line 1\s+happy$", run.out, re.M)


def test_heard_words_merge_with_an_events_file(tmp_path, said):
    path, word_end = said
    (tmp_path / "both.face").write_text(SCRIPT + "on signal poke { sad }\n")
    (tmp_path / "events.txt").write_text("0.5 signal poke\n")
    run = baxterface(
        "explain", str(tmp_path / "both.face"), "--hear", str(path), "--events", str(tmp_path / "events.txt")
    )
    assert run.code == 0, run.err
    lines = [line for line in run.out.splitlines() if "event signal" in line or "event word" in line]
    # Each says where it came from: the events file's line, the recording it was heard in.
    assert lines[0].endswith(f"event signal poke ({tmp_path / 'events.txt'}:1)"), run.out
    assert lines[1].endswith(f'event word "robot" (heard in {path})'), run.out


def test_render_plays_the_handler_after_the_word_it_heard(tmp_path, said):
    path, word_end = said
    (tmp_path / "robot.face").write_text(SCRIPT)
    out = tmp_path / "robot.gif"
    run = baxterface("render", str(tmp_path / "robot.face"), "--hear", str(path), "--out", str(out))
    assert run.code == 0, run.err
    heard = subprocess.run(
        ["ffprobe", "-v", "error", "-show_entries", "format=duration", "-of", "csv=p=0", str(out)],
        capture_output=True,
        text=True,
        check=True,
    )
    # nothing happens before the word: the video lasts until its handler (0.3 s of `happy`) has run
    assert float(heard.stdout) > word_end


@pytest.mark.parametrize(
    "args, message",
    [
        (["--hear", "missing.wav"], r"--hear: missing.wav: no such file$"),
        (["--hear", "robot.face"], r"--hear: robot.face: not a sound file FFmpeg reads"),
    ],
)
def test_a_file_it_cannot_read_is_a_one_line_error(tmp_path, args, message):
    (tmp_path / "robot.face").write_text(SCRIPT)
    for command in ("explain", "render", "play"):
        extra = ["--out", "x.gif"] if command == "render" else ["--terminal"] if command == "play" else []
        run = baxterface(command, "robot.face", *args, *extra, cwd=tmp_path)
        assert run.code != 0
        assert re.fullmatch(rf"baxterface {command}: {message}[^\n]*\n", run.err), run.err


def test_a_script_that_waits_for_no_words_is_told_so(tmp_path, said):
    path, _ = said
    (tmp_path / "poke.face").write_text("on signal poke { sad }\n")
    run = baxterface("explain", str(tmp_path / "poke.face"), "--hear", str(path))
    assert run.code == 2
    assert run.err.strip() == (
        "baxterface explain: --hear: the script listens for no words ('on word \"hello\" { ... }')"
    )


def test_a_recording_in_another_format_is_heard_as_say_file_reads_it(tmp_path, said):
    path, word_end = said
    deep = tmp_path / "said24.wav"  # 24-bit samples, as a sound recorder writes them
    subprocess.run(["sox", str(path), "-b", "24", str(deep)], check=True)
    (tmp_path / "robot.face").write_text(SCRIPT)
    run = baxterface("explain", "robot.face", "--hear", str(deep), cwd=tmp_path)
    assert run.code == 0, run.err
    ran = re.search(r"^\s*([0-9.]+) s\s+react line 1 'on word \"robot\"' runs$", run.out, re.M)
    assert ran and abs(float(ran.group(1)) - word_end) < NEAR, run.out


def test_a_header_that_claims_hours_is_refused_before_reading(tmp_path):
    slow = tmp_path / "slow.wav"  # 320 KB at one sample a second: 44 hours, were it resampled
    with wave.open(str(slow), "wb") as w:
        w.setnchannels(1), w.setsampwidth(2), w.setframerate(1)
        w.writeframes(b"\0\0" * 160_000)
    (tmp_path / "robot.face").write_text(SCRIPT)
    run = baxterface("explain", "robot.face", "--hear", str(slow), cwd=tmp_path)
    assert (run.code, run.err) == (
        1,
        f"baxterface explain: --hear: {slow}: too long (160000 s; the limit is 600 s)\n",
    )
