"""`say file`: a recording said, its mouth found in its own sound (pocketsphinx, or its spectrum).

The recording is made here by espeak-ng, padded with quiet and a little
noise, so the true phoneme times are known: the mouth `say` would show for
the same words is what the recording's mouth is held to. One analysis of
each kind serves the whole module (and is kept in the tests' own cache
folder, see conftest.py).
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import wave
from collections import Counter, OrderedDict
from pathlib import Path

import numpy as np
import pytest

from baxterface_cli import parse
from baxterface_cli.core.face_constants import REST
from baxterface_cli.engine.compiler import compile_script
from baxterface_cli.language.diagnostics import ScriptError
from baxterface_cli.speech.soundtrack import write_wav
from baxterface_cli.speech.synthesis import Phoneme, Utterance
from baxterface_cli.speech.visemes import CLOSURES, mouth_track, shape_at
from conftest import baxterface

# One worker runs the module, so the recordings, and what is heard in them, are made once.
pytestmark = pytest.mark.xdist_group("recordings")

pytest.importorskip("av")
pytest.importorskip("pocketsphinx")

TEXT = "Bob met Pam. Mike paid a big bill."
VOICE, RATE = "en-gb", 150  # the bench speaks with others
PAD = 0.4  # seconds of quiet before and after the voice
FPS = 30


@pytest.fixture(scope="module")
def recorded(tmp_path_factory, engine):
    """(folder holding said.wav, the utterance as espeak-ng timed it, shifted to the file's times)."""
    folder = tmp_path_factory.mktemp("recorded")
    said = engine.say(TEXT, VOICE, RATE)
    rate = said.sample_rate
    quiet = np.zeros(round(PAD * rate))
    sound = np.concatenate([quiet, said.samples.astype(float), quiet])
    sound += np.random.default_rng(1).normal(0, 60, len(sound))  # about -50 dB under the voice's peaks
    write_wav(str(folder / "said.wav"), np.clip(sound, -32768, 32767).astype(np.int16), rate)
    phonemes = tuple(Phoneme(p.at + PAD, p.end + PAD, p.name) for p in said.phonemes)
    padded = np.concatenate([np.zeros(len(quiet), np.int16), said.samples, np.zeros(len(quiet), np.int16)])
    truth = Utterance(TEXT, VOICE, RATE, padded, rate, phonemes, ())
    return folder, truth


def said_from(folder, statement):
    (said,) = compile_script(parse(statement, str(folder / "talk.face"))).speech
    return said


@pytest.fixture(scope="module")
def aligned(recorded):
    folder, _ = recorded
    return said_from(folder, f'say file "said.wav" text "{TEXT}"')


@pytest.fixture(scope="module")
def heard(recorded):
    folder, _ = recorded
    return said_from(folder, 'say file "said.wav"')


def frames(track, duration):
    return [shape_at(track, (i + 0.5) / FPS)[0] for i in range(int(duration * FPS))]


def agreement(truth, track):
    """The share of the voice's frames where `track` shows the shape `say`'s mouth shows."""
    expected = mouth_track(truth)
    first, last = int(expected[0].at * FPS), int(expected[-1].at * FPS)
    pairs = list(zip(frames(expected, truth.duration), frames(track, truth.duration)))[first:last]
    return sum(a == b for a, b in pairs) / len(pairs)


def closures(truth):
    return [(p.at, p.end) for p in truth.phonemes if p.name in CLOSURES]


def test_a_recording_is_said_whole_at_its_time_with_its_words(recorded, aligned):
    folder, truth = recorded
    assert aligned.at == 0.0
    assert abs(aligned.utterance.duration - truth.duration) < 0.001
    assert aligned.utterance.samples[: round(PAD * truth.sample_rate)].any()  # its noise, as it is
    assert aligned.utterance.recording.method == "phonemes aligned to its words"
    assert aligned.utterance.recording.path == str(folder / "said.wav")
    words = [w.text for w in aligned.utterance.words]
    assert words == ["Bob", "met", "Pam", "Mike", "paid", "a", "big", "bill"]
    starts = [w.at for w in aligned.utterance.words]
    bob = next(p.at for p in truth.phonemes if p.name == "b")
    assert abs(starts[0] - bob) < 0.06 and starts == sorted(starts)


def test_the_aligned_mouth_is_the_mouth_say_shows_for_those_words(recorded, aligned):
    _, truth = recorded
    assert agreement(truth, aligned.mouth) >= 0.7


def test_p_b_and_m_close_the_lips_in_the_recording(recorded, aligned):
    _, truth = recorded
    for start, end in closures(truth):
        shown = frames(aligned.mouth, truth.duration)[int(start * FPS) - 1 : int(end * FPS) + 2]
        assert "closed" in shown, (start, end, shown)


@pytest.mark.parametrize("which", ["aligned", "heard"])
def test_the_mouth_rests_before_between_and_after_the_sentences(recorded, which, request):
    _, truth = recorded
    said = request.getfixturevalue(which)
    assert said.mouth[0].at >= PAD - 0.05 and said.mouth[-1].shape == REST
    assert said.mouth[-1].at <= truth.duration - PAD + 0.05
    pause = next(p for p in truth.phonemes if p.name.startswith("_") and p.end - p.at >= 0.2)
    assert shape_at(said.mouth, (pause.at + pause.end) / 2)[0] == REST


def without_words() -> str:
    """How a recording's phonemes are found without its words here: recognised by hama where it is
    installed (test_phonemes_heard.py holds it to the phoneme loop), else the phoneme loop's."""
    from baxterface_cli.speech import phoneme_recogniser

    return "phonemes recognised" if phoneme_recogniser.available() else "phonemes heard"


def test_without_its_words_the_mouth_follows_the_phonemes_heard(recorded, heard):
    _, truth = recorded
    assert heard.utterance.recording.method == without_words() and heard.utterance.words == ()
    assert agreement(truth, heard.mouth) >= 0.45
    shown = frames(heard.mouth, truth.duration)
    assert (
        sum(
            any(s == "closed" for s in shown[int(a * FPS) - 1 : int(b * FPS) + 2]) for a, b in closures(truth)
        )
        >= 3
    )


def test_another_language_without_hama_follows_the_loudness_and_spectrum(recorded, monkeypatch):
    from baxterface_cli.speech import phoneme_recogniser

    folder, truth = recorded
    monkeypatch.setattr(phoneme_recogniser, "available", lambda: False)
    said = said_from(folder, 'say file "said.wav" language fr')
    assert said.utterance.recording.method == "loudness and spectrum" and said.utterance.voice == "fr"
    shapes = {key.shape for key in said.mouth}
    assert len(shapes) >= 4 and said.mouth[-1].shape == REST
    pause = next(p for p in truth.phonemes if p.name.startswith("_") and p.end - p.at >= 0.2)
    assert shape_at(said.mouth, (pause.at + pause.end) / 2)[0] == REST


def test_the_analysis_is_kept_by_content_and_read_back(recorded, aligned, monkeypatch):
    folder, _ = recorded
    kept = list((Path(os.environ["XDG_CACHE_HOME"]) / "baxterface" / "lipsync").glob("*.json"))
    assert kept and all(str(k).startswith(os.environ["XDG_CACHE_HOME"]) for k in kept)
    # The same content under another name: found by its content, nothing heard again.
    shutil.copy(folder / "said.wav", folder / "copy.wav")
    from baxterface_cli.speech import phones_heard

    monkeypatch.setattr(phones_heard, "hear", lambda *a, **k: pytest.fail("analysed again"))
    again = said_from(folder, f'say file "copy.wav" text "{TEXT}"')
    assert again.mouth == aligned.mouth and again.utterance.words == aligned.utterance.words


def test_a_new_text_for_a_recording_is_aligned_and_nothing_else_found_again(recorded, tmp_path, monkeypatch):
    """The studio compiles its script at every press: a new `text` for the same recording is aligned
    anew, but the recording is read, and what its sound says without words found, once."""
    from baxterface_cli.speech import phones_heard, recordings

    folder, _ = recorded
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))  # nothing kept on disk
    monkeypatch.setattr(recordings, "_recent", OrderedDict())  # nor in memory
    calls = Counter()

    def counted(name, function):
        def counting(*args, **kwargs):
            calls[name] += 1
            return function(*args, **kwargs)

        return counting

    monkeypatch.setattr(recordings, "read_sound", counted("read", recordings.read_sound))
    monkeypatch.setattr(phones_heard, "hear", counted("heard without words", phones_heard.hear))
    wrong = ["Completely different words are written here by mistake.", "Other words nobody said at all."]
    said = [
        said_from(folder, f'say file "said.wav" text "{text}"') for text in [TEXT, *wrong, "Bob met Pam."]
    ]
    assert calls == {"read": 1, "heard without words": 1}
    assert said[1].utterance.recording.method == said[2].utterance.recording.method == without_words()
    assert said[1].mouth == said[2].mouth and said[3].utterance.words != said[0].utterance.words
    assert said_from(folder, f'say file "said.wav" text "{TEXT}"').mouth == said[0].mouth
    assert calls == {"read": 1, "heard without words": 1}


