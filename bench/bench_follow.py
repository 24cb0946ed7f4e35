"""Following, against the baselines, in one run: the head sonar (baxterface's
follower against the original's), then the head camera (bench/follow_camera.py:
baxterface's FaceFollower with MTCNN's networks against the same follower with
OpenCV's cascades and a plain Haar detector on every full frame). Real faces by
size, the networks beside the cascades, are bench/bench_face_sizes.py's.

    taskset -c 0 python bench/bench_follow.py

`sonar_report()` runs both on the faulty traces of tests/support/traces.py, real
sonar's faults: 4 % of what the sensors report is spurious (a random sensor,
anything from 0.3 to 3.5 m, so often nearer than the person), 15 % of the
person's readings drop out, and in half the traces a still object stands
further off on the other side. A person walks back and forth along the whole
sensor line at 0.3 or 1.0 spacings a second, or stands still. The original
is written from the spec, as the tests carry it (`HumanFollower.original()`
is the same, number for number). One row a trace: RMSE is the root mean
square distance in eye pixels between where the eyes look and where the
person is (after the first second), lag the delay at which the eyes best
match a walker, still std the standard deviation of where the eyes look
while the person stands (after the first two seconds, once the original's
35-reading average is full); new/original is the goal's ratio. Then the
worst ratios against the goals (at most 0.6 for RMSE at both speeds, at most
1.5 for still std), and still std's ratio over a wider sweep of still people,
whose tail the table's few seeds cannot show.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests" / "support"))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from baxterface_cli.robot.following import HumanFollower  # noqa: E402
from traces import OriginalFollower, faulty_trace, faulty_traces, lag, rms_error, run, spread, still  # noqa: E402

GOALS = {"walk 0.3/s": 0.6, "walk 1.0/s": 0.6, "still": 1.5}
SWEEP_AT = (-3.0, -1.5, -0.2, 0.0, 0.5, 1.0, 2.2, 3.0)  # on a sensor, between two, and in between
SWEEP_SEEDS = range(1, 16)


def sonar_report() -> None:
    """The original and the new follower on the faulty traces: a table, then the worst ratios."""
    row = "{:<30} {:>8} {:>5} {:>8}   {:>8} {:>5}   {:>8} {:>5} {:>8}".format
    print(f"{'':<30} {'RMSE px':^23}   {'lag s':^14}   {'still std px':^23}".rstrip())
    print(row("trace", "original", "new", "new/orig", "original", "new", "original", "new", "new/orig"))
    worst = dict.fromkeys(GOALS, 0.0)
    for name, readings in faulty_traces().items():
        original, new = run(OriginalFollower(), readings), run(HumanFollower(), readings)
        kind = next(kind for kind in GOALS if name.startswith(kind))
        error = (f"{rms_error(original):.1f}", f"{rms_error(new):.1f}")
        if kind == "still":  # lag means nothing for someone standing
            ratio = spread(new) / spread(original)
            cells = (*error, "-", "-", "-", f"{spread(original):.2f}", f"{spread(new):.2f}", f"{ratio:.2f}")
        else:
            ratio = rms_error(new) / rms_error(original)
            cells = (*error, f"{ratio:.2f}", f"{lag(original):.2f}", f"{lag(new):.2f}", "-", "-", "-")
        worst[kind] = max(worst[kind], ratio)
        print(row(name, *cells))
    print("worst new/original:")
    for kind, goal in GOALS.items():
        measure = "still std" if kind == "still" else f"RMSE, {kind}"
        print(f"  {measure:<18} {worst[kind]:5.2f}  (goal: at most {goal})")
    ratios = sorted(
        spread(run(HumanFollower(), readings)) / spread(run(OriginalFollower(), readings))
        for readings in still_sweep()
    )
    print(
        f"still std, new/original, on {len(ratios)} more still traces ({len(SWEEP_AT)} places, with and"
        f" without the object, seeds {SWEEP_SEEDS[0]}-{SWEEP_SEEDS[-1]}):"
    )
    print(
        f"  median {ratios[len(ratios) // 2]:.2f}, 95th percentile {ratios[int(0.95 * len(ratios))]:.2f},"
        f" worst {ratios[-1]:.2f}; {sum(r > GOALS['still'] for r in ratios)} over {GOALS['still']}"
    )


def still_sweep():
    """More still people than the table shows: places along the line, with and without the object."""
    for at in SWEEP_AT:
        for second_object in (False, True):
            for seed in SWEEP_SEEDS:
                yield faulty_trace(still(at), 30.0, seed, second_object)


def main() -> None:
    sonar_report()
    print()
    try:
        from follow_camera import report as camera_report
    except ImportError as e:  # OpenCV or scikit-image missing: the sonar half still stands
        print(f"camera: not run ({e}); pip install '.[camera,test]'")
        return
    camera_report()


if __name__ == "__main__":
    main()
