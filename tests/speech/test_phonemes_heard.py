"""`say file` without its words: the phonemes hama recognises, aligned by pocketsphinx, and the fallbacks.

The recordings are made here by espeak-ng in a voice, rate and sentence that
nothing was tuned on (the bench and test_recordings.py use others), with
noise 30 dB under the voice, so the true mouth is the one `say` shows for the
same words.
"""

from __future__ import annotations

import unicodedata

import numpy as np
import pytest
from test_recordings import agreement, blocked_env  # the right-frames measure, one copy

from baxterface_cli import parse
from baxterface_cli.core.face_constants import REST
from baxterface_cli.engine.compiler import compile_script
from baxterface_cli.speech.soundtrack import write_wav
from baxterface_cli.speech.synthesis import Phoneme, Utterance
from baxterface_cli.speech.visemes import shape_at
from conftest import baxterface

pytestmark = pytest.mark.xdist_group("recordings")

pytest.importorskip("av")
pytest.importorskip("pocketsphinx")

TEXT = "Would you carry the heavy parcel to my desk? Thank you, that helps a lot."
VOICE, RATE = "en-gb-x-gbcwmd", 155
PAD = 0.4
RECOGNISED, HEARD = "phonemes recognised", "phonemes heard"


def has_hama() -> bool:
    from baxterface_cli.speech import phoneme_recogniser

    return phoneme_recogniser.available()


needs_hama = pytest.mark.skipif(
    "not has_hama()", reason="hama (the [lipsync] extra, Python 3.9+) is not here"
)


def recording(engine, folder, name, text=TEXT, voice=VOICE, rate=RATE, snr=30.0, seed=3):
    """A noisy WAV of `text` and the utterance `say` would make of it, at the file's times."""
    said = engine.say(text, voice, rate)
    quiet = np.zeros(round(PAD * said.sample_rate), np.int16)
    clean = np.concatenate([quiet, said.samples, quiet])
    voiced = said.samples[np.abs(said.samples) > 64].astype(float)
    noise = np.random.default_rng(seed).normal(0, np.sqrt(np.mean(voiced**2)) * 10 ** (-snr / 20), len(clean))
    write_wav(str(folder / name), np.clip(clean + noise, -32768, 32767).astype(np.int16), said.sample_rate)
    phonemes = tuple(Phoneme(p.at + PAD, p.end + PAD, p.name) for p in said.phonemes)
    return Utterance(text, voice, rate, clean, said.sample_rate, phonemes, ())


def said_from(folder, statement):
    (said,) = compile_script(parse(statement, str(folder / "talk.face"))).speech
    return said


@pytest.fixture(scope="module")
def recorded(tmp_path_factory, engine):
    folder = tmp_path_factory.mktemp("heard")
    return folder, recording(engine, folder, "parcel.wav")


@pytest.fixture(scope="module")
def phone_loop(recorded):
    """The same recording heard by pocketsphinx's phoneme loop, as without hama."""
    from baxterface_cli.speech import phoneme_recogniser

    folder, _ = recorded
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(phoneme_recogniser, "available", lambda: False)
        return said_from(folder, 'say file "parcel.wav"')


@needs_hama
def test_without_words_the_phonemes_recognised_put_the_right_mouth_on_most_frames(recorded, phone_loop):
    folder, truth = recorded
    said = said_from(folder, 'say file "parcel.wav"')
    assert said.utterance.recording.method == RECOGNISED and said.utterance.words == ()
    right = agreement(truth, said.mouth)
    assert right >= 0.65, right  # 55 % and less from the phoneme loop on recordings like this
    assert right > agreement(truth, phone_loop.mouth)


@needs_hama
def test_the_recognised_mouth_rests_before_between_and_after_the_sentences(recorded):
    folder, truth = recorded
    said = said_from(folder, 'say file "parcel.wav"')
    assert said.mouth[0].at >= PAD - 0.05 and said.mouth[-1].shape == REST
    assert said.mouth[-1].at <= truth.duration - PAD + 0.05
    pause = next(p for p in truth.phonemes if p.name.startswith("_") and p.end - p.at >= 0.1)
    assert shape_at(said.mouth, (pause.at + pause.end) / 2)[0] == REST


@needs_hama
def test_the_recognised_analysis_is_kept_apart_from_the_phoneme_loops_and_read_back(
    recorded, phone_loop, monkeypatch
):
    from baxterface_cli.speech import phones_heard, recordings

    folder, _ = recorded
    first = said_from(folder, 'say file "parcel.wav"')
    recordings._recent.clear()  # as a new process: from the cache folder
    monkeypatch.setattr(phones_heard, "hear", lambda *a, **k: pytest.fail("analysed again"))
    again = said_from(folder, 'say file "parcel.wav"')
    assert again.mouth == first.mouth and again.utterance.recording.method == RECOGNISED
    assert phone_loop.utterance.recording.method == HEARD and phone_loop.mouth != first.mouth


