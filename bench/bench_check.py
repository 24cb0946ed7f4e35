"""Checking stays linear: pathological 256 KiB scripts against a valid one.

    python bench/bench_check.py

Each input fills the size limit with one line repeated. The baseline, timed
in the same run, is a valid script of similar one-line statements; each
pathological input prints its time and its ratio to the baseline. Before
errors were capped and rendered in one pass, 32,000 misspelt lines took 45 s.
"""

from __future__ import annotations

import time

from baxterface_cli import ScriptError, parse
from baxterface_cli.parser import grammar
from baxterface_cli.tables import LIMITS

BASELINE = ("valid: 'skin 1' lines", "skin 1\n")
INPUTS = [
    ("unknown word: 'a' lines", "a\n"),
    ("misspelling: 'hapy' lines", "hapy\n"),
    ("warning: 'look 500 0 in 0s' lines", "look 500 0 in 0s\n"),
    ("syntax error: 'look' lines", "look\n"),
    ("unclosed '{', then 'hapy' lines", None),
]


def filled(line: str) -> str:
    return line * (LIMITS.max_bytes // len(line))


def timed(text: str) -> float:
    """Seconds to parse and check `text` and render what is wrong with it."""
    start = time.perf_counter()
    try:
        parse(text, "bench.face")
    except ScriptError as e:
        e.render()
    return time.perf_counter() - start


def main() -> None:
    grammar()  # built once, outside the timings
    name, line = BASELINE
    base = min(timed(filled(line)) for _ in range(2))
    print(f"parse + check of {LIMITS.max_bytes // 1024} KiB, best of 2")
    print(f"  {name:<34} {base:6.2f} s  (baseline)")
    for name, line in INPUTS:
        text = filled(line) if line else "repeat 2 {\n" + filled("hapy\n")[:-16]
        seconds = min(timed(text) for _ in range(2))
        print(f"  {name:<34} {seconds:6.2f} s  {seconds / base:5.1f}x")


if __name__ == "__main__":
    main()
