"""Mouth shapes from real espeak-ng utterances: in time with the sound, and never a flicker.

The pauses and loudness here are measured from the samples, apart from the
track's own code. Without espeak-ng these skip, except on CI (CI=true).
"""

from __future__ import annotations

from typing import List, Tuple

import numpy as np
import pytest

from baxterface_cli.core.face_constants import REST, VISEMES
from baxterface_cli.speech.synthesis import Phoneme, Utterance, Word
from baxterface_cli.speech.visemes import (
    CLOSURES,
    MOUTH_RULES,
    PHONEME_SHAPES,
    SHAPE_POSITIONS,
    MouthKey,
    mouth_track,
    phoneme_shape,
    shape_at,
)

FRAME = 1 / 30  # the face's frame rate: what "in time" is measured in
RATES = (80, 175, 300, 400)
SENTENCES = (
    "Bob met Pam",
    "Hello, world. How are you?",
    "The quick brown fox jumps over the lazy dog. Pack my box with five dozen liquor jugs!",
    "Maybe, maybe not; I'm a robot, my name is Baxter, and I am happy to meet you.",
)


def silences(
    u: Utterance, least: float, window: float = 0.01, level: float = 30.0
) -> List[Tuple[float, float]]:
    """(start, end) of the stretches of at least `least` seconds whose 10 ms windows are silent."""
    width = round(window * u.sample_rate)
    window = width / u.sample_rate
    count = len(u.samples) // width
    frames = u.samples[: count * width].astype(np.float64).reshape(count, width)
    quiet = np.sqrt((frames * frames).mean(axis=1)) < level
    found, start = [], None
    for i, q in enumerate(list(quiet) + [False]):
        if q and start is None:
            start = i
        elif not q and start is not None:
            if (i - start) * window >= least:
                found.append((start * window, i * window))
            start = None
    return found


def fully(track, t) -> str:
    """The shape at t, or "" during a tween."""
    shape, tween_from, progress = shape_at(track, t)
    return shape if tween_from is None or progress >= 1.0 else ""


def steps(start: float, end: float, step: float = 0.001) -> np.ndarray:
    return np.arange(start, end, step)


def closed_runs(track, start: float, end: float) -> List[Tuple[float, float]]:
    """The stretches, to the millisecond, when the mouth is fully closed."""
    runs: List[Tuple[float, float]] = []
    for t in steps(start, end):
        if fully(track, t) != "closed":
            continue
        if runs and t - runs[-1][1] < 0.0015:
            runs[-1] = (runs[-1][0], t)
        else:
            runs.append((t, t))
    return runs


def test_bob_met_pam_closes_the_lips_at_every_b_m_and_p(engine):
    for rate in RATES:
        u = engine.say("Bob met Pam", rate=rate)
        track = mouth_track(u)
        closures = [p for p in u.phonemes if p.name in ("b", "m", "p")]
        assert {p.name for p in closures} == {"b", "m", "p"}
        runs = closed_runs(track, -0.1, u.duration + 0.1)
        for p in closures:
            # Fully closed for at least a frame, over the phoneme (with its neighbour, maybe:
            # "b m" in "Bob met" is one closure).
            over = [b - a for a, b in runs if a <= p.end and b >= p.at]
            assert over and max(over) >= FRAME - 0.0015, (rate, p, track)


@pytest.mark.parametrize("rate", RATES)
def test_the_mouth_rests_through_every_pause(engine, rate):
    u = engine.say("Hello, world. How are you?", rate=rate)
    track = mouth_track(u)
    pauses = silences(u, 0.1)
    inside = [(a, b) for a, b in pauses if a > 0.05 and b < u.duration - 0.05]
    if rate <= 175:
        assert len(inside) == 2, pauses  # after "Hello," and "world."
    for start, end in pauses:
        for t in steps(start + FRAME, end):
            assert shape_at(track, t) == (REST, None, 1.0), (start, end, t, track)


@pytest.mark.parametrize("text", SENTENCES)
@pytest.mark.parametrize("rate", RATES)
def test_the_mouth_opens_with_the_voice_and_rests_when_it_stops(engine, text, rate):
    u = engine.say(text, rate=rate)
    track = mouth_track(u)
    loud = np.flatnonzero(np.abs(u.samples.astype(np.int32)) > 32)
    assert track[0].at >= loud[0] / u.sample_rate
    # At rest when the sound stops: within a frame, and not after the utterance.
    assert track[-1].shape == REST
    assert abs(track[-1].at - (loud[-1] + 1) / u.sample_rate) <= FRAME
    assert track[-1].at + track[-1].blend <= u.duration
    for t in (-1.0, -1e-9, u.duration, u.duration + 1e-9, u.duration + 5.0):
        assert shape_at(track, t) == (REST, None, 1.0)
    assert shape_at((), 1.0) == (REST, None, 1.0)


@pytest.mark.parametrize("text", SENTENCES)
@pytest.mark.parametrize("rate", RATES)
def test_no_shape_flickers_but_a_closure(engine, text, rate):
    track = mouth_track(engine.say(text, rate=rate))
    assert all(k.shape in VISEMES or k.shape == REST for k in track)
    for key, after in zip(track, track[1:]):
        assert key.shape != after.shape
        assert after.at > key.at and key.blend <= after.at - key.at
        least = MOUTH_RULES.closure if key.shape == "closed" else MOUTH_RULES.hold
        assert after.at - key.at >= least - 1e-9, (key, after)


