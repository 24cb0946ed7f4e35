"""A script's sound: utterances mixed at their times, resampled, written as WAV."""

from __future__ import annotations

import io
import wave
from typing import NamedTuple

import numpy as np

from baxterface_cli.speech.soundtrack import resample, soundtrack, write_wav


class Utterance(NamedTuple):
    samples: np.ndarray
    sample_rate: int


class Said(NamedTuple):
    at: float
    utterance: Utterance


def test_nothing_said_is_no_soundtrack():
    assert soundtrack([], 3.0) is None


def test_utterances_are_mixed_at_their_times_and_clipped_not_wrapped():
    rate = 1000
    a = Said(0.5, Utterance(np.full(1000, 20000, np.int16), rate))
    b = Said(1.0, Utterance(np.full(200, 20000, np.int16), rate))  # over the middle of a
    samples, got_rate = soundtrack([a, b], 2.0)
    assert got_rate == rate and len(samples) == 2000
    assert samples[:500].tolist() == [0] * 500
    assert samples[500:1000].tolist() == [20000] * 500
    assert samples[1000:1200].tolist() == [32767] * 200  # 40000 clipped, not wrapped round to negative
    assert samples[1200:1500].tolist() == [20000] * 300
    assert samples[1500:].tolist() == [0] * 500


def test_a_sound_past_the_end_is_cut_at_the_end():
    said = Said(0.9, Utterance(np.ones(500, np.int16), 1000))
    samples, _ = soundtrack([said], 1.0)
    assert len(samples) == 1000 and samples[900:].tolist() == [1] * 100


def test_a_voice_at_another_rate_is_resampled_to_the_first_voices_rate():
    first = Said(0.0, Utterance(np.zeros(100, np.int16), 1000))
    other = Said(0.0, Utterance(np.full(50, 7, np.int16), 500))  # 0.1 s at half the rate
    samples, rate = soundtrack([first, other], 0.2)
    assert rate == 1000 and samples[:100].tolist() == [7] * 100 and samples[100:].tolist() == [0] * 100


def test_resampling_keeps_the_duration_and_the_shape():
    t = np.arange(22050) / 22050
    tone = (10000 * np.sin(2 * np.pi * 5 * t)).astype(np.int16)
    out = resample(tone, 22050, 16000)
    assert len(out) == 16000
    expected = 10000 * np.sin(2 * np.pi * 5 * np.arange(16000) / 16000)
    assert np.abs(out - expected).max() < 5
    assert resample(tone, 22050, 22050) is tone and resample(tone, 22050, 0) is tone


def test_a_wav_reads_back_as_the_samples_written():
    samples = np.array([0, 1, -1, 32767, -32768], np.int16)
    out = io.BytesIO()
    write_wav(out, samples, 16000)
    with wave.open(io.BytesIO(out.getvalue())) as w:
        assert (w.getnchannels(), w.getsampwidth(), w.getframerate()) == (1, 2, 16000)
        assert np.frombuffer(w.readframes(5), "<i2").tolist() == samples.tolist()
