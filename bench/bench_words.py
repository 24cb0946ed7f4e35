"""Hearing words (`on word "..."`): hits and false alarms on voices nothing was tuned on, the face's
own speech, and the time from a word's end to the reaction's first frame.

    .venv/bin/python bench/bench_words.py [--tune | --latency-only] [--latency-runs N] [--keyphrase]

The recordings are made by espeak-ng: sentences with and without the phrases "hello", "goodbye"
and "robot", 0.6 s apart, white noise 20 dB under the voice (RMS over its voiced part).

- `--tune`: sweeps phrase_ctc.THRESHOLD (hama's recogniser, the default) and
  word_spotter.PER_PHONE (pocketsphinx alone) on the tuning voices (en-us, en-gb: the tests' voice
  and one more) and prints hits and false alarms for each value.
- accuracy: on other voices (en-gb-scotland, en-029, en-gb-x-rp, en-gb-x-gbclan, en-us+f3),
  pocketsphinx alone at its PER_PHONE and hama's recogniser at its THRESHOLD (and at -0.5, -0.75
  and -1 a phone): the share of phrases said that were heard (within the sentence that says
  them), false alarms (a phrase heard in a sentence that does not say it, or heard twice in one
  that does) a minute of sound, and the real-time factor (the spotter's CPU time over the
  sound's length: one core).
- the face's own speech: the face says all the sentences (en-us, its default voice), the
  spotter hears them through the air (the same samples, noise added) with `speaking` true while
  it says them: words told (goal 0), and words heard when barge-in lets them through.
- latency: "look at that robot" (en-gb-x-gbclan, noise 30 dB under it, after 1 to 1.3 s of quiet:
  a different phase each run) fed to a spotter in real time (blocks of 50 ms on the monotonic
  clock, as a microphone gives them) while a live session with `on word "robot" { happy }` is
  ticked at 30 fps on the same clock: from the word's end (known from the recording) to the first
  frame whose face differs from the face without the event (goal <= 400 ms). `--keyphrase`: with
  pocketsphinx alone listening.

The machine's load is printed (`os.getloadavg`): under load the latency grows.
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from baxterface_cli.speech import listening, phrase_ctc  # noqa: E402
from baxterface_cli.speech import word_spotter as ws  # noqa: E402

WORDS = ("hello", "goodbye", "robot")
WITH = [
    "hello, is anybody there?",
    "well hello there, how are you today?",
    "I came to say goodbye to you.",
    "goodbye, and thank you for the help.",
    "look at that robot over there.",
    "the robot is smiling at me.",
    "hello robot, nice to meet you.",
    "we said goodbye at the station.",
    "can you say hello to my sister?",
    "my little robot likes music.",
]
WITHOUT = [
    "the weather is lovely this morning.",
    "please pass me the salt and pepper.",
    "yellow fellows follow the hollow road.",
    "good night, sleep well.",
    "a row of boats is on the river.",
    "she bought a new coat yesterday.",
    "hold the door, I am coming too.",
    "the rabbit ran under the bridge.",
    "how low can you go?",
    "robin and bobby are good friends.",
]
TUNING = ("en-us", "en-gb")
HELD_OUT = ("en-gb-scotland", "en-029", "en-gb-x-rp", "en-gb-x-gbclan", "en-us+f3")
GAP = 0.6
SNR_DB = 20.0
METHOD = "keyphrase" if "--keyphrase" in sys.argv else None  # the latency's spotter: the default
LATENCY_SNR_DB = 30.0  # a word alone at 20 dB is missed too often to time it


def say(text: str, voice: str, folder: str) -> np.ndarray:
    path = os.path.join(folder, "say.wav")
    subprocess.run(["espeak-ng", "-v", voice, "-w", path, text], check=True)
    return ws.read_recording(path)


def voiced_rms(samples: np.ndarray) -> float:
    x = samples.astype(np.float64)
    frames = x[: len(x) // 160 * 160].reshape(-1, 160)
    energy = np.sqrt((frames**2).mean(axis=1))
    voiced = energy[energy > 0.1 * energy.max()]
    return float(np.sqrt((voiced**2).mean())) if len(voiced) else 1.0


def noisy(samples: np.ndarray, rng: np.random.Generator, snr_db: float = SNR_DB) -> np.ndarray:
    noise = rng.normal(0.0, voiced_rms(samples) / 10 ** (snr_db / 20), len(samples))
    return np.clip(samples + noise, -32768, 32767).astype(np.int16)


def track(
    voice: str, folder: str, rng: np.random.Generator
) -> Tuple[np.ndarray, List[Tuple[float, float, str]]]:
    """Every sentence in `voice`, one after another; (start, end, text) of each."""
    pieces, spans, at = [], [], 0.0
    gap = np.zeros(int(GAP * ws.RATE), np.int16)
    for text in WITH + WITHOUT:
        samples = say(text, voice, folder)
        pieces += [samples, gap]
        spans.append((at, at + len(samples) / ws.RATE, text))
        at += (len(samples) + len(gap)) / ws.RATE
    return noisy(np.concatenate(pieces), rng), spans


def score(heard: Sequence[ws.Heard], spans, seconds: float) -> Dict[str, float]:
    said = sum(1 for _, _, text in spans for w in WORDS if w in text)
    hits, alarms = 0, 0
    for start, end, text in spans:
        for word in WORDS:
            found = [h for h in heard if h.word == word and start - 0.1 <= h.at <= end + GAP]
            if word in text:
                hits += bool(found)
                alarms += max(0, len(found) - 1)
            else:
                alarms += len(found)
    return {"said": said, "hits": hits, "alarms": alarms, "minutes": seconds / 60}


def accuracy(voices: Sequence[str], folder: str, settings: Sequence[Dict[str, object]]) -> None:
    rng = np.random.default_rng(37)
    tracks = [track(v, folder, rng) for v in voices]
    for options in settings:
        total = {"said": 0, "hits": 0, "alarms": 0, "minutes": 0.0}
        rows, cpu = [], 0.0
        for voice, (samples, spans) in zip(voices, tracks):
            began = time.process_time()
            heard = spot_samples(samples, WORDS, **options)
            cpu += time.process_time() - began
            s = score(heard, spans, len(samples) / ws.RATE)
            rows.append(f"{voice} {s['hits']}/{s['said']} {s['alarms']}fa")
            for k in total:
                total[k] += s[k]
        rate = total["hits"] / total["said"]
        per_minute = total["alarms"] / total["minutes"]
        shown = ", ".join(f"{k} {v:g}" if isinstance(v, float) else f"{k} {v}" for k, v in options.items())
        print(
            f"  {shown}: hit rate {rate:.0%} ({total['hits']}/{total['said']}), "
            f"false alarms {per_minute:.1f}/min ({total['alarms']} in {total['minutes']:.1f} min), "
            f"real-time factor {cpu / (total['minutes'] * 60):.2f}  " + ", ".join(rows),
            flush=True,
        )


def spot_samples(samples, words, **options):
    """The word spotter's phrases (bench_hearing.py measures Moonshine's listener)."""
    return listening.spot_samples(samples, words, **{"method": "spotter", **options}).words


def own_speech(folder: str) -> None:
    rng = np.random.default_rng(3)
    samples, spans = track("en-us", folder, rng)
    saying = [(start, end) for start, end, _ in spans]

    def speaking(t: float) -> bool:
        return any(start <= t <= end for start, end in saying)

    spotter_heard = spot_samples(samples, WORDS, speaking=speaking)
    everything = spot_samples(samples, WORDS, barge_in=True)
    phrases = sum(1 for _, _, t in spans for w in WORDS if w in t)
    print(
        f"  the face saying {len(spans)} sentences ({phrases} phrases): {len(spotter_heard)} words told "
        f"while muted; with barge-in it hears {len(everything)}"
    )


def latency(folder: str, runs: int) -> None:
    from baxterface_cli.language.parser import parse

    # "robot" ends the sentence: it ends where the sound last rises over 5 % of its peak.
    sentence = say("look at that robot", "en-gb-x-gbclan", folder)
    envelope = np.abs(sentence.astype(np.int32))
    last_loud = int(np.nonzero(envelope > 0.05 * envelope.max())[0][-1])
    script = parse('on word "robot" { happy }\nforever { wait 1s }', "bench.face")
    delays = []
    for run in range(runs):
        # the word ends at a different point of the spotter's blocks, looks and frames each run
        lead = np.zeros(int((1.0 + run / runs * 0.3) * ws.RATE), np.int16)
        tail = np.zeros(int(1.5 * ws.RATE), np.int16)
        samples = noisy(np.concatenate([lead, sentence, tail]), np.random.default_rng(5), LATENCY_SNR_DB)
        delay = _one_run(samples, script, (len(lead) + last_loud + 1) / ws.RATE)
        if delay is not None:
            delays.append(delay)
    if delays:
        print(
            f"  word end to the first changed frame over {len(delays)}/{runs} runs: "
            f"median {statistics.median(delays) * 1000:.0f} ms, worst {max(delays) * 1000:.0f} ms"
        )
    else:
        print(f"  the word was not heard in {runs} runs")


def _one_run(samples: np.ndarray, script, word_end: float) -> Optional[float]:
    """One real-time run: seconds from the word's end to the first changed frame; None if unheard."""
    from baxterface_cli.engine.live_session import LiveSession
    from baxterface_cli.language import syntax_tree as n

    origin = time.monotonic() + 0.2
    session = LiveSession(script, seed=0, now=0.0, idle=False)
    plain = LiveSession(script, seed=0, now=0.0, idle=False)
    heard: List[Tuple[str, float]] = []
    lock = threading.Lock()

    def on_word(w: str, at: float) -> None:
        with lock:
            heard.append((w, at))

    spotter = ws.WordSpotter(["robot"], on_word, clock=lambda: time.monotonic() - origin, method=METHOD)
    block = int(0.05 * ws.RATE)

    def microphone() -> None:  # the blocks arrive when their last sample has been heard
        for i in range(0, len(samples), block):
            time.sleep(max(0.0, origin + (i + block) / ws.RATE - time.monotonic()))
            spotter.feed(samples[i : i + block])

    thread = threading.Thread(target=microphone)
    thread.start()
    first = None
    frame = 0
    while first is None and frame / 30 < len(samples) / ws.RATE + 1.0:
        t = frame / 30
        time.sleep(max(0.0, origin + t - time.monotonic()))
        with lock:
            words, heard[:] = list(heard), []
        for w, at in words:
            session.post(n.Event("word", w), max(at, session.clock), "microphone")
        state, _ = session.tick(t)
        if state != plain.tick(t)[0]:
            first = time.monotonic() - origin
        frame += 1
    thread.join()
    spotter.close()
    return None if first is None else first - word_end


