"""Hostile speech and recordings: what a script says is counted as it will be said, recordings that
are not what they seem are refused fast and alike by `check` and `render`, and nothing is left behind.

Real espeak-ng, real WAV files (sox and the wave module), a real FIFO, the real `baxterface`.
"""

from __future__ import annotations

import os
import shutil
import struct
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest
from support.waiting import eventually

from baxterface_cli import parse
from baxterface_cli.core.run_folders import own_folder, sweep
from baxterface_cli.language.durations import speech_bound
from conftest import baxterface

SOX = shutil.which("sox")
ESPEAK = shutil.which("espeak-ng")


def sox(*args: str) -> None:
    if SOX is None:
        pytest.skip("needs sox")
    subprocess.run([SOX, *args], check=True, capture_output=True, timeout=60)


def finishes(work, seconds: float = 60.0):
    """`work()`'s result or exception, failing the test if it is still running after `seconds`."""
    box: dict = {}

    def run():
        try:
            box["value"] = work()
        except BaseException as e:  # handed back to the test
            box["error"] = e

    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    thread.join(seconds)
    assert not thread.is_alive(), "hung"
    return box


def wav_bytes(channels=1, rate=16000, bits=16, tag=1, data=b"\0\0" * 1600, with_data=True) -> bytes:
    block = channels * ((bits + 7) // 8)
    fmt = struct.pack("<HHIIHH", tag, channels, rate, rate * block, block, bits)
    body = b"WAVE" + b"fmt " + struct.pack("<I", len(fmt)) + fmt
    if with_data:
        body += b"data" + struct.pack("<I", len(data)) + data
    return b"RIFF" + struct.pack("<I", len(body)) + body


# -- a `say` counts for as long as it can take ---------------------------------------------------


SAID = """
import json, sys
from baxterface_cli.speech.synthesis import engine
print(engine().say(sys.argv[1], sys.argv[2], int(sys.argv[3])).duration)
"""


@pytest.mark.parametrize(
    "text, voice",
    [
        ("你好世界" * 60, "cmn"),  # the issue's: counted as one word, spoke four minutes
        ("ሀሁሂሃሄ" * 10, "sw"),  # spelled by name: the slowest characters measured
        ("%/%\\" * 10, "sw"),  # signs said by name ("{}[]" in ky would too, but crashes espeak-ng 1.51)
        ("1234567890" * 4, "tn"),
        ("qwrtzpsdfghjklxcvbnm" * 3, "qdb"),
        ("The quick brown fox, as it happens, jumps.", "en"),
    ],
)
@pytest.mark.parametrize("rate", [80, 175, 400])
def test_no_say_speaks_longer_than_it_is_counted(engine, text, voice, rate):
    # A process of its own for each: espeak-ng 1.51 has crashed on a run of hostile texts in one.
    said = subprocess.run(
        [sys.executable, "-c", SAID, text, voice, str(rate)], capture_output=True, text=True, timeout=120
    )
    assert said.returncode == 0, said.stderr[-300:]
    seconds = float(said.stdout)
    assert 0 < seconds <= speech_bound(text, rate), (seconds, speech_bound(text, rate))


def test_a_script_of_long_chinese_says_is_refused_where_it_passes_the_hour(tmp_path):
    script = tmp_path / "cmn.face"
    script.write_text(('say "' + "你好世界" * 250 + '" voice cmn\n') * 20, encoding="utf-8")
    for command in ("check", "explain"):
        run = baxterface(command, str(script))
        assert run.code == 1, run.err
        first = run.err.splitlines()[0]
        assert first.startswith(f"{script}:") and "the limit is 1 hour" in first, first
        assert "No envelope" not in run.err  # nothing was spoken to find it out


def test_repeated_recordings_count_as_long_as_their_files(tmp_path):
    sox("-n", "-r", "16000", "-b", "16", "-c", "1", str(tmp_path / "ok.wav"), "synth", "2.9", "sine", "300")
    (tmp_path / "many.face").write_text('happy\nrepeat 10000 { say file "ok.wav" }\n')
    (tmp_path / "few.face").write_text('repeat 1000 { say file "ok.wav" }\n')
    for command in ("check", "explain"):
        run = baxterface(command, str(tmp_path / "many.face"))
        assert run.code == 1 and run.err.startswith(
            f"{tmp_path / 'many.face'}:2:1: error: the script runs 8 hours"
        )
    out = tmp_path / "x.wav"
    run = baxterface("render", str(tmp_path / "many.face"), "--out", str(out))
    assert run.code == 1 and "the limit is 1 hour" in run.err and not out.exists()
    assert baxterface("check", str(tmp_path / "few.face")).code == 0  # 2,900 s: under the hour


def test_a_live_face_refuses_recordings_longer_than_the_limit(tmp_path):
    from baxterface_cli.core.face_state import FaceState
    from baxterface_cli.engine.live_face import LiveFace
    from baxterface_cli.language.diagnostics import ScriptError
    from baxterface_cli.language.parser import parse
    from baxterface_cli.speech.recordings import Recordings

    sox("-n", "-r", "16000", "-b", "16", "-c", "1", str(tmp_path / "ok.wav"), "synth", "2.9", "sine", "300")
    live = LiveFace(idle=False, recordings=Recordings(tmp_path, confined=True))
    with pytest.raises(ScriptError, match="display_chatter:1:1: error: the script runs 8 hours"):
        live.prepare(parse('repeat 10000 { say file "ok.wav" }', "display_chatter"), FaceState())


# -- recordings that are not what they seem -----------------------------------------------------

BAD_HEADERS = {
    "nochannels.wav": (wav_bytes(channels=0), "0 channels"),
    "nobits.wav": (wav_bytes(bits=0), "0-bit samples"),
    "oddtag.wav": (wav_bytes(tag=0x1234), "format tag 0x1234"),
    "nodata.wav": (wav_bytes(with_data=False), "no data chunk"),
}


@pytest.mark.parametrize("name", sorted(BAD_HEADERS))
def test_check_refuses_what_render_refuses_with_the_same_clear_words(tmp_path, name):
    pytest.importorskip("av")
    data, reason = BAD_HEADERS[name]
    (tmp_path / name).write_bytes(data)
    (tmp_path / "s.face").write_text(f'say file "{name}"\n')
    checked = baxterface("check", str(tmp_path / "s.face"))
    rendered = baxterface("render", str(tmp_path / "s.face"), "--out", str(tmp_path / "x.wav"))
    assert checked.code == rendered.code == 1
    first = checked.err.splitlines()[0]
    assert first.startswith(f"{tmp_path / 's.face'}:1:10: error: cannot read recording '{name}': ")
    assert reason in first and rendered.err.splitlines()[0] == first
    assert "object has no attribute" not in checked.err + rendered.err


def test_a_fifo_named_as_a_recording_fails_at_once(tmp_path):
    from baxterface_cli.speech.audio_files import AudioError, probe, read_sound

    fifo = tmp_path / "said.wav"
    os.mkfifo(str(fifo))
    for read in (probe, read_sound):
        box = finishes(lambda read=read: read(str(fifo)))
        assert isinstance(box.get("error"), AudioError) and str(box["error"]) == "not a file"
    (tmp_path / "s.face").write_text('say file "said.wav"\n')
    run = baxterface("check", str(tmp_path / "s.face"))  # its own timeout fails a hang
    assert run.code == 1 and "cannot read recording 'said.wav': not a file" in run.err


def test_a_recording_swapped_for_a_fifo_after_its_check_is_refused_when_read(tmp_path):
    pytest.importorskip("av")
    from baxterface_cli.speech.recordings import RecordingError, Recordings

    (tmp_path / "said.wav").write_bytes(wav_bytes())
    recordings = Recordings(tmp_path, confined=True)
    script = parse('say file "said.wav"')
    assert recordings.check(script) == []
    os.remove(str(tmp_path / "said.wav"))
    os.mkfifo(str(tmp_path / "said.wav"))
    box = finishes(lambda: recordings.recite(script.body[0]))
    assert isinstance(box.get("error"), RecordingError) and "not a file" in str(box["error"])


def test_a_header_before_megabytes_of_zeros_is_refused_from_the_header(tmp_path):
    pytest.importorskip("av")
    with open(str(tmp_path / "zeros.wav"), "wb") as f:
        f.write(b"RIFF" + struct.pack("<I", 0xFFFFFFFF) + b"WAVE")
        f.truncate(190 * 2**20)  # sparse: nothing is written
    fmt = wav_bytes(data=b"")[:-8]  # a format, then a data chunk as long as the file
    with open(str(tmp_path / "long.wav"), "wb") as f:
        f.write(fmt + b"data" + struct.pack("<I", 0xFFFFFFFF))
        f.truncate(190 * 2**20)
    (tmp_path / "s.face").write_text('say file "zeros.wav"\nsay file "long.wav"\n')
    run = baxterface("check", str(tmp_path / "s.face"))
    assert run.code == 1
    assert "1:10: error: cannot read recording 'zeros.wav': a WAV file with no format chunk" in run.err
    assert "2:10: error: cannot read recording 'long.wav': too long (6226 s; the limit is 600 s)" in run.err


def test_without_pyav_check_refuses_every_recording_render_could_not_read(tmp_path):
    (tmp_path / "said.wav").write_bytes(wav_bytes())
    blocker = tmp_path / "blocked"
    blocker.mkdir()
    (blocker / "av.py").write_text("raise ImportError('blocked for a test')\n")
    env = dict(
        os.environ, PYTHONPATH=os.pathsep.join(filter(None, [str(blocker), os.environ.get("PYTHONPATH")]))
    )
    run = baxterface("check", "-", stdin='say file "said.wav"\n', cwd=tmp_path, env=env)
    assert run.code == 1, run.err
    assert "pip install 'baxterface[lipsync]'" in run.err.splitlines()[0]


# -- the analysis cache ----------------------------------------------------------------------------


def test_the_analysis_cache_is_private_and_bounded_by_bytes(tmp_path, monkeypatch):
    pytest.importorskip("av")
    from baxterface_cli.speech import recordings as module

    sox("-n", "-r", "16000", "-b", "16", "-c", "1", str(tmp_path / "tone.wav"), "synth", "1", "sine", "300")
    cache = tmp_path / "deep" / "cache" / "lipsync"
    recordings = module.Recordings(tmp_path, cache=cache)
    monkeypatch.setattr(module, "CACHE_BYTES", 1)  # keep only the newest
    for word in ("one", "two", "three"):
        recordings.recite(parse(f'say file "tone.wav" text "{word}" language fr').body[0])
        recordings.recite(parse(f'say file "tone.wav" text "{word}"').body[0])
    assert len(list(cache.glob("*.json"))) == 1
    for folder in (cache, cache.parent, cache.parent.parent):
        assert folder.stat().st_mode & 0o777 == 0o700


def test_the_analysis_cache_is_bounded_by_count(tmp_path, monkeypatch):
    pytest.importorskip("av")
    from baxterface_cli.speech import recordings as module

    sox("-n", "-r", "16000", "-b", "16", "-c", "1", str(tmp_path / "tone.wav"), "synth", "1", "sine", "300")
    cache = tmp_path / "cache"
    recordings = module.Recordings(tmp_path, cache=cache)
    monkeypatch.setattr(module, "CACHE_FILES", 3, raising=False)
    for word in ("one", "two", "three", "four", "five", "six"):
        recordings.recite(parse(f'say file "tone.wav" text "{word}"').body[0])
    assert len(list(cache.glob("*.json"))) == 3


def test_speech_remembered_is_bounded_by_bytes(engine, monkeypatch):
    from baxterface_cli.speech import synthesis

    monkeypatch.setattr(synthesis, "CACHE_BYTES", 200_000)
    for n in range(6):
        for times in (2, 1):  # kept as asked for again, and once
            for _ in range(times):
                engine.say(f"Number {n} is said {times} times, long enough to weigh something.", "en", 80)
    for kept in (engine._cache, engine._once):
        held = sum(u.samples.nbytes for u in kept.values())
        assert 0 < held <= 200_000 or len(kept) == 1


# -- the mouth of a recording heard without its words ----------------------------------------------


def test_a_recording_heard_without_text_does_not_rest_inside_continuous_speech(tmp_path):
    pytest.importorskip("av")
    if ESPEAK is None:
        pytest.skip("needs espeak-ng")
    from baxterface_cli.core.face_constants import REST
    from baxterface_cli.speech.phone_names import frame_loudness
    from baxterface_cli.speech.recordings import Recordings

    sentence = "The quick brown fox jumps over the lazy dog while the robot keeps talking about its day"
    subprocess.run([ESPEAK, "-v", "en-us", "-w", str(tmp_path / "s.wav"), sentence], check=True, timeout=60)
    recital = Recordings(tmp_path, cache=tmp_path / "cache").recite(parse('say file "s.wav"').body[0])
    sound = recital.utterance
    loud = frame_loudness(sound.samples, sound.sample_rate)
    rests = [k.at for k in recital.mouth if k.shape == REST and k.at < sound.duration - 0.3]
    for at in rests:  # every rest inside is at a true silence of 100 ms or more
        around = loud[max(0, int(at * 100) - 10) : int(at * 100) + 15]
        quiet = max((len(run) for run in "".join("q" if x < 50 else " " for x in around).split()), default=0)
        assert quiet >= 10, (at, rests)
    assert len(rests) <= 2


# -- files left behind -----------------------------------------------------------------------------


class _Publisher:
    def __init__(self):
        self.sent = []

    def listeners(self):
        return 1

    def publish(self, **fields):
        self.sent.append(fields)


class _Link:
    def publisher(self, topic, kind):
        return _Publisher()


def _speech(seconds: float):
    from baxterface_cli.engine.effects import Speech
    from baxterface_cli.speech.synthesis import Utterance

    samples = (np.sin(np.arange(int(16000 * seconds)) / 5) * 3000).astype(np.int16)
    return Speech(Utterance("x", "en", 175, samples, 16000, (), ()))


def test_speech_files_go_on_time_with_nothing_more_said(tmp_path, monkeypatch):
    from baxterface_cli.ros.speakers import SoundPlaySpeaker

    monkeypatch.setenv("TMPDIR", str(tmp_path))
    monkeypatch.setattr("tempfile.tempdir", None)
    monkeypatch.setattr(SoundPlaySpeaker, "KEEP", 0.2)
    speaker = SoundPlaySpeaker(_Link(), lambda line: None)
    assert Path(speaker.folder).name.startswith(f"baxterface-speech-{os.getpid()}-")
    speaker.speak(_speech(0.1))
    assert len(os.listdir(speaker.folder)) == 1
    eventually(lambda: not os.listdir(speaker.folder))
    speaker.close()
    assert not os.path.exists(speaker.folder)


def test_speech_files_are_bounded_by_bytes(tmp_path, monkeypatch):
    from baxterface_cli.ros.speakers import SoundPlaySpeaker

    monkeypatch.setenv("TMPDIR", str(tmp_path))
    monkeypatch.setattr("tempfile.tempdir", None)
    monkeypatch.setattr(SoundPlaySpeaker, "MAX_BYTES", 100_000)  # three seconds of 16 kHz
    speaker = SoundPlaySpeaker(_Link(), lambda line: None)
    for _ in range(10):
        speaker.speak(_speech(1.0))
    files = [Path(speaker.folder) / name for name in os.listdir(speaker.folder)]
    assert 1 <= len(files) <= 3 and sum(f.stat().st_size for f in files) <= 100_000
    assert (Path(speaker.folder) / "say-000010.wav") in files  # the newest stays
    speaker.close()


def test_a_dead_processs_folders_are_swept_and_a_living_ones_kept(tmp_path, monkeypatch):
    monkeypatch.setenv("TMPDIR", str(tmp_path))
    monkeypatch.setattr("tempfile.tempdir", None)
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    living = subprocess.Popen([sys.executable, "-c", "import sys; sys.stdin.read()"], stdin=subprocess.PIPE)
    try:
        for pid in (dead.pid, living.pid):
            folder = tmp_path / f"baxterface-speech-{pid}-abc"
            folder.mkdir()
            (folder / "say-000001.wav").write_bytes(wav_bytes())
        other_kind = tmp_path / f"baxterface-genpy-{dead.pid}-abc"
        other_kind.mkdir()
        mine = own_folder("speech")
        assert not (tmp_path / f"baxterface-speech-{dead.pid}-abc").exists()
        assert (tmp_path / f"baxterface-speech-{living.pid}-abc").exists() and other_kind.exists()
        assert sweep("genpy") == 1 and not other_kind.exists()
        os.rmdir(mine)
    finally:
        living.communicate(b"")


def test_a_node_killed_outright_leaves_no_genpy_folders_the_next_does_not_sweep(tmp_path):
    pytest.importorskip("genpy")
    env = dict(os.environ, TMPDIR=str(tmp_path))
    build = (
        "import os, signal\n"
        "from baxterface_cli.ros import messages\n"
        "messages._generate('sound_play/SoundRequest')\n"
        "os.kill(os.getpid(), signal.SIGKILL)\n"
    )
    killed = subprocess.run([sys.executable, "-c", build], env=env, capture_output=True, timeout=120)
    assert killed.returncode == -9, killed.stderr
    (left,) = [p.name for p in tmp_path.iterdir()]
    assert left.startswith("baxterface-genpy-") and not any(
        p.name.startswith("genpy_") for p in tmp_path.iterdir()
    )
    again = subprocess.run(
        [
            sys.executable,
            "-c",
            "from baxterface_cli.ros import messages; messages._generate('sound_play/SoundRequest')",
        ],
        env=env,
        capture_output=True,
        timeout=120,
    )
    assert again.returncode == 0, again.stderr
    assert list(tmp_path.iterdir()) == []  # the dead one's swept at start, its own at exit


# -- what a live face keeps ------------------------------------------------------------------------


def test_a_live_face_keeps_no_more_speech_after_150_new_says_than_after_20(engine, tmp_path, monkeypatch):
    """The node's memory grew with every new text said on display_chatter (issue 43, 9c): each is
    said once and never again, so none is kept past the few a repeat may ask for."""
    import gc

    from baxterface_cli.engine.effects import Speech
    from baxterface_cli.engine.live_face import sleep_face
    from baxterface_cli.engine.live_session import LiveSession
    from baxterface_cli.ros.speakers import SoundPlaySpeaker
    from baxterface_cli.speech.synthesis import Utterance

    monkeypatch.setenv("TMPDIR", str(tmp_path))
    speaker = SoundPlaySpeaker(_Link(), lambda line: None)
    session = LiveSession(start=sleep_face(), idle=True, now=0.0, seed=None, keep_up=True)
    gc.collect()
    kept, now, spoken = {0: sum(type(o) is Utterance for o in gc.get_objects())}, 0.0, 0  # other tests'
    for said in range(1, 151):
        session.run(parse(f'say "Command number {said} is a sentence never said before."', "command"), now)
        for at in (now + 0.05, now + 3.0):  # the speech starts, and ends
            spoken += sum(
                speaker.speak(c.effect) is None for c in session.tick(at)[1] if isinstance(c.effect, Speech)
            )
        now += 3.0
        if said in (20, 150):
            gc.collect()
            kept[said] = sum(type(o) is Utterance for o in gc.get_objects())
    speaker.close()
    assert spoken == 150
    assert kept[150] <= kept[20] <= kept[0] + 10, kept  # the last few, in case they are asked for again
