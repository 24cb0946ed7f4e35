"""Lip-sync from recordings (`say file`): how right the mouth is, and how fast it is found.

    .venv/bin/python bench/bench_lipsync.py [--held-out | --languages]

The recordings are made by espeak-ng (through the engine `say` uses), so the
true phoneme times are known, at voices and rates the tests do not use
(en-us at 165 and en-gb-x-rp at 195 words a minute), with 0.3 s of quiet
around them and white noise 40 dB under the voice's peak throughout. With
`--held-out`, other recordings, which nothing was tuned on: other sentences,
in five other voices and rates, with white noise 40 and then 20 dB under
the voice (signal-to-noise ratio: the voice's RMS over its voiced part to
the noise's). With `--languages`, two sentences in each of eight other
languages, noise 30 dB under the voice. The truth is the mouth `say` shows for the same words, voice
and rate; each way of finding a recording's mouth is held to it, frame by
frame at 30 fps:

- boundaries: for each change of the true mouth, how far (in frames) the
  nearest change of the found mouth is; the median (goal: within one frame);
- shape: the share of frames within the voice whose shape is the true one
  (goal: 80 %);
- pauses: the share of the true pauses (the mouth at rest for 100 ms or
  more inside the voice) where the found mouth is at rest at their middle
  (goal: 90 %);
- speed: seconds of sound analysed per second of one core's work (CPU time
  of this single-threaded process; goal: 10x real time), against reading the
  files (PyAV's decoding) in the same run as the baseline, and the second
  time, from the cache.
"""

from __future__ import annotations

import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

SENTENCES = [
    "Good morning! Would you like to see what I can do with my arms?",
    "The weather today is cold and grey, so please close the window.",
    "Five people sat on the red sofa, waiting for the show to begin.",
    "My name is Baxter. I work in a lab, and I like to help.",
    "Put the blue box on the table, then bring me the small cup.",
    "Thank you very much. That was a lovely visit; come back soon!",
]
VOICES = [("en-us", 165), ("en-gb-x-rp", 195)]
PAD, NOISE_DB, FPS = 0.3, -40.0, 30
HELD_OUT_SENTENCES = [
    "Could you hand me the yellow bottle from the shelf behind you?",
    "We finished the job early, so everyone went home before lunch.",
    "Robots move boxes, but they also learn to watch and listen.",
    "Please speak slowly; I am still learning how to understand people.",
]
HELD_OUT_VOICES = [
    ("en-gb", 150),
    ("en-gb-scotland", 180),
    ("en-us", 130),
    ("en-gb-x-gbclan", 170),
    ("en-029", 160),
]
HELD_OUT_NOISE = [-40.0, -20.0]  # under the voice's RMS: SNR 40 and 20 dB
LANGUAGES = {  # --languages: two sentences in each of other languages espeak-ng speaks
    "fr": [
        "Bonjour, je m'appelle Baxter et je travaille dans un laboratoire.",
        "Pose la boîte bleue sur la table, puis apporte-moi la petite tasse.",
    ],
    "de": [
        "Guten Morgen, ich heiße Baxter und arbeite in einem Labor.",
        "Stell die blaue Kiste auf den Tisch und bring mir die kleine Tasse.",
    ],
    "es": [
        "Buenos días, me llamo Baxter y trabajo en un laboratorio.",
        "Pon la caja azul sobre la mesa y tráeme la taza pequeña.",
    ],
    "it": [
        "Buongiorno, mi chiamo Baxter e lavoro in un laboratorio.",
        "Metti la scatola blu sul tavolo e portami la tazza piccola.",
    ],
    "nl": [
        "Goedemorgen, ik heet Baxter en ik werk in een laboratorium.",
        "Zet de blauwe doos op de tafel en breng me het kleine kopje.",
    ],
    "pt": [
        "Bom dia, o meu nome é Baxter e trabalho num laboratório.",
        "Põe a caixa azul em cima da mesa e traz-me a chávena pequena.",
    ],
    "ko": [
        "안녕하세요, 제 이름은 백스터이고 실험실에서 일해요.",
        "파란 상자를 탁자 위에 놓고 작은 컵을 가져다 주세요.",
    ],
    "cmn": ["早上好，我叫巴克斯特，我在实验室工作。", "把蓝色的盒子放在桌子上，然后把小杯子拿给我。"],
}


def make_recordings(folder: Path, sentences=SENTENCES, voices=VOICES, noise_db=NOISE_DB, to_rms=False):
    """(path, text, true utterance) for every sentence in every voice, written as noisy WAV files;
    the noise `noise_db` under the voice's peak, or its RMS (`to_rms`)."""
    from baxterface_cli.speech.soundtrack import write_wav
    from baxterface_cli.speech.synthesis import Phoneme, Utterance, engine

    rng = np.random.default_rng(7)
    out = []
    for voice, rate in voices:
        for i, text in enumerate(sentences):
            said = engine().say(text, voice, rate)
            quiet = np.zeros(round(PAD * said.sample_rate), np.int16)
            clean = np.concatenate([quiet, said.samples, quiet])
            voiced = said.samples[np.abs(said.samples) > 64].astype(np.float64)
            level = float(np.sqrt(np.mean(voiced**2))) if to_rms else float(np.abs(clean).max())
            noisy = clean + rng.normal(0, level * 10 ** (noise_db / 20), len(clean))
            path = folder / f"{voice}-{rate}-{i}-{-noise_db:.0f}.wav"
            write_wav(str(path), np.clip(noisy, -32768, 32767).astype(np.int16), said.sample_rate)
            phonemes = tuple(Phoneme(p.at + PAD, p.end + PAD, p.name) for p in said.phonemes)
            out.append((path, text, Utterance(text, voice, rate, clean, said.sample_rate, phonemes, ())))
    return out