# -- files ------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def formats(recorded):
    folder, _ = recorded
    wav = str(folder / "said.wav")
    subprocess.run(["sox", wav, str(folder / "said.flac")], check=True)
    subprocess.run(["sox", wav, str(folder / "said.ogg")], check=True)
    subprocess.run(["ffmpeg", "-v", "error", "-y", "-i", wav, str(folder / "said.mp3")], check=True)
    return folder


@pytest.mark.parametrize("ext", ["flac", "ogg", "mp3"])
def test_flac_ogg_and_mp3_are_read_as_the_wav_is(recorded, formats, ext):
    from baxterface_cli.speech.audio_files import read_sound

    _, truth = recorded
    wav, other = read_sound(str(formats / "said.wav")), read_sound(str(formats / f"said.{ext}"))
    assert abs(other.duration - wav.duration) < 0.06
    n = min(len(wav.analysis), len(other.analysis))
    a, b = wav.analysis[:n].astype(float), other.analysis[:n].astype(float)
    lags = range(-1200, 1201, 10)  # an MP3 encoder's delay is a few hundred samples at most
    best = max(np.dot(a[max(0, -k) : n - max(0, k)], b[max(0, k) : n - max(0, -k)]) for k in lags)
    assert best / np.sqrt(np.dot(a, a) * np.dot(b, b)) > 0.9


