"""Following a person with the head sonar: baxterface's follower against the original's.

    python bench/bench_follow.py

Both run on the same generated traces (tests/traces.py): a person about a
metre away, walking along the sensors' line or standing, seen by noisy
sensors, with stray echoes and sensors behind the robot answering too. The
original is written from the spec, as the tests carry it. Error is the RMS
distance in eye pixels between where the eyes look and where the person is;
lag the delay at which the eyes best match the person; jitter the mean
movement of the eyes from one reading to the next while the person stands.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

from baxterface_cli.following import HumanFollower  # noqa: E402
from traces import OriginalFollower, jitter, lag, rms_error, run, standing, walks  # noqa: E402

TRACES = {**walks(), "standing still": standing()}


def main() -> None:
    print(f"{'trace':<28} {'error px':>16} {'lag s':>14} {'jitter px':>16}")
    print(f"{'':<28} {'original / ours':>16} {'original / ours':>14} {'original / ours':>16}")
    for name, readings in TRACES.items():
        original, ours = run(OriginalFollower(), readings), run(HumanFollower(), readings)
        error = f"{rms_error(original):7.1f} / {rms_error(ours):5.1f}"
        delay = f"{lag(original):5.2f} / {lag(ours):4.2f}"
        # Jitter means something only while the person stands still.
        shake = f"{jitter(original):6.3f} / {jitter(ours):5.3f}" if "still" in name else "-"
        print(f"{name:<28} {error:>16} {delay:>14} {shake:>16}")


if __name__ == "__main__":
    main()
