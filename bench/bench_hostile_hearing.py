"""Hearing and recordings under hostile input (issue 43, 7 to 9): what they cost, against a baseline
of the same run.

    python bench/bench_hostile_hearing.py [phrases] [zeros] [texts] [says]

With no phase named, all run.

phrases (7): the listener's CPU a second of sound (one core's, time.process_time) over 10 s of
speech (greeting.ogg twice), for 1, 10 and 30 short phrases, 32 of two words, and the heaviest phrase
the language takes (eight words the dictionary spells four or five ways: 1,323 phones), each as a
ratio to one phrase ("hello", the baseline); then `explain --hear` of 1,000 phrases over 8 minutes
(the issue's: no answer in 300 s) and of 32 two-word phrases over 590 s: the time to the answer and
its line. The bounds (LIMITS.max_phrases, max_phones, max_phone_seconds) refuse both at once.

zeros (8): a 190 MB WAV of zero bytes, 8 channels of 8 bits at 44.1 kHz (565 s, a constant at full
scale), against a 190 MB WAV of 16-bit zeros (259 s of true silence), the baseline: reading each
(read_sound), and the time and peak memory of `explain` saying each (`say file`, analysis cache
empty) and hearing each (`--hear`, one phrase).

texts (9b): a studio press after each edit of a `say file`'s words (compile_script, in-process, the
analysis cache empty at first), for greeting.ogg (5 s) and it eight times over (41 s): each press's
time as a ratio to the first (the baseline: the recording found from nothing), the recording's reads,
hama's runs and the analyses kept on disk so far. Each press says how its phonemes were found
(aligned: the words fit; recognised: they did not).

says (9c): the node's LiveSession and SoundPlaySpeaker in-process, 150 says of 3 s: RSS and the
utterances alive (gc) after 20 and after 150, for 150 new texts against one text 150 times (the
baseline, same run): RSS after 150 as a ratio to the baseline's.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import wave
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests" / "support"))
from listened_words import HEAVY, WORDS  # noqa: E402


def explain(folder: Path, *args: str) -> tuple:
    """(seconds, peak MB, exit code, the first line of stderr) of `baxterface explain ARGS`."""
    env = dict(os.environ, XDG_CACHE_HOME=str(folder / "cache"), PYTHONPATH=str(ROOT))
    start = time.monotonic()
    with open(str(folder / "err.txt"), "w+") as err:
        child = subprocess.Popen(
            [sys.executable, "-m", "baxterface_cli", "explain", *args],
            cwd=str(folder),
            env=env,
            stdout=subprocess.DEVNULL,
            stderr=err,
        )
        timer = threading.Timer(600, child.kill)
        timer.start()
        _, status, usage = os.wait4(child.pid, 0)
        timer.cancel()
        child.returncode = os.WEXITSTATUS(status) if os.WIFEXITED(status) else -os.WTERMSIG(status)
        err.seek(0)
        line = (err.read().strip().splitlines() or [""])[0]  # a diagnostic: its first line
    return time.monotonic() - start, usage.ru_maxrss // 1024, child.returncode, line[:160]


def handlers(phrases) -> str:
    return "".join(f'on word "{p}" {{ happy }}\n' for p in phrases)


def phrases(folder: Path) -> None:
    from baxterface_cli.speech.listening import spot_samples
    from baxterface_cli.speech.word_spotter import WordError, read_recording

    speech = read_recording(str(ROOT / "scripts_examples" / "greeting.ogg"))
    speech = np.concatenate([speech, speech])
    seconds = len(speech) / 16000
    pairs = [f"{a} {b}" for a, b in zip(WORDS, WORDS[1:] + WORDS[:1])][:32]
    cases = [("1 phrase (baseline)", ["hello"]), ("10 phrases", WORDS[:10]), ("30 phrases", WORDS[:30])]
    cases += [("32 two-word phrases", pairs), ("the heaviest phrase", [HEAVY])]
    print(f"the listener over {seconds:.1f} s of speech, CPU a second of sound:")
    base = None
    for label, words in cases:
        start = time.process_time()
        try:
            spot_samples(speech, words)
        except WordError as e:
            print(f"  {label:24} refused: {e}")
            continue
        cost = (time.process_time() - start) / seconds
        base = base or cost
        print(f"  {label:24} {cost * 1000:6.0f} ms   x{cost / base:.2f}")
    for name, length in (("eight.wav", 480), ("long.wav", 590)):
        with wave.open(str(folder / name), "wb") as w:
            w.setnchannels(1), w.setsampwidth(2), w.setframerate(16000)
            noise = np.random.default_rng(1).normal(0, 3000, 16000 * length).astype(np.int16)
            w.writeframes(noise.tobytes())  # sound all along: every second is listened to
    many = [f"{a} {b}" for a in WORDS for b in WORDS if a != b][:1000]
    (folder / "many.face").write_text(handlers(many))
    (folder / "pairs.face").write_text(handlers(pairs))
    for label, args in (
        ("1,000 phrases over 480 s (the issue's)", ("many.face", "--hear", "eight.wav")),
        ("32 two-word phrases over 590 s", ("pairs.face", "--hear", "long.wav")),
    ):
        took, peak, code, line = explain(folder, *args)
        print(f"  explain --hear, {label}: {took:.1f} s, exit {code}: {line}")


def zeros(folder: Path) -> None:
    from baxterface_cli.speech.audio_files import read_sound

    size = 190 * 2**20
    layouts = (("silence.wav", 8, 2, 48000, "16-bit zeros, 8 channels at 48 kHz (baseline)"),)
    layouts += (("zeros.wav", 8, 1, 44100, "8-bit zero bytes, 8 channels at 44.1 kHz"),)
    for name, channels, width, rate, _ in layouts:
        with wave.open(str(folder / name), "wb") as w:
            w.setnchannels(channels), w.setsampwidth(width), w.setframerate(rate)
            block = bytes(2**20)
            for _ in range(size // 2**20):
                w.writeframesraw(block)
    (folder / "hello.face").write_text('on word "hello" { happy }\n')
    rows = []
    for name, _, _, _, label in layouts:
        (folder / f"say-{name}.face").write_text(f'say file "{name}"\n')
        start = time.monotonic()
        sound = read_sound(str(folder / name))
        read = time.monotonic() - start
        said = explain(folder, f"say-{name}.face")
        heard = explain(folder, "hello.face", "--hear", name)
        rows.append((label, sound.duration, read, said, heard))
    base = rows[0]
    for label, duration, read, said, heard in rows:
        print(f"{label}, {duration:.0f} s:")
        print(f"  read_sound {read:6.2f} s   x{read / base[2]:.2f}")
        print(f"  say file   {said[0]:6.2f} s   x{said[0] / base[3][0]:.2f}   {said[1]} MB   exit {said[2]}")
        print(
            f"  --hear     {heard[0]:6.2f} s   x{heard[0] / base[4][0]:.2f}   {heard[1]} MB   exit {heard[2]}"
        )


def texts(folder: Path) -> None:
    from baxterface_cli import parse
    from baxterface_cli.engine.compiler import compile_script
    from baxterface_cli.speech import phoneme_recogniser, recordings
    from baxterface_cli.speech.audio_files import read_sound
    from baxterface_cli.speech.soundtrack import write_wav

    os.environ["XDG_CACHE_HOME"] = str(folder / "cache")  # read at each analysis: empty
    greeting = read_sound(str(ROOT / "scripts_examples" / "greeting.ogg"))
    write_wav(str(folder / "long.wav"), np.concatenate([greeting.samples] * 8), greeting.rate)
    shutil.copy(str(ROOT / "scripts_examples" / "greeting.ogg"), str(folder / "greeting.ogg"))
    counts = {"recogniser": 0, "read": 0}

    def counted(name, function):
        def counting(*args, **kwargs):
            counts[name] += 1
            return function(*args, **kwargs)

        return counting

    phoneme_recogniser.recognise = counted("recogniser", phoneme_recogniser.recognise)
    recordings.read_sound = counted("read", recordings.read_sound)
    presses = ["hello there", "hello here", "hello there again"]
    presses += [
        "Completely different words are written here by mistake.",
        "Completely different words are written here by mistake, twice.",
    ]
    for name in ("greeting.ogg", "long.wav"):
        length = greeting.duration * (8 if name == "long.wav" else 1)
        print(f"a studio press after each edit of the words of `say file {name!r}` ({length:.0f} s):")
        base = None
        for text in presses:
            start = time.monotonic()
            script = parse(f'say file "{name}" text "{text}"', str(folder / "studio.face"))
            (said,) = compile_script(script).speech
            took = time.monotonic() - start
            base = base or took
            kept = len(list((folder / "cache" / "baxterface" / "lipsync").glob("*.json")))
            label = f"{text[:30]!r}" + (" (baseline)" if took is base else "")
            print(
                f"  {label:44} {took * 1000:6.0f} ms   x{took / base:.2f}   read {counts['read']}, "
                f"recogniser {counts['recogniser']}, {kept} files kept; {said.utterance.recording.method}"
            )


def says(folder: Path) -> None:
    import gc

    from baxterface_cli import parse
    from baxterface_cli.engine.effects import Speech
    from baxterface_cli.engine.live_face import sleep_face
    from baxterface_cli.engine.live_session import LiveSession
    from baxterface_cli.ros.speakers import SoundPlaySpeaker
    from baxterface_cli.speech.synthesis import Utterance

    class Link:
        def publisher(self, topic, kind):
            return self

        def listeners(self):
            return 1

        def publish(self, **fields):
            pass

    def rss() -> float:
        with open("/proc/self/status") as status:
            return next(int(line.split()[1]) for line in status if line.startswith("VmRSS")) / 1024

    print("the node's session and sound_play speaker in-process, 150 says (3 s each, 16 frames):")
    speaker = SoundPlaySpeaker(Link(), print)
    found = {}
    for label, new in (("the same text 150 times (baseline)", False), ("150 new texts (the issue's)", True)):
        session = LiveSession(start=sleep_face(), idle=True, now=0.0, seed=None, keep_up=True)
        now, marks = 0.0, {}
        for said in range(1, 151):
            text = f"Command number {said if new else 0} is a sentence of some seconds said now."
            session.run(parse(f'say "{text}"', "command"), now)
            for k in range(16):
                for cue in session.tick(now + 0.05 + k * 0.2)[1]:
                    if isinstance(cue.effect, Speech):
                        speaker.speak(cue.effect)
            now += 3.2
            if said in (20, 150):
                gc.collect()
                marks[said] = (rss(), sum(type(o) is Utterance for o in gc.get_objects()))
        found[label] = marks
        base = found[next(iter(found))]
        print(
            f"  {label:36} RSS after 20 {marks[20][0]:5.1f} MB, after 150 {marks[150][0]:5.1f} MB "
            f"(x{marks[150][0] / base[150][0]:.2f} the baseline's); "
            f"utterances kept {marks[20][1]} -> {marks[150][1]}"
        )
    speaker.close()


def main() -> None:
    wanted = sys.argv[1:] or ["phrases", "zeros", "texts", "says"]
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    with tempfile.TemporaryDirectory() as tmp:
        for phase in wanted:
            {"phrases": phrases, "zeros": zeros, "texts": texts, "says": says}[phase](Path(tmp))


if __name__ == "__main__":
    main()