def test_check_names_a_missing_or_unreadable_recording_where_it_is(recorded, tmp_path):
    folder, _ = recorded
    script = folder / "check.face"
    script.write_text('happy\nsay file "said.wav"\nsay file "gone.wav" text "Hi"\nsay file "check.face"\n')
    run = baxterface("check", str(script), cwd=tmp_path)  # paths are the script's folder's
    assert run.code == 1
    lines = [line for line in run.err.splitlines() if ": error: " in line]
    assert lines == [
        f"{script}:3:10: error: cannot read recording 'gone.wav': no such file",
        f"{script}:4:10: error: cannot read recording 'check.face': not a sound file FFmpeg reads "
        "(invalid data found when processing input)",
    ]
    run = baxterface("check", "-", stdin='say file "said.wav"\n', cwd=folder)  # stdin: the current folder
    assert (run.code, run.err) == (0, "")
    run = baxterface("check", "-", stdin='say file "said.wav"\n', cwd=tmp_path)
    assert run.code == 1 and "<stdin>:1:10: error: cannot read recording 'said.wav': no such file" in run.err


def test_render_puts_the_recording_in_the_sound_track_at_its_time(recorded, aligned, tmp_path):
    folder, truth = recorded
    out = tmp_path / "x.wav"
    run = baxterface("render", "-e", f'wait 0.5s; say file "{folder / "said.wav"}"', "--out", str(out))
    assert run.code == 0, run.err
    with wave.open(str(out)) as w:
        rate, sound = w.getframerate(), np.frombuffer(w.readframes(w.getnframes()), np.int16)
    start = round(0.5 * rate)
    assert rate == truth.sample_rate and len(sound) == start + len(aligned.utterance.samples)
    assert np.array_equal(sound[start:], aligned.utterance.samples) and not sound[:start].any()


