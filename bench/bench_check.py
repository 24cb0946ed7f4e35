"""Checking stays linear: pathological 256 KiB scripts against a valid one.

    python bench/bench_check.py

Each input fills the size limit with one line repeated. The baseline, timed
in the same run, is the densest valid script the limits let through; each
pathological input prints its time and its ratio to the baseline, then the
whole `baxterface check` command (start-up included) on the slowest input,
against the goal of 2 s. Before errors were capped and rendered in one pass,
32,000 misspelt lines took 45 s; before the piece limit, 256 KiB of 'a' lines
took 6.5 s.
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import time

from baxterface_cli import ScriptError, parse
from baxterface_cli.core.face_constants import LIMITS

BASELINE = ("valid: 'look 40 -20 in 0.05s' lines", "look 40 -20 in 0.05s\n")
INPUTS = [
    ("an error on each: 'mouth x' lines", "mouth x\n"),
    ("unknown word: 'a' lines", "a\n"),
    ("misspelling: 'hapy' lines", "hapy\n"),
    ("warning: 'look 500 0 in 0s' lines", "look 500 0 in 0s\n"),
    ("syntax error: 'look' lines", "look\n"),
    ("unclosed '{', then 'hapy' lines", None),
]


def filled(line: str) -> str:
    """`line` repeated to the size limit, or to just under the piece limit."""
    pieces = len(line.split()) + 1
    return line * min(LIMITS.max_bytes // len(line), LIMITS.max_pieces // pieces)


def command_seconds(text: str) -> float:
    """Wall time of `baxterface check` on `text`, as a user would run it."""
    with tempfile.NamedTemporaryFile("w", suffix=".face") as f:
        f.write(text)
        f.flush()
        start = time.perf_counter()
        subprocess.run([sys.executable, "-m", "baxterface_cli", "check", f.name], capture_output=True)
        return time.perf_counter() - start


def timed(text: str) -> float:
    """Seconds to parse and check `text` and render what is wrong with it."""
    start = time.perf_counter()
    try:
        parse(text, "bench.face")
    except ScriptError as e:
        e.render()
    return time.perf_counter() - start


def main() -> None:
    parse("blink")  # the parser is built once, outside the timings
    name, line = BASELINE
    base = min(timed(filled(line)) for _ in range(2))
    print(f"parse + check of up to {LIMITS.max_bytes // 1024} KiB, best of 2")
    print(f"  {name:<38} {base:6.2f} s  (baseline)")
    slowest = (base, filled(line))
    for name, line in INPUTS:
        text = filled(line) if line else "repeat 2 {\n" + filled("hapy\n")[:-16]
        seconds = min(timed(text) for _ in range(2))
        slowest = max(slowest, (seconds, text))
        print(f"  {name:<38} {seconds:6.2f} s  {seconds / base:5.1f}x")
    whole = min(command_seconds(slowest[1]) for _ in range(2))
    print(f"'baxterface check' on the slowest, start-up included: {whole:.2f} s (goal: under 2 s)")


if __name__ == "__main__":
    main()