def shapes(track, duration):
    from baxterface_cli.speech.visemes import shape_at

    return [shape_at(track, (i + 0.5) / FPS)[0] for i in range(int(duration * FPS))]


def measure(truth, track):
    """(boundary distances in frames, right frames, frames, pauses at rest, pauses)."""
    from baxterface_cli.core.face_constants import REST
    from baxterface_cli.speech.visemes import mouth_track, shape_at

    expected = mouth_track(truth)
    changes = [key.at for key in track] or [0.0]
    distances = [min(abs(key.at - t) for t in changes) * FPS for key in expected]
    first, last = int(expected[0].at * FPS), int(expected[-1].at * FPS)
    pairs = list(zip(shapes(expected, truth.duration), shapes(track, truth.duration)))[first:last]
    pauses = [
        (key.at, after.at)
        for key, after in zip(expected, expected[1:])
        if key.shape == REST and after.at - key.at >= 0.1
    ]
    rested = sum(shape_at(track, (a + b) / 2)[0] == REST for a, b in pauses)
    return distances, sum(a == b for a, b in pairs), len(pairs), rested, len(pauses)


def main() -> None:
    held_out = "--held-out" in sys.argv[1:]
    with tempfile.TemporaryDirectory() as tmp:
        os.environ["XDG_CACHE_HOME"] = str(Path(tmp) / "cache")  # a cache of its own, empty
        if "--languages" in sys.argv[1:]:
            for language, sentences in LANGUAGES.items():
                made = make_recordings(Path(tmp), sentences, [(language, 160)], -30.0, to_rms=True)
                run(made, Path(tmp), [(language, 160)], "SNR 30 dB", f" language {language}")
            return
        if not held_out:
            run(make_recordings(Path(tmp)), Path(tmp), VOICES, f"noise {NOISE_DB:.0f} dB under the peak")
            return
        for noise in HELD_OUT_NOISE:
            made = make_recordings(Path(tmp), HELD_OUT_SENTENCES, HELD_OUT_VOICES, noise, to_rms=True)
            run(made, Path(tmp), HELD_OUT_VOICES, f"held out, SNR {-noise:.0f} dB")


def run(made, folder: Path, voices, noise: str, other_language: str = "") -> None:
    from baxterface_cli import parse
    from baxterface_cli.engine.compiler import compile_script
    from baxterface_cli.speech import phoneme_recogniser, recordings
    from baxterface_cli.speech.audio_files import read_sound

    seconds = sum(truth.duration for _, _, truth in made)
    start = time.process_time()
    for path, _, _ in made:
        read_sound(str(path))
    reading = time.process_time() - start
    print(
        f"{len(made)} recordings, {seconds:.1f} s of speech "
        f"({', '.join(f'{v} at {r}' for v, r in voices)}), {noise}; one core"
    )
    print(f"  reading the files (baseline)   {seconds / reading:6.0f}x real time")
    methods = [
        ("with its words (aligned)", "text", "", True),
        ("without them (recognised)", "", "", True),
        ("without them, phoneme loop", "", "", False),
        ("loudness and spectrum", "", " language fr", False),
    ]
    if other_language:  # what may be found in another language: recognised, or its spectrum
        methods = [(name, "", other_language, hama) for name, _, _, hama in methods[1::2]]
    recogniser = phoneme_recogniser.available
    for name, words, option, hama in methods:
        phoneme_recogniser.available = recogniser if hama else lambda: False
        distances, right, frames, rested, pauses = [], 0, 0, 0, 0
        start = time.process_time()
        tracks = []
        for path, text, truth in made:
            written = f' text "{text}"' if words else ""
            script = parse(f'say file "{path.name}"{written}{option}', str(folder / "bench.face"))
            (said,) = compile_script(script).speech
            tracks.append((truth, said.mouth))
        work = time.process_time() - start
        for truth, track in tracks:
            d, r, f, rs, p = measure(truth, track)
            distances += d
            right, frames, rested, pauses = right + r, frames + f, rested + rs, pauses + p
        recordings._recent.clear()  # the second time: from the cache on disk, as a new process
        start = time.process_time()
        for path, text, _ in made:
            written = f' text "{text}"' if words else ""
            compile_script(parse(f'say file "{path.name}"{written}{option}', str(folder / "bench.face")))
        again = time.process_time() - start
        print(
            f"  {name:<28} boundaries {statistics.median(distances):4.2f} frames (median; "
            f"p75 {np.percentile(distances, 75):.2f})  shape {100 * right / frames:5.1f} % of frames  "
            f"pauses at rest {rested}/{pauses}  analysis {seconds / work:5.1f}x real time, "
            f"cached {seconds / again:5.0f}x"
        )
    phoneme_recogniser.available = recogniser


if __name__ == "__main__":
    main()