def test_explain_names_the_recording_and_its_words(recorded, aligned):
    folder, _ = recorded
    (folder / "talk.face").write_text(f'say file "said.wav" text "{TEXT}"\n')
    run = baxterface("explain", str(folder / "talk.face"))
    assert run.code == 0, run.err
    line = next(line for line in run.out.splitlines() if "robot" in line)
    assert line.endswith(
        f'robot say file "said.wav" text "{TEXT}" ({aligned.utterance.duration:.2f} s, '
        "phonemes aligned to its words)"
    )
    words = [line.split()[-1] for line in run.out.splitlines() if " word " in line]
    assert words == ["Bob", "met", "Pam", "Mike", "paid", "a", "big", "bill"]
    frames_json = baxterface("explain", "--json", str(folder / "talk.face")).out.splitlines()
    saying = {json.loads(f)["saying"] for f in frames_json}
    assert TEXT in saying


# -- where a recording may be read from ---------------------------------------------------------------


def test_a_confined_folder_refuses_paths_that_leave_it(recorded, tmp_path):
    from baxterface_cli.speech.recordings import RecordingError, Recordings

    folder, _ = recorded
    (tmp_path / "escape.wav").symlink_to(folder / "said.wav")
    here = Recordings(tmp_path, confined=True)
    for written in ("../said.wav", str(folder / "said.wav"), "escape.wav"):
        with pytest.raises(RecordingError, match="outside .* the folder recordings are read from"):
            here.path(written)
    inside = Recordings(folder, confined=True)
    assert inside.path("said.wav") == os.path.realpath(folder / "said.wav")
    nowhere = Recordings(
        None, refusal="this face node reads no recordings; start it with _recordings:=FOLDER"
    )
    with pytest.raises(RecordingError, match="start it with _recordings:=FOLDER"):
        nowhere.path("said.wav")


def test_the_live_face_reads_no_recording_unless_given_a_folder(recorded):
    from baxterface_cli.core.face_state import FaceState
    from baxterface_cli.engine.live_face import LiveFace
    from baxterface_cli.engine.live_session import LiveSession
    from baxterface_cli.engine.session_intake import SessionIntake
    from baxterface_cli.language.parser import parse
    from baxterface_cli.speech.recordings import Recordings
    from waiting import eventually

    folder, _ = recorded
    with pytest.raises(Exception, match="reads no recordings"):
        LiveFace(idle=False).prepare(parse('say file "said.wav"', "display_chatter"), FaceState())
    session = LiveSession(idle=False, recordings=Recordings(folder, confined=True))
    logged = []
    with SessionIntake(session, lambda: 0.0, log=lambda level, text: logged.append(text)) as intake:
        intake.submit(f'say file "{folder}/../said.wav"')
        eventually(lambda: logged)
        assert "outside" in logged[0]
        assert logged[0].startswith("bad command: display_chatter:1:10: error: recording"), logged
        intake.submit('say file "said.wav"')
        eventually(lambda: intake.idle() and session.face.timeline.speech)
        (said,) = session.face.timeline.speech
    assert said.utterance.recording.name == "said.wav"


def test_a_bag_asks_sound_play_to_play_the_recording_file(aligned):
    from baxterface_cli.engine.effects import Speech
    from baxterface_cli.ros.effect_messages import SOUND_PLAY_FILE, SOUND_TOPIC, ros_commands

    (command,) = ros_commands(Speech(aligned.utterance))
    assert command.topic == SOUND_TOPIC
    assert (command.fields["sound"], command.fields["arg"]) == (
        SOUND_PLAY_FILE,
        aligned.utterance.recording.path,
    )


# -- without the extra ---------------------------------------------------------------------------------


def blocked_env(tmp_path, module):
    """An environment whose Python cannot import `module`, as where it is not installed."""
    site = tmp_path / f"no_{module}"
    (site / module).mkdir(parents=True, exist_ok=True)
    (site / module / "__init__.py").write_text(f"raise ImportError('No module named {module}')\n")
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(site), env.get("PYTHONPATH", "")]))
    return env