@needs_hama
def test_another_language_is_recognised_too_and_righter_than_its_spectrum(engine, tmp_path, monkeypatch):
    from baxterface_cli.speech import phoneme_recogniser

    text = "Nous partirons demain matin, avant que le soleil ne se lève sur la ville."
    truth = recording(engine, tmp_path, "demain.wav", text, "fr", 150)
    said = said_from(tmp_path, f'say file "demain.wav" text "{text}" language fr')
    # Its words are not aligned: pocketsphinx's dictionary is English.
    assert said.utterance.recording.method == RECOGNISED and said.utterance.words == ()
    assert said.mouth[-1].shape == REST
    monkeypatch.setattr(phoneme_recogniser, "available", lambda: False)
    spectrum = said_from(tmp_path, 'say file "demain.wav" language fr')
    assert spectrum.utterance.recording.method == "loudness and spectrum"
    right = agreement(truth, said.mouth)
    assert right >= 0.5 and right > agreement(truth, spectrum.mouth) + 0.05, right


def test_without_hama_the_phoneme_loop_hears_them_and_nothing_is_said(recorded, tmp_path):
    folder, _ = recorded
    (folder / "talk.face").write_text('say file "parcel.wav"\n')
    run = baxterface("explain", str(folder / "talk.face"), env=blocked_env(tmp_path, "hama"))
    assert run.code == 0 and run.err == "", run.err
    line = next(line for line in run.out.splitlines() if "robot say file" in line)
    assert line.endswith(f"s, {HEARD})"), line


def test_words_heard_that_do_not_fit_the_sound_are_let_go_for_the_phoneme_loop(recorded):
    from baxterface_cli.speech import phones_heard
    from baxterface_cli.speech.audio_files import read_sound

    folder, _ = recorded
    sound = read_sound(str(folder / "parcel.wav")).analysis
    # Far more phonemes than a few seconds can hold: no alignment can place them.
    heard = phones_heard.hear(sound, recognise=lambda piece, rate: [["ZH"] * 400])
    assert not heard.recognised and not heard.aligned
    names = {name for _, _, name in heard.phones}
    assert "ZH" not in names and len(names - {"SIL"}) >= 10
    assert heard.phones[0][0] == 0.0 and abs(heard.phones[-1][1] - len(sound) / 16000) < 1e-6


@needs_hama
def test_a_long_recording_is_recognised_in_pieces_cut_where_it_is_quiet(engine, tmp_path):
    from baxterface_cli.speech import phones_heard
    from baxterface_cli.speech.audio_files import read_sound

    sentences = [
        "Could you pass the green cup, please?",
        "The robot waved at the visitors and smiled.",
        "We will meet again tomorrow morning at nine.",
        "Bring the small blue box over to the bench.",
        "She opened the window because the room was warm.",
    ] * 2
    truths = [recording(engine, tmp_path, f"{i}.wav", text, "en-us", 150) for i, text in enumerate(sentences)]
    sound = np.concatenate([read_sound(str(tmp_path / f"{i}.wav")).analysis for i in range(len(sentences))])
    seconds = len(sound) / 16000
    assert seconds > phones_heard.PIECE_SECONDS
    pieces = phones_heard.pieces(sound)
    assert len(pieces) >= 2 and pieces[0][0] == 0 and pieces[-1][1] == len(sound)
    for (_, end), (start, _) in zip(pieces, pieces[1:]):
        assert end == start
        around = sound[end - 80 : end + 80].astype(float)
        assert np.sqrt(np.mean(around**2)) < 0.05 * np.abs(sound).max()  # in a quiet gap, not a word
    assert all(b - a <= phones_heard.PIECE_SECONDS * 16000 for a, b in pieces)
    write_wav(str(tmp_path / "long.wav"), sound, 16000)
    said = said_from(tmp_path, 'say file "long.wav"')
    assert said.utterance.recording.method == RECOGNISED
    at, right = 0.0, []
    for truth in truths:  # each sentence's share, where it sits in the long recording
        shown = tuple(k._replace(at=k.at - at) for k in said.mouth if at <= k.at < at + truth.duration)
        right.append(agreement(truth, shown))
        at += truth.duration
    assert np.mean(right) >= 0.6, right


def test_every_phoneme_hama_hears_is_spelled_in_phones_pocketsphinx_knows():
    pytest.importorskip("hama")
    import pocketsphinx

    from baxterface_cli.speech import phoneme_recogniser

    model = phoneme_recogniser._model()
    used = set()
    for token in model.decoder_tokens:
        phones = phoneme_recogniser.phones(token)
        used.update(phones)
        letter = unicodedata.normalize("NFD", token)[0]
        if unicodedata.category(letter) == "Ll" and letter != "ʔ":  # a sound, not a mark, tone or pause
            assert phones, token
    # Every phone used is one of pocketsphinx's: a word of them can be added to its dictionary.
    decoder = pocketsphinx.Decoder(lm=None, loglevel="FATAL")
    decoder.add_word("every-phone", " ".join(sorted(used)), True)
    assert decoder.lookup_word("every-phone") == " ".join(sorted(used))
    assert {"P", "B", "M", "F", "V", "IY", "UW", "AA", "CH", "JH", "NG", "ER"} <= used
