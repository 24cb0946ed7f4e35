"""Speech from espeak-ng: the sound, and phoneme and word times that keep to it.

These use the real espeak-ng and skip without it, except on CI (CI=true), where
a missing espeak-ng is a failure.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import re
import shutil
import subprocess
import threading

import numpy as np
import pytest

from baxterface_cli.core.voices import NATURAL_VOICES, voice_languages
from baxterface_cli.extras import MissingTool
from baxterface_cli.resources import resource
from baxterface_cli.speech import espeak
from baxterface_cli.speech import synthesis as speech
from baxterface_cli.speech.synthesis import RATES, VOICES, Utterance, known_voice
from conftest import baxterface

HELLO = "Hello. World."


def rms(u: Utterance, start: float, end: float) -> float:
    piece = u.samples[round(start * u.sample_rate) : round(end * u.sample_rate)].astype(np.float64)
    return float(np.sqrt(np.mean(piece * piece))) if len(piece) else 0.0


def test_duration_grows_with_the_text_and_shrinks_with_the_rate(engine):
    short = engine.say("Hello there.")
    longer = engine.say("Hello there. How are you today, my friend?")
    assert 0.3 < short.duration < longer.duration
    slow, normal, fast = (engine.say("Hello there, my friend.", rate=r) for r in (80, 175, 400))
    assert slow.duration > 1.5 * normal.duration > 2.0 * fast.duration
    assert normal.duration == pytest.approx(len(normal.samples) / normal.sample_rate)
    assert normal.sample_rate == 22050 and normal.samples.dtype == np.int16


def test_phonemes_follow_each_other_in_time_within_the_sound(engine):
    for rate in (80, 175, 400):
        u = engine.say("The quick brown fox jumps over the lazy dog. Then it sleeps.", rate=rate)
        assert len(u.phonemes) > 20
        assert u.phonemes[0].at >= 0 and u.phonemes[-1].end == pytest.approx(u.duration)
        for p, after in zip(u.phonemes, u.phonemes[1:]):
            assert 0 <= p.at < p.end == after.at <= u.duration


def test_silence_is_trimmed_to_the_voice_and_the_times_move_with_it(engine):
    u = engine.say(HELLO)
    loud = np.flatnonzero(np.abs(u.samples.astype(np.int32)) > speech.TRIM.threshold)
    keep = round(speech.TRIM.keep * u.sample_rate)
    assert loud[0] <= keep and len(u.samples) - 1 - loud[-1] <= keep
    # The first phoneme, an "h", starts where the sound does.
    assert u.phonemes[0].name == "h"
    assert u.phonemes[0].at == pytest.approx(loud[0] / u.sample_rate, abs=0.005)


@pytest.mark.parametrize("rate", [80, 175, 300])
def test_a_pause_phoneme_sits_on_silence_and_the_vowels_on_sound(engine, rate):
    # The core promise: a mouth drawn from these times cannot drift from the voice.
    slack = 0.002
    u = engine.say(HELLO, rate=rate)
    loudness = rms(u, 0, u.duration)
    pauses = [p for p in u.phonemes if p.name == "_:" and p.end - p.at >= 0.03 + 2 * slack]
    assert pauses, [(p.name, p.end - p.at) for p in u.phonemes]
    for p in pauses:
        assert rms(u, p.at + slack, p.end - slack) < 0.01 * loudness, p
    vowels = [p for p in u.phonemes if p.name in ("@", "oU", "3:")]
    assert len(vowels) == 3
    for p in vowels:
        assert rms(u, p.at + slack, p.end - slack) > 0.3 * loudness, p


def test_at_the_top_rate_the_times_are_still_close(engine):
    # At the top rate the pauses are short, and their middles still silent.
    u = engine.say("Hello. World. The quick brown fox. It jumps.", rate=400)
    loudness = rms(u, 0, u.duration)
    pauses = [p for p in u.phonemes if p.name == "_:" and p.end - p.at >= 0.02]
    assert len(pauses) == 3
    for p in pauses:
        middle = (p.at + p.end) / 2
        assert rms(u, middle - 0.005, middle + 0.005) < 0.01 * loudness, p


def test_words_come_back_as_written_in_order(engine):
    text = 'The café costs $5, "she" said; e-mail 1234 people! Hi 😀 there.'
    u = engine.say(text)
    assert [w.text for w in u.words] == [
        "The",
        "café",
        "costs",
        "$5",
        "she",
        "said",
        "e-mail",
        "1234",
        "people",
        "Hi",
        "😀",
        "there",
    ]
    times = [w.at for w in u.words]
    assert times == sorted(times) and len(set(times)) == len(times)
    # Each word starts with one of its sounds.
    starts = {p.at for p in u.phonemes}
    assert all(t in starts for t in times)


def test_a_word_espeak_runs_into_its_neighbour_still_comes_back(engine):
    # espeak-ng reports no word event for the "am" of "I am a robot".
    for rate in (80, 175, 300):
        u = engine.say("I am a robot -- ... and you?", rate=rate)
        assert [w.text for w in u.words] == ["I", "am", "a", "robot", "and", "you"]
        times = [w.at for w in u.words]
        assert times == sorted(times) and len(set(times)) == len(times)


def test_bob_met_pam_closes_the_lips(engine):
    names = [p.name for p in engine.say("Bob met Pam").phonemes]
    assert {"b", "m", "p"} <= set(names)
    assert names.count("b") == 2 and names.count("m") == 2


def test_an_unknown_voice_or_rate_is_refused(engine):
    with pytest.raises(ValueError, match=r"unknown voice 'xx-nonsense'"):
        engine.say("Hello", voice="xx-nonsense")
    with pytest.raises(ValueError, match=r"did you mean 'en-us'"):
        engine.say("Hello", voice="en-uz")
    for rate in (RATES[0] - 1, RATES[1] + 1, 100.5):
        with pytest.raises(ValueError, match="words a minute"):
            engine.say("Hello", rate=rate)
    assert engine.say("Hello", voice="EN-GB").voice == "en-gb"


def test_the_same_request_gives_the_same_sound(engine):
    first = engine._synthesize("Deterministic, please.", "en-us", 200)
    engine._synthesize("Something else in between.", "de", 300)
    second = engine._synthesize("Deterministic, please.", "en-us", 200)
    assert np.array_equal(first.samples, second.samples)
    assert first == second and hash(first) == hash(second)
    # Repeats come from the cache, read-only.
    assert engine.say("Cached.") is engine.say("Cached.")
    assert not engine.say("Cached.").samples.flags.writeable


def test_threads_take_turns(engine):
    texts = [f"Thread number {i} is talking." for i in range(4)]
    alone = [engine._synthesize(t, "en", 175) for t in texts]
    together = [None] * len(texts)

    def run(i):
        together[i] = engine._synthesize(texts[i], "en", 175)

    threads = [threading.Thread(target=run, args=(i,)) for i in range(len(texts))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for a, b in zip(alone, together):
        assert np.array_equal(a.samples, b.samples) and a.phonemes == b.phonemes


def test_nothing_to_say_is_no_sound(engine):
    for text in ("", "   ", "\0"):
        u = engine.say(text)
        assert u.duration == 0 and u.phonemes == () and u.words == ()


def test_other_languages_speak(engine):
    for voice in ("de", "fr-fr", "es", "zh"):
        u = engine.say("Guten Tag, bonjour, hola.", voice=voice)
        assert u.duration > 0.5 and u.phonemes and u.voice == voice


def test_the_carried_voices_are_known_without_an_engine():
    assert {"en", "en-gb", "en-us", "de", "fr-fr"} <= VOICES
    assert known_voice("EN-US") and known_voice("en") and not known_voice("xx-nonsense")
    lines = resource("data/voices.txt").read_text(encoding="utf-8").splitlines()
    names = [line.split()[0] for line in lines if line and not line.startswith("#")]
    assert names == sorted(set(names)) and all(n == n.lower() for n in names)
    assert frozenset(names) == VOICES
    # Each with its language, as `baxterface voices` shows it.
    assert voice_languages()["en-us"] == "English (America)" and voice_languages()["de"] == "German"
    assert all(voice_languages().values())


def test_voices_says_each_language_and_finds_them_by_code_or_name():
    run = baxterface("voices", "en")
    assert run.code == 0, run.err
    rows = [line.split(None, 1) for line in run.out.splitlines()]
    assert ["en-us", "English (America)"] in rows and ["en-gb-scotland", "English (Scotland)"] in rows
    assert all(name == "en" or name.startswith("en-") or name in NATURAL_VOICES for name, _ in rows)
    spanish = baxterface("voices", "Spanish").out.split()
    assert {"es", "es-419"} <= set(spanish) and "en" not in spanish
    assert len(baxterface("voices").out.splitlines()) == len(VOICES) + len(NATURAL_VOICES)  # and natural ones
    nothing = baxterface("voices", "elvish")
    assert nothing.code == 1 and nothing.out == "" and "no voice speaks 'elvish'" in nothing.err


def listed_voices() -> set:
    """Voice names as data/voices.txt is made from `espeak-ng --voices`, before they are tried."""
    listing = subprocess.run(["espeak-ng", "--voices"], capture_output=True, text=True, check=True).stdout
    names = set()
    for line in listing.splitlines()[1:]:
        _, language, _, _, file, *others = line.split()
        names |= {language, file.rsplit("/", 1)[-1]}
        names |= set(re.findall(r"\(([^ )]+)", " ".join(others)))
    return {n.lower() for n in names}


def test_espeak_ng_accepts_every_carried_voice(engine):
    files = {voice: engine.voice_file(voice) for voice in sorted(VOICES)}  # raises for any it lacks
    assert files["en"] == "gmw/en" and files["en-us"] == "gmw/en-US" and files["fr-fr"] == "roa/fr"
    with pytest.raises(ValueError):
        engine.voice_file("xx-nonsense")


@pytest.mark.one_python  # a hundred runs of the espeak-ng program: the same under every Python
def test_the_engine_takes_the_voices_the_espeak_ng_program_takes(engine):
    if shutil.which("espeak-ng") is None:
        pytest.skip("the espeak-ng program is not installed, only its library")
    listed = listed_voices() | {"xx-nonsense"}
    said = {
        name
        for name in listed
        if subprocess.run(["espeak-ng", "-v", name, "-q", ""], capture_output=True).returncode == 0
    }
    taken = set()
    for name in listed:
        try:
            engine.voice_file(name)
            taken.add(name)
        except ValueError:
            pass
    assert taken == said
    # And data/voices.txt is what this espeak-ng makes of it, when it is the one it was made with.
    made_with = re.search(r"espeak-ng (\d[\w.]*)", resource("data/voices.txt").read_text(encoding="utf-8"))
    if made_with and espeak.espeak_version() == made_with.group(1):
        assert said == VOICES


def test_the_event_struct_matches_speak_lib_h():
    pointer = ctypes.sizeof(ctypes.c_void_p)
    assert espeak._Event.user_data.offset == 24
    assert espeak._Event.id.offset == 24 + pointer
    assert ctypes.sizeof(espeak._Event) == 24 + pointer + max(8, pointer)


def test_without_the_library_the_error_says_how_to_install_it(monkeypatch):
    monkeypatch.setattr(ctypes.util, "find_library", lambda name: None)
    monkeypatch.setattr(espeak, "_LIBRARY_NAMES", ("libespeak-ng-is-not-here.so.1",))
    monkeypatch.setattr(espeak, "_found", None)
    # As the speech process finds the library (a whole engine's, without it: test_say.py).
    with pytest.raises(MissingTool, match="apt install espeak-ng"):
        espeak.espeak_library()