def main() -> None:
    runs = int(sys.argv[sys.argv.index("--latency-runs") + 1]) if "--latency-runs" in sys.argv else 5
    load = ", ".join(f"{x:.1f}" for x in os.getloadavg())
    print(
        f"load average {load} on {os.cpu_count()} cores; "
        f"PER_PHONE {ws.PER_PHONE:g}, THRESHOLD {phrase_ctc.THRESHOLD:g}"
    )
    with tempfile.TemporaryDirectory() as folder:
        if "--latency-only" in sys.argv:
            latency(folder, runs)
            return
        if "--tune" in sys.argv:
            print(f"tuning on {', '.join(TUNING)}:")
            ctc = [{"method": "ctc", "ctc_threshold": t} for t in (-0.4, -0.5, -0.6, -0.75, -1.0)]
            keyphrase = [{"method": "keyphrase", "per_phone": float(p)} for p in (3, 4, 5, 6)]
            accuracy(TUNING, folder, ctc + keyphrase)
            return
        print(f"held-out voices ({', '.join(HELD_OUT)}), noise {SNR_DB:g} dB under the voice:")
        around = [{"method": "ctc", "ctc_threshold": t} for t in (-0.5, -0.75, -1.0)]
        accuracy(HELD_OUT, folder, [{"method": "keyphrase"}, {"method": "ctc"}] + around)
        print("the face's own speech:")
        own_speech(folder)
        print("a word to the reaction (real time):")
        latency(folder, runs)


if __name__ == "__main__":
    main()
