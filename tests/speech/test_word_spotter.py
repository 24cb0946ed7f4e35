"""Hearing words: pocketsphinx's keyphrase search on espeak-ng's en-us voice (the benchmark,
bench/bench_words.py, measures other voices)."""

from __future__ import annotations

import subprocess

import numpy as np
import pytest

pytest.importorskip("pocketsphinx")
ws = pytest.importorskip("baxterface_cli.speech.word_spotter")
listening = pytest.importorskip("baxterface_cli.speech.listening")


def spot_samples(samples, words, **options):
    """The phrases the word spotter hears (never Moonshine: test_hearing.py hears with it)."""
    return listening.spot_samples(samples, words, **{"method": "spotter", **options}).words


def spot_file(path, words):
    return listening.spot_file(path, words, method="spotter").words


def said(tmp_path, text: str) -> np.ndarray:
    path = tmp_path / "said.wav"
    subprocess.run(["espeak-ng", "-v", "en-us", "-w", str(path), text], check=True)
    return ws.read_recording(str(path))


def with_quiet(samples: np.ndarray, before: float = 0.5) -> np.ndarray:
    return np.concatenate([np.zeros(int(before * ws.RATE), np.int16), samples])


def test_a_word_is_heard_with_the_time_it_ended(tmp_path):
    samples = with_quiet(said(tmp_path, "look at that robot over there"), before=1.0)
    heard = spot_samples(samples, ["robot"])
    assert [h.word for h in heard] == ["robot"]
    # "robot" is the fourth of six words: it ends after the first second of quiet, well before the end.
    length = len(samples) / ws.RATE
    assert 1.3 < heard[0].at < length - 0.3
    assert heard[0].start < heard[0].at


def test_a_wav_file_at_another_rate_is_read_as_16k_mono(tmp_path):
    subprocess.run(
        ["espeak-ng", "-v", "en-us", "-w", str(tmp_path / "r.wav"), "the robot smiles"], check=True
    )
    heard = spot_file(str(tmp_path / "r.wav"), ["Robot"])  # espeak-ng writes 22050 Hz
    assert [h.word for h in heard] == ["robot"]


def test_the_face_does_not_hear_itself_unless_barge_in(tmp_path):
    samples = with_quiet(said(tmp_path, "the robot is smiling at me"))
    length = len(samples) / ws.RATE

    def speaking(t: float) -> bool:
        return 0.5 <= t <= length

    told = []
    spotter = ws.WordSpotter(["robot"], lambda word, at: told.append(word), speaking=speaking)
    for i in range(0, len(samples), 800):
        spotter.feed(samples[i : i + 800], end=(i + 800) / ws.RATE)
    spotter.feed(np.zeros(8000, np.int16), end=length + 0.5)
    assert told == [] and [h.word for h in spotter.ignored] == ["robot"]
    heard = spot_samples(samples, ["robot"], speaking=speaking, barge_in=True)
    assert [h.word for h in heard] == ["robot"]


def test_on_word_is_told_on_the_callers_clock(tmp_path):
    samples = with_quiet(said(tmp_path, "hello robot"))
    clock = {"now": 100.0}
    told = []
    spotter = ws.WordSpotter(["robot"], lambda word, at: told.append((word, at)), clock=lambda: clock["now"])
    for i in range(0, len(samples) + 8000, 800):
        clock["now"] = 100.0 + (i + 800) / ws.RATE
        spotter.feed(np.pad(samples[i : i + 800], (0, max(0, 800 - len(samples[i : i + 800])))))
    assert [w for w, _ in told] == ["robot"]
    assert 100.5 < told[0][1] < 100.0 + len(samples) / ws.RATE + 0.05


def test_a_word_the_model_does_not_know_is_a_one_line_error():
    with pytest.raises(ws.WordError, match="'blorptastic' is not a word the speech model knows"):
        ws.WordSpotter(["hello blorptastic"], lambda word, at: None)


def test_thresholds_grow_more_lenient_with_a_phrases_length():
    assert ws.threshold(8) < ws.threshold(4) < 1.0


def test_no_sounddevice_module_is_a_one_line_error(monkeypatch):
    from baxterface_cli.speech.sound_device import Microphone, MicrophoneError

    monkeypatch.setitem(__import__("sys").modules, "sounddevice", None)  # as if not installed
    wanted = r"listening needs the sounddevice module: pip install"
    with pytest.raises(MicrophoneError, match=wanted), Microphone(lambda block: None):
        pass


def test_hamas_recogniser_listens_where_it_runs_and_pocketsphinx_alone_elsewhere(tmp_path):
    from baxterface_cli.speech import phoneme_recogniser

    samples = with_quiet(said(tmp_path, "look at that robot over there"), before=1.0)
    spotter = ws.WordSpotter(["robot"], lambda word, at: None)
    assert spotter.method == ("ctc" if phoneme_recogniser.available() else "keyphrase")
    for method in ("ctc",) * phoneme_recogniser.available() + ("keyphrase",):
        heard = spot_samples(samples, ["robot"], method=method)
        assert [h.word for h in heard] == ["robot"], method
        assert 1.3 < heard[0].at < len(samples) / ws.RATE - 0.3


def test_the_recogniser_tells_a_phrase_once_though_it_looks_at_it_many_times(tmp_path):
    pytest.importorskip("hama")
    # each "robot" is in several overlapping windows
    samples = with_quiet(said(tmp_path, "a robot smiles at another robot."), before=1.0)
    heard = spot_samples(samples, ["robot"], method="ctc")
    assert [h.word for h in heard] == ["robot", "robot"]
    assert heard[0].at < heard[1].start


def test_a_phrase_unsaid_is_not_heard_in_silence_or_other_words(tmp_path):
    pytest.importorskip("hama")
    samples = with_quiet(said(tmp_path, "the weather is lovely this morning"), before=1.0)
    silence = np.zeros(3 * ws.RATE, np.int16)
    assert spot_samples(np.concatenate([samples, silence]), ["robot"], method="ctc") == []