def test_without_pocketsphinx_the_mouth_follows_the_sound_after_one_line_naming_the_extra(recorded, tmp_path):
    folder, _ = recorded
    out = tmp_path / "x.wav"
    script = 'say file "said.wav"; say file "said.wav" text "Bob"'
    run = baxterface(
        "render", "-e", script, "--out", str(out), cwd=folder, env=blocked_env(tmp_path, "pocketsphinx")
    )
    assert run.code == 0 and out.exists()
    assert run.err.splitlines() == [
        "baxterface: lip-sync from a recording hears its phonemes with pocketsphinx: "
        "pip install 'baxterface[lipsync]'; the mouth follows its loudness and spectrum instead",
        f"wrote {out} (6.98 s)",
    ]


def test_without_pyav_a_recording_is_one_line_naming_the_extra(recorded, tmp_path):
    folder, _ = recorded
    out = tmp_path / "x.mp4"
    run = baxterface(
        "render", "-e", 'say file "said.wav"', "--out", str(out), cwd=folder, env=blocked_env(tmp_path, "av")
    )
    assert run.code == 1 and not out.exists(), run.err
    assert run.err.splitlines()[0] == (
        "<-e>:1:10: error: cannot read recording 'said.wav': "
        "reading a recording needs the 'av' module: pip install 'baxterface[lipsync]'"
    )
    run = baxterface(
        "check",
        "-",
        stdin='say file "said.wav"\nsay file "gone.wav"\n',
        cwd=folder,
        env=blocked_env(tmp_path, "av"),
    )
    # `check` refuses what `render` could not read, where it is named.
    assert run.code == 1 and "<stdin>:1:10: error: cannot read recording 'said.wav': reading" in run.err
    assert "<stdin>:2:10: error: cannot read recording 'gone.wav': no such file" in run.err


def test_a_bad_say_file_is_reported_where_it_is():
    with pytest.raises(ScriptError) as caught:
        parse('say file "a.wav" voice en\nsay "Hi" text "Hello"\nsay file ""')
    assert [(d.line, d.column, d.message) for d in caught.value.errors] == [
        (1, 18, "a recording has its own voice and rate: 'say file' takes no 'voice'"),
        (2, 10, "'text' is for a recording: say file \"NAME\" text ..."),
        (3, 10, "no recording named: the file name is empty"),
    ]


def test_a_recordings_words_may_be_ten_minutes_long_not_more():
    words = "word " * 1500  # past a say's 1000 characters
    (say,) = parse(f'say file "a.wav" text "{words}"').body
    assert say.text == words
    with pytest.raises(ScriptError, match="too much to say at once .15001 characters; the limit is 10000"):
        parse(f'say file "a.wav" text "{words * 2}x"')


def test_words_that_do_not_fit_the_sound_are_let_go_for_the_phonemes_heard(recorded):
    folder, _ = recorded
    said = said_from(
        folder, 'say file "said.wav" text "Completely different words are written here by mistake."'
    )
    assert said.utterance.recording.method == without_words() and said.utterance.words == ()
    assert said.mouth and said.mouth[-1].shape == REST


def test_a_video_carries_the_recording_as_its_sound_track(recorded, aligned, tmp_path):
    import av

    folder, _ = recorded
    out = tmp_path / "x.mp4"
    run = baxterface("render", "-e", 'say file "said.wav"', "--out", str(out), "--fps", "5", cwd=folder)
    assert run.code == 0, run.err
    with av.open(str(out)) as container:
        stream = container.streams.audio[0]
        sound = np.concatenate([frame.to_ndarray().mean(axis=0) for frame in container.decode(stream)])
        rate = stream.rate
    duration = aligned.utterance.duration
    assert abs(len(sound) / rate - duration) < 0.1  # AAC pads a frame or two
    # Loud where the recording is loud: its voice, 0.4 s in, not its quiet start.
    level = [float(np.sqrt(np.mean(sound[int(a * rate) : int((a + 0.2) * rate)] ** 2))) for a in (0.1, 1.0)]
    assert level[1] > 20 * level[0]
