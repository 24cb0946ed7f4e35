"""Natural voices (`say "..." voice heart`, `voice joe`): how soon, how fast, how right the mouth.

    taskset -c 0 .venv/bin/python bench/bench_natural_voices.py [--lipsync]

- first sound: from a `say` statement to its sound and mouth ready (the script compiled, as a live
  face compiles each command: synthesis, the phonemes timed), for a short sentence
  ("Hello there, NAME.", a new name each time so no cache helps), the model loaded (a live face
  loads the voices its start names, or its first `say` does: "the first say of a process" below);
  espeak-ng's `say` in the same run is the baseline. Goal: 200 ms.
- speed: 20 twelve-word sentences, seconds of speech per second of one core's CPU time, the whole
  `say` (synthesis, phonemes, words: aligned where the model's are not the text's) and the synthesis
  alone; espeak-ng's the baseline, by wall time (it speaks in a process of its own). Goal: 10x.
- lip-sync: the truth is each model's own phoneme times (model_durations.py: piper's and hibari's
  durations), which the mouth now follows, named as espeak-ng's phonemes of the same mouth: the mouth
  shown, with a recording's rules (silence over the voice's hiss), scored against the mouth `say`'s
  rules make of them, frame by frame at 30 fps as bench_lipsync.py scores a recording (`measure`: the
  share of frames of the true shape, goal 80 %; the changes' distance from the true ones; pauses at
  rest); and the mouth from the text aligned to the sound (pocketsphinx, as `say file` with its words:
  the fallback where a model's times cannot be had, and the words where the model's are not the
  text's) scored the same way. The sentences are bench_lipsync.py's six and its four held out.
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path
from typing import List

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_lipsync import HELD_OUT_SENTENCES, SENTENCES, measure  # noqa: E402

NAMES = ("Anna", "Ben", "Clara", "David", "Emma", "Frank", "Grace", "Henry", "Iris", "Jack")
NAMES += ("Kate", "Liam", "Maria", "Noah", "Olivia", "Peter", "Rose", "Sam", "Tom", "Vera")
WORDS = ("the", "robot", "looked", "up", "and", "smiled", "at", "everyone", "in", "the", "room", "number")


def sentences(count: int, offset: int = 0) -> List[str]:
    return [" ".join(WORDS[:11] + (str(offset + i),)) for i in range(count)]


def first_sound() -> None:
    from baxterface_cli import parse
    from baxterface_cli.engine.compiler import compile_script
    from baxterface_cli.speech import natural_voices
    from baxterface_cli.speech.synthesis import engine

    start = time.perf_counter()
    compile_script(parse('say "Hello there, Baxter." voice heart'))
    cold_heart = time.perf_counter() - start
    start = time.perf_counter()
    compile_script(parse('say "Hello there, Baxter." voice joe'))
    cold_joe = time.perf_counter() - start
    engine().say("warm up")
    print("first sound: a `say` statement to its sound and mouth ready, short sentence (ms)")
    cold = f"heart {cold_heart * 1000:.0f}, joe {cold_joe * 1000:.0f}"
    print(f"  the first say of a process (it loads the model): {cold}")
    for voice in ("en", "heart", "joe"):
        times = []
        for name in NAMES:
            script = parse(f'say "Hello there, {name}." voice {voice}')
            start = time.perf_counter()
            (said,) = compile_script(script).speech
            times.append((time.perf_counter() - start) * 1000)
        name = "espeak-ng en (baseline)" if voice == "en" else voice
        print(
            f"  {name:24s} median {statistics.median(times):5.0f}  p95 {np.percentile(times, 95):5.0f}"
            f"  worst {max(times):5.0f}  ({said.utterance.duration:.2f} s of speech)"
        )
    natural_voices._said.clear()


def speed() -> None:
    from baxterface_cli.speech import natural_voices
    from baxterface_cli.speech.synthesis import engine

    texts = sentences(20, 100)
    print("speed: 20 twelve-word sentences, one core's CPU time (x real time)")
    start = time.perf_counter()
    spoken = sum(engine().say(text).duration for text in texts)
    print(f"  espeak-ng en (baseline)  {spoken / (time.perf_counter() - start):6.1f}x (wall time)")
    for voice in ("heart", "joe"):
        model = natural_voices._model(voice)
        start = time.process_time()
        sound = sum(len(s) / rate for s, rate, _ in (model(text, 1.0) for text in texts))
        alone = time.process_time() - start
        start = time.process_time()
        spoken = sum(natural_voices.say(text, voice, 175).duration for text in texts)
        whole = time.process_time() - start
        print(
            f"  {voice:24s} {spoken / whole:6.1f}x the whole say ({spoken:.1f} s of speech), "
            f"{sound / alone:6.1f}x its synthesis alone"
        )


def lipsync() -> None:
    from baxterface_cli.speech import natural_voices

    print("lip-sync: against the models' own phoneme times, 30 fps (bench_lipsync.py's scoring)")
    for voice in ("joe", "heart"):
        for name, texts in (("bench_lipsync's", SENTENCES), ("its held-out ones", HELD_OUT_SENTENCES)):
            scores = {"the model's times (the mouth now)": [], "the text aligned (the fallback)": []}
            seconds = 0.0
            for text in texts:
                said = natural_voices.say(text, voice, 175)
                assert said.recording is None and said.phonemes
                rate = said.sample_rate
                aligned = natural_voices._aligned(text, voice, 175, said.samples, rate)
                scores["the model's times (the mouth now)"].append(measure(said, natural_voices.mouth(said)))
                scores["the text aligned (the fallback)"].append(measure(said, natural_voices.mouth(aligned)))
                seconds += said.duration
            print(f"  {voice}, {name} sentences ({len(texts)}, {seconds:.1f} s of speech)")
            for way, found in scores.items():
                distances = [d for f in found for d in f[0]]
                right, frames = sum(f[1] for f in found), sum(f[2] for f in found)
                rested, pauses = sum(f[3] for f in found), sum(f[4] for f in found)
                print(
                    f"    {way:34s} changes {statistics.median(distances):4.2f} frames from the true ones "
                    f"(median)  shape {100 * right / frames:5.1f} % of frames  "
                    f"pauses at rest {rested}/{pauses}"
                )


def main() -> None:
    if "--lipsync" not in sys.argv[1:]:
        first_sound()
        speed()
    lipsync()


if __name__ == "__main__":
    main()
