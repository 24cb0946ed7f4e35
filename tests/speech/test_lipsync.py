"""Lip-sync, measured as a viewer would: in the MP4 that `render` writes, picture against sound.

The video is decoded by PyAV, independently of the writer. Per frame, the
mouth's opening is the area of mouth-inside, tongue and teeth colours in the
mouth's box; the voice's loudness is the audio's RMS over the frame's time.
Goals (issue 12): the mouth follows the audio within one frame at its best
lag; it is back at rest within one frame in every pause of 100 ms or more;
p, b and m close the lips.
"""

from __future__ import annotations

import numpy as np
import pytest

from conftest import baxterface

# One worker runs the module, so the rendered video is made once, not once a worker.
pytestmark = pytest.mark.xdist_group("lipsync_video")

av = pytest.importorskip("av")
speech = pytest.importorskip("baxterface_cli.speech.synthesis")

FPS = 30
TEXT = "Hello there, I am Baxter. Bob met Pam, and Mike paid a big bill. Maybe. Move up."
SCRIPT = f'default; wait 0.5s; say "{TEXT}"; wait 0.5s'
BOX = (380, 400, 644, 580)  # x0, y0, x1, y1: the mouth at 1024x600, with room around it
INSIDE = np.array([(128, 32, 44), (232, 110, 120), (250, 250, 244)], float)  # inside, tongue, teeth
START = 0.5 + 0.3  # the say starts after the emotion's lids and the wait


@pytest.fixture(scope="module")
def utterance(engine):
    return engine.say(TEXT)


@pytest.fixture(scope="module")
def video(tmp_path_factory, utterance):
    """(frame times, mouth crops as RGB, audio samples as floats, audio rate) of the rendered MP4."""
    out = tmp_path_factory.mktemp("lipsync") / "talk.mp4"
    run = baxterface("render", "-e", SCRIPT, "--out", str(out), "--fps", str(FPS))
    assert run.code == 0, run.err
    x0, y0, x1, y1 = BOX
    times, crops, sound = [], [], []
    with av.open(str(out)) as container:
        for frame in container.decode(video=0):
            times.append(frame.time)
            crops.append(frame.to_ndarray(format="rgb24")[y0:y1, x0:x1].astype(float))
    with av.open(str(out)) as container:
        stream = container.streams.audio[0]
        rate = stream.rate
        for frame in container.decode(audio=0):
            data = frame.to_ndarray()
            sound.append(data.mean(axis=0) if data.ndim == 2 else data)
    return np.array(times), crops, np.concatenate(sound).astype(float), rate


def opening(crop):
    """Pixels of mouth inside, tongue or teeth: how open the mouth is."""
    distance = np.linalg.norm(crop[:, :, None, :] - INSIDE[None, None], axis=3).min(axis=2)
    return int((distance < 45).sum())


def loudness(sound, rate, t0, t1):
    piece = sound[int(t0 * rate) : max(int(t0 * rate) + 1, int(t1 * rate))]
    return float(np.sqrt(np.mean(piece**2))) if piece.size else 0.0


def pauses(sound, rate, start, end, least=0.100):
    """(start, end) of each stretch of silence of `least` seconds or more inside the speech."""
    window = int(rate * 0.01)
    level = np.array([loudness(sound, rate, t, t + 0.01) for t in np.arange(start, end, 0.01)])
    quiet = level < 0.02 * level.max()
    found, run_from = [], None
    for i, q in enumerate(list(quiet) + [False]):
        if q and run_from is None:
            run_from = i
        elif not q and run_from is not None:
            if (i - run_from) * 0.01 >= least and run_from > 0 and i < len(quiet):
                found.append((start + run_from * 0.01, start + i * 0.01))
            run_from = None
    assert window > 0
    return found


def test_the_video_carries_the_voice_where_the_script_says(video, utterance):
    """The MP4's sound is the utterance itself, starting at the say's time (AAC's priming undone)."""
    _, _, sound, rate = video
    assert rate == utterance.sample_rate
    voice = utterance.samples.astype(float) / 32768
    start = round(START * rate)
    # Where the utterance sits in the track: the best match near the say's time.
    near = sound[start - rate // 10 : start + len(voice) + rate // 10]
    match = np.correlate(near, voice, mode="valid")
    found = (start - rate // 10 + int(np.argmax(match))) / rate
    assert found == pytest.approx(START, abs=0.002)
    heard = sound[round(found * rate) : round(found * rate) + len(voice)]
    assert np.corrcoef(heard, voice)[0, 1] > 0.9  # AAC keeps the voice, if not every sample


def test_the_mouth_follows_the_voice_within_one_frame(video):
    times, crops, sound, rate = video
    open_ = np.array([opening(c) for c in crops], float)
    loud = np.array([loudness(sound, rate, t, t + 1 / FPS) for t in times])
    speaking = (times >= START - 0.2) & (times <= times[-1] - 0.3)
    a, b = open_[speaking], loud[speaking]

    def correlation(lag):  # the mouth `lag` frames after the sound
        x, y = (a[lag:], b[: len(b) - lag]) if lag >= 0 else (a[:lag], b[-lag:])
        return float(np.corrcoef(x, y)[0, 1])

    scores = {lag: correlation(lag) for lag in range(-4, 5)}
    best = max(scores, key=scores.get)
    print({k: round(v, 3) for k, v in scores.items()})
    assert abs(best) <= 1, scores
    assert scores[best] > 0.5, scores


def test_the_mouth_rests_in_every_pause(video, utterance):
    times, crops, sound, rate = video
    rest = crops[int(np.searchsorted(times, START - 0.1))]  # the emotion's own mouth, before speaking
    found = pauses(sound, rate, START, START + utterance.duration)
    assert len(found) >= 3, found  # after "there,", "Baxter.", "Pam,", "bill." ...
    for start, end in found:
        inside = [i for i, t in enumerate(times) if start + 1 / FPS <= t and t + 1 / FPS <= end]
        for i in inside:
            difference = np.abs(crops[i] - rest).mean()
            assert difference < 3.0, f"frame at {times[i]:.3f} s in the pause {start:.2f}-{end:.2f} s"


def test_p_b_and_m_close_the_lips(video, utterance):
    times, crops, _, _ = video
    closures = [p for p in utterance.phonemes if p.name in ("p", "b", "m")]
    assert len(closures) >= 8
    open_during_speech = max(opening(c) for c in crops)
    for p in closures:
        shown = [
            opening(crops[i])
            for i, t in enumerate(times)
            if START + p.at - 1 / FPS <= t < START + p.end + 1 / FPS
        ]
        assert shown and min(shown) < 0.02 * open_during_speech, (p, shown)