@pytest.mark.parametrize("rate", RATES)
def test_only_far_shapes_tween_and_closures_cut(engine, rate):
    track = mouth_track(engine.say(SENTENCES[2], rate=rate))
    tweened = 0
    for before, key in zip((MouthKey(0, REST, 0),) + track, track):
        (x1, y1), (x2, y2) = SHAPE_POSITIONS[before.shape], SHAPE_POSITIONS[key.shape]
        far = np.hypot(x1 - x2, y1 - y2) > MOUTH_RULES.far
        if key.shape == "closed" or not far:
            assert key.blend == 0
        tweened += key.blend > 0
        assert key.blend <= MOUTH_RULES.tween
    assert tweened > 3


def test_the_mouth_is_open_when_the_voice_is_loud(engine):
    text = " ".join(SENTENCES)
    for rate in (80, 175, 300):
        u = engine.say(text, rate=rate)
        track = mouth_track(u)
        width = round(FRAME * u.sample_rate)
        rest, opened = [], []
        for i in range(len(u.samples) // width):
            piece = u.samples[i * width : (i + 1) * width].astype(np.float64)
            loudness = np.sqrt(np.mean(piece * piece))
            shape = shape_at(track, (i + 0.5) * FRAME)[0]
            if shape == REST:
                rest.append(loudness)
            elif shape in ("open", "wide", "round"):
                opened.append(loudness)
        assert len(rest) > 10 and len(opened) > 10
        assert np.mean(rest) < 0.25 * np.mean(opened), (rate, np.mean(rest), np.mean(opened))


def test_english_phonemes_are_all_in_the_table(engine):
    text = (
        "The quick brown fox jumps over the lazy dog. Thought, although, pleasure, measure, church, "
        "judge, sing, yes, hue, cure, poor, tour, boy, air, near, square, bath, cloth, north, force, "
        "goose, foot, nurse, letter, happy, horses, butter, water, little, button, rhythm, bottom, uh-oh."
    )
    for voice in ("en", "en-gb", "en-us", "en-gb-x-rp", "en-gb-scotland", "en-029"):
        names = {p.name for p in engine.say(text, voice=voice).phonemes}
        missing = {n for n in names if n not in PHONEME_SHAPES and not n.startswith("_")}
        assert not missing, (voice, missing)


def test_other_languages_get_shapes_too(engine):
    for voice, text in (("de", "Guten Morgen, wie geht es Ihnen?"), ("fr-fr", "Bonjour, je suis un robot.")):
        u = engine.say(text, voice=voice)
        track = mouth_track(u)
        shapes = {k.shape for k in track}
        assert {"closed", REST} <= shapes and len(shapes) >= 4, (voice, track)


def test_the_tables():
    assert set(PHONEME_SHAPES.values()) == set(VISEMES)
    assert set(SHAPE_POSITIONS) == set(VISEMES) | {REST}
    assert {"p", "b", "m"} <= CLOSURES and all(PHONEME_SHAPES[c] == "closed" for c in CLOSURES)
    assert [phoneme_shape(n) for n in ("_", "_:", "_!", "_^_", "")] == [REST] * 5
    # Guesses for names the table does not have.
    guesses = {"y:": "round", "a:": "open", "E~": "wide", "o~": "round", "tS;": "wide", "x#": "slight"}
    assert {n: phoneme_shape(n) for n in guesses} == guesses
    assert all(n not in PHONEME_SHAPES for n in guesses)


def test_shape_at_tweens_from_the_shape_before():
    track = (MouthKey(0.1, "open", 0.04), MouthKey(0.2, "slight", 0.0), MouthKey(0.3, REST, 0.02))
    assert shape_at(track, 0.05) == (REST, None, 1.0)
    assert shape_at(track, 0.1) == ("open", REST, 0.0)
    shape, before, progress = shape_at(track, 0.12)
    assert (shape, before) == ("open", REST) and progress == pytest.approx(0.5)
    assert shape_at(track, 0.15) == ("open", None, 1.0)
    assert shape_at(track, 0.2) == ("slight", None, 1.0)
    assert shape_at(track, 0.31)[:2] == (REST, "slight")
    assert shape_at(track, 9.0) == (REST, None, 1.0)


def test_a_made_up_utterance_follows_its_sound():
    # A 1 s tone with 300 ms of silence in its middle, said as "mama": the mouth rests in the gap.
    rate = 22050
    t = np.arange(rate) / rate
    samples = (8000 * np.sin(2 * np.pi * 150 * t)).astype(np.int16)
    samples[round(0.4 * rate) : round(0.7 * rate)] = 0
    phonemes = (
        Phoneme(0.0, 0.1, "m"),
        Phoneme(0.1, 0.5, "a"),  # its sound stops at 0.4: the pause is found in the audio
        Phoneme(0.5, 0.7, "_:"),
        Phoneme(0.7, 0.72, "m"),  # 20 ms: lengthened to show
        Phoneme(0.72, 0.75, "@"),  # 30 ms: merged into the next
        Phoneme(0.75, 1.0, "a"),
    )
    u = Utterance("mama", "en", 175, samples, rate, phonemes, (Word(0.0, "mama"),))
    track = mouth_track(u)
    assert [k.shape for k in track] == ["closed", "open", REST, "closed", "open", REST]
    assert track[2].at == pytest.approx(0.4, abs=0.002)
    assert track[3].at == pytest.approx(0.7, abs=0.002)
    assert track[4].at - track[3].at == pytest.approx(MOUTH_RULES.closure)
    assert track[5].at == pytest.approx(1.0, abs=0.002)
    assert mouth_track(u) == track  # pure


def test_silence_makes_no_track():
    silent = Utterance("", "en", 175, np.zeros(0, np.int16), 22050, (), ())
    assert mouth_track(silent) == ()
    hush = Utterance(".", "en", 175, np.zeros(2205, np.int16), 22050, (Phoneme(0, 0.1, "_:"),), ())
    assert mouth_track(hush) == ()
