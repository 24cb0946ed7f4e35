"""What saying through the speech process costs: a short `say`, in this process and through it.

    .venv/bin/python bench/bench_speech_process.py

espeak-ng runs in a child process of its own (speech/espeak_process.py) so that its crashes take
only that child down. Measured in one run, each way on the same 40 different short texts
(nothing cached), median and p95 of one `say`:

- in this process: libespeak-ng called here, as the engine did before (the baseline);
- through the kept child: the engine's `say` as it is now (a round trip through two pipes);
- the espeak-ng program for each text (`--stdout`), the alternative considered: no event times;
- and the first `say` of a fresh program (the child's start with it), before and after.
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Callable, List

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from baxterface_cli.speech import espeak  # noqa: E402
from baxterface_cli.speech.espeak_process import EspeakProcess  # noqa: E402
from baxterface_cli.speech.synthesis import SpeechEngine, _utterance  # noqa: E402

COUNT = 40
COLD_RUNS = 8


def texts(tag: str) -> List[str]:
    return [f"Hello there, number {tag}{i}." for i in range(COUNT)]


def timed(say: Callable[[str], object], tag: str) -> List[float]:
    say("warm up")
    times = []
    for text in texts(tag):
        start = time.perf_counter()
        say(text)
        times.append(time.perf_counter() - start)
    return times


def in_process(text: str) -> object:
    """The engine's work before: libespeak-ng here, then the same trimming and timing."""
    spoken = espeak.synthesize(espeak.espeak_library()[0], text, "en", 175)
    samples = np.frombuffer(spoken.pcm, dtype=np.int16)
    return _utterance(text, "en", 175, samples, espeak.espeak_library()[1], spoken.heard)


def program(text: str) -> object:
    return subprocess.run(["espeak-ng", "--stdout", text], capture_output=True, check=True).stdout


COLD = {
    "in this process": "from baxterface_cli.speech import espeak; "
    "espeak.synthesize(espeak.espeak_library()[0], 'Hello there.', 'en', 175)",
    "through the child": "from baxterface_cli.speech.synthesis import engine; engine().say('Hello there.')",
}
IMPORTS = "import baxterface_cli.speech.synthesis"


def cold(code: str) -> float:
    """Seconds from a fresh program's start to its first `say` said, less the imports."""
    probe = f"import time; {IMPORTS}; start = time.perf_counter(); {code}; print(time.perf_counter() - start)"
    runs = [
        float(
            subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True).stdout
        )
        for _ in range(COLD_RUNS)
    ]
    return statistics.median(runs)


def line(name: str, times: List[float]) -> str:
    times = sorted(times)
    p95 = times[min(len(times) - 1, round(0.95 * (len(times) - 1)))]
    return f"  {name:32s} median {statistics.median(times) * 1000:6.1f} ms   p95 {p95 * 1000:6.1f} ms"


def main() -> None:
    print(subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())
    engine = SpeechEngine(EspeakProcess())
    here, there = timed(in_process, "a"), timed(engine.say, "b")
    print(f"one short say ({COUNT} different texts, espeak-ng {espeak.espeak_version()})")
    print(line("in this process (before)", here))
    print(line("through the kept child (after)", there))
    print(line("espeak-ng program each time", timed(program, "c")))
    ratio = statistics.median(there) / statistics.median(here)
    print(f"  child / in process: {ratio:.2f}x")
    engine.close()
    print(f"first say of a fresh program, less imports (median of {COLD_RUNS})")
    for name, code in COLD.items():
        print(f"  {name:32s} {cold(code) * 1000:6.1f} ms")


if __name__ == "__main__":
    main()
