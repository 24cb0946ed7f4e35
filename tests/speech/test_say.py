"""`say`: the language, the timeline it makes, and what `explain`, `check` and `render` do with it.

Speech comes from the real espeak-ng; the mouth-shape rules have their own
tests (test_visemes.py), and the lip-sync measured in an exported video is in
test_lipsync.py.
"""

from __future__ import annotations

import json
import re
import wave

import numpy as np
import pytest

from baxterface_cli import ScriptError, parse
from baxterface_cli.core.face_constants import LIMITS, VISEMES, viseme_mouth
from baxterface_cli.engine.compiler import compile_script
from baxterface_cli.engine.effects import Speech
from baxterface_cli.language import syntax_tree as n
from conftest import baxterface

SPEECH_MOUTHS = {viseme_mouth(shape) for shape in VISEMES}


def body(text):
    return parse(text, "t.face").body


def errors(text):
    with pytest.raises(ScriptError) as caught:
        parse(text, "t.face")
    return [(d.line, d.column, d.message) for d in caught.value.errors]


# -- the language ----------------------------------------------------------


def test_say_takes_text_and_optional_voice_and_rate():
    assert body('say "Hello there, I am Baxter."') == (n.Say("Hello there, I am Baxter."),)
    assert body('say "Hi" voice en-GB rate 150') == (n.Say("Hi", "en-gb", 150),)
    assert body('SAY "Hi" rate 150wpm voice en-us') == (n.Say("Hi", "en-us", 150),)


def test_strings_take_escaped_quotes_and_backslashes():
    (said,) = body(r'say "She said \"hi\" \\ left"')
    assert said.text == 'She said "hi" \\ left'


def test_braces_and_hashes_in_a_string_are_text():
    script = parse('repeat 2 {\n  say "a {brace} # and a hash"\n}\nblink', "t.face")
    (repeat, blink) = script.body
    assert repeat.body == (n.Say("a {brace} # and a hash"),)
    assert blink == n.Blink()


def test_say_is_a_statement_like_any_other():
    script = parse('happy\ntogether {\n  say "Hi"\n  look left in 1s\n}\nsay "Bye"', "t.face")
    assert [type(s).__name__ for s in script.body] == ["Emotion", "Together", "Say"]


@pytest.mark.parametrize(
    "text, expected",
    [
        ('say "Hello', (1, 5, "unterminated string: it needs a closing '\"' on the same line")),
        ('blink\nsay ""', (2, 5, "nothing to say: the text is empty")),
        ('say "   "', (1, 5, "nothing to say: the text is empty")),
        ('say "Hi" voice klingon', (1, 16, "unknown voice 'klingon'; 'baxterface voices' lists them")),
        ('say "Hi" voice en-bg', (1, 16, "unknown voice 'en-bg'; did you mean 'en-gb'?")),
        ('say "Hi" rate 20', (1, 15, "a speech rate must be a whole number from 80 to 400, not 20")),
        ('say "Hi" rate 150s', (1, 18, "unknown unit 's' for a speech rate; a speech rate takes 'wpm'")),
        ('say "a\\tb"', (1, 7, "unknown escape '\\t'; write \\\" or \\\\")),
        ('say "Hi" rate 100 rate 120', (1, 1, "'say' takes one 'rate'")),
        ("say hello", (1, 5, "unexpected 'hello'; expected 'file' or a string in double quotes")),
    ],
)
def test_bad_say_statements_are_reported_where_they_are(text, expected):
    assert errors(text)[0] == expected


def test_a_long_text_is_refused_before_anything_speaks_it():
    text = "word " * (LIMITS.max_say // 5 + 1)
    (error,) = errors(f'say "{text}"')
    assert error[:2] == (1, 5) and "too much to say at once" in error[2]


def test_check_needs_no_speech_engine(tmp_path):
    """`check` never loads the engine: with espeak-ng unloadable it passes a good script."""
    script = tmp_path / "talk.face"
    script.write_text('say "Hello" voice en-gb rate 150\n', encoding="utf-8")
    run = baxterface("check", str(script), env=no_espeak_env(tmp_path))
    assert (run.code, run.out, run.err) == (0, "", "")
    run = baxterface("check", "-", stdin='say "Hi" voice klingon\n', env=no_espeak_env(tmp_path))
    assert run.code == 1 and "<stdin>:1:16: error: unknown voice 'klingon'" in run.err


def test_without_espeak_ng_render_says_how_to_install_it(tmp_path):
    out = tmp_path / "x.mp4"
    run = baxterface("render", "-e", 'say "Hi"', "--out", str(out), env=no_espeak_env(tmp_path))
    assert run.code == 1
    assert run.err.count("\n") == 1 and "espeak-ng" in run.err and "apt install" in run.err, run.err
    assert not out.exists()


def no_espeak_env(tmp_path):
    """An environment whose Python cannot load the espeak-ng library, as on a machine without it."""
    import os

    site = tmp_path / "no_espeak"
    site.mkdir(exist_ok=True)
    (site / "sitecustomize.py").write_text(
        "import ctypes, ctypes.util\n"
        "_load, _find = ctypes.CDLL.__init__, ctypes.util.find_library\n"
        "def _init(self, name, *a, **k):\n"
        "    if name and 'espeak' in str(name):\n"
        "        raise OSError(f'{name}: cannot open shared object file')\n"
        "    _load(self, name, *a, **k)\n"
        "ctypes.CDLL.__init__ = _init\n"
        "ctypes.util.find_library = lambda name: None if 'espeak' in name else _find(name)\n",
        encoding="utf-8",
    )
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(site), env.get("PYTHONPATH", "")]))
    return env


# -- the timeline (real espeak-ng) ------------------------------------------

speech = pytest.importorskip("baxterface_cli.speech.synthesis")


def test_say_lasts_as_long_as_its_speech(engine):
    timeline = compile_script(parse('say "Hello there, I am Baxter."'))
    utterance = engine.say("Hello there, I am Baxter.")
    assert timeline.duration == pytest.approx(utterance.duration)
    (cue,) = timeline.cues
    assert cue.at == 0 and isinstance(cue.effect, Speech) and cue.effect.utterance.text == utterance.text


def test_together_runs_speech_beside_moves(engine):
    said = engine.say("Hi").duration
    timeline = compile_script(parse('together { say "Hi"; look left in 1s }; blink'))
    assert said < 1.0
    assert timeline.duration == pytest.approx(1.0 + 0.5)  # the look, then the blink
    long = compile_script(parse('together { say "Hello there, I am Baxter."; look left in 0.2s }'))
    assert long.duration == pytest.approx(engine.say("Hello there, I am Baxter.").duration)


def test_the_mouth_speaks_then_returns_to_the_emotions_mouth(engine):
    timeline = compile_script(parse('happy; wait 0.5s; say "Hello there, I am Baxter."; wait 1s'))
    (said,) = timeline.speech
    mouths = [timeline.sample(said.at + k * 0.01).mouth for k in range(int(said.utterance.duration * 100))]
    assert set(mouths) & SPEECH_MOUTHS and len(set(mouths) & SPEECH_MOUTHS) >= 3
    happy = timeline.sample(said.at - 0.01)
    after = timeline.sample(said.end + 0.05)
    assert after.mouth == happy.mouth and happy.mouth not in SPEECH_MOUTHS
    assert timeline.sample(said.at).mouth not in SPEECH_MOUTHS  # no shape before the voice starts


def test_the_rest_of_the_face_goes_on_while_speaking(engine):
    timeline = compile_script(
        parse('sad; together { say "Hello there, I am Baxter."; look left in 1s; blink }')
    )
    start = timeline.speech[0].at
    moving = [timeline.sample(start + k * 0.1) for k in range(11)]
    assert moving[0].eye_x < moving[5].eye_x < moving[10].eye_x  # eyes on the move
    assert min(s.eyelids for s in moving) < 0.5  # a blink
    assert {s.skin for s in moving} == {1} and {s.brows for s in moving} == {"worried"}


# -- explain, render ------------------------------------------------------


def test_explain_lists_the_words_with_their_times(engine):
    run = baxterface("explain", "-e", 'happy; say "Hello there, I am Baxter." voice en-gb')
    assert run.code == 0, run.err
    words = re.findall(r"^\s+([\d.]+) s\s+word\s+(\S+)$", run.out, re.MULTILINE)
    # As espeak-ng reports them: each as written, less its punctuation; a word it
    # speaks as one with the next ("I am") comes once.
    said = [w for _, w in words]
    assert said[0] == "Hello" and said[-1] == "Baxter" and "there" in said
    assert set(said) <= {"Hello", "there", "I", "am", "Baxter"}
    times = [float(t) for t, _ in words]
    assert times == sorted(times) and times[0] >= 0.3  # after the emotion's 0.3 s
    assert re.search(
        r'robot say "Hello there, I am Baxter\." \([\d.]+ s, voice en-gb, 175 words a minute\)', run.out
    )


def test_explain_json_gives_the_mouth_shape_and_what_is_said(engine):
    run = baxterface("explain", "--json", "-e", 'say "Bob met Pam."; wait 0.2s')
    assert run.code == 0, run.err
    frames = [json.loads(line) for line in run.out.splitlines()]
    assert {f["mouth"] for f in frames} & SPEECH_MOUTHS >= {viseme_mouth("closed")}
    assert {f["saying"] for f in frames} == {"Bob met Pam.", None}


def test_render_wav_writes_the_speech_alone(tmp_path, engine):
    out = tmp_path / "hi.wav"
    run = baxterface("render", "-e", 'wait 0.5s; say "Hello there."', "--out", str(out))
    assert run.code == 0, run.err
    utterance = engine.say("Hello there.")
    with wave.open(str(out)) as w:
        assert (w.getnchannels(), w.getsampwidth(), w.getframerate()) == (1, 2, utterance.sample_rate)
        samples = np.frombuffer(w.readframes(w.getnframes()), "<i2")
    assert len(samples) / utterance.sample_rate == pytest.approx(0.5 + utterance.duration, abs=0.001)
    start = round(0.5 * utterance.sample_rate)
    assert not samples[: start - 10].any()  # silence through the wait
    assert np.array_equal(samples[start : start + len(utterance.samples)], utterance.samples)


@pytest.mark.parametrize("ext, codec", [(".mp4", "aac"), (".webm", "opus")])
def test_videos_carry_the_speech(tmp_path, engine, ext, codec):
    av = pytest.importorskip("av")
    out = tmp_path / f"hi{ext}"
    run = baxterface("render", "-e", 'say "Hello there."; wait 0.2s', "--out", str(out), "--size", "256x150")
    assert run.code == 0, run.err
    with av.open(str(out)) as container:
        (audio,) = container.streams.audio
        assert audio.codec_context.name == codec
        frames = list(container.decode(audio=0))
    heard = sum(f.samples for f in frames) / audio.rate
    sound = np.concatenate([f.to_ndarray().reshape(-1) for f in frames])
    assert heard == pytest.approx(engine.say("Hello there.").duration + 0.2, abs=0.1)
    assert np.abs(sound).max() > 0.1
