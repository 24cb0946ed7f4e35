"""Following a face with the head camera: baxterface's FaceFollower against a plain Haar detector.

    python bench/follow_camera.py

Both look at the same synthetic 640x400 streams (tests/support/face_streams.py: real
face photos from scikit-image pasted at known places over real backgrounds),
on one core (cv2.setNumThreads(1)). The baseline runs OpenCV's
frontalface_default cascade over every full grey frame (scaleFactor 1.1,
minNeighbors 4) and looks at the largest face found, through the same
geometry. For each stream: the share of frames with a target among those with
a face in full view after the first second, the RMS error in eye pixels of
those targets, frames with a target where there is no face to follow at all
(cat and text posters), and the median and 95th percentile time a frame.
Times are printed, never asserted: they depend on the machine.
"""

from __future__ import annotations

import math
import statistics
import sys
from pathlib import Path
from typing import Callable, List, Optional, Tuple

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests" / "support"))

import cv2  # noqa: E402

import face_streams as fs  # noqa: E402
from baxterface_cli.robot.face_finder import FaceFollower, eye_target  # noqa: E402

Target = Optional[Tuple[float, float]]


def plain_haar() -> Callable[..., Target]:
    """The baseline: the default cascade on every full frame, the largest face's centre."""
    cascade = cv2.CascadeClassifier(cv2.data.haarcascades + "haarcascade_frontalface_default.xml")

    def update(image, at=None) -> Target:
        grey = cv2.cvtColor(image, cv2.COLOR_BGR2GRAY)
        faces = cascade.detectMultiScale(grey, scaleFactor=1.1, minNeighbors=4)
        if len(faces) == 0:
            return None
        x, y, w, h = max(faces, key=lambda f: f[2] * f[3])
        return eye_target(x + w / 2.0, y + h / 2.0, grey.shape[1], grey.shape[0])

    return update


def percentile(values: List[float], share: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(math.ceil(share * len(ordered))) - 1)]


def row(result: fs.Result) -> str:
    ms = [1000.0 * s for s in result.seconds]
    if result.stream.follow is None:
        wrong = sum(target is not None for target in result.targets)
        quality = f"{'-':>6} {'-':>6} {wrong:>5}"
    else:
        quality = f"{100 * fs.coverage(result):5.1f}% {fs.rmse(result):6.2f} {'-':>5}"
    return f"{quality} {statistics.median(ms):7.1f} {percentile(ms, 0.95):6.1f}"


def report() -> None:
    cv2.setNumThreads(1)  # one core, as the goal is stated
    print(f"{'stream':<12} {'':<8} {'target':>6} {'RMSE':>6} {'wrong':>5} {'median':>7} {'p95':>6}")
    print(f"{'':<12} {'':<8} {'':>6} {'eye px':>6} {'':>5} {'ms':>7} {'ms':>6}")
    ours: List[fs.Result] = []
    theirs: List[fs.Result] = []
    for make in fs.SCENARIOS:
        stream = make()
        follower = FaceFollower()
        ours.append(fs.run(stream, follower.update))
        theirs.append(fs.run(stream, plain_haar()))
        print(f"{stream.name:<12} {'ours':<8} {row(ours[-1])}")
        print(f"{'':<12} {'haar':<8} {row(theirs[-1])}")
        if stream.left_at is not None:
            after = [fs.let_go_after(r) for r in (ours[-1], theirs[-1])]
            ours_after, theirs_after = ("never" if a is None else f"{a:.2f} s" for a in after)
            print(f"{'':<12} let go {ours_after} after the face left (plain Haar: {theirs_after})")
    print()
    for name, results in (("ours", ours), ("haar", theirs)):
        faced = [r for r in results if r.stream.follow is not None]
        ms = [1000.0 * s for r in results for s in r.seconds]
        print(
            f"summary {name}: target in {100 * min(fs.coverage(r) for r in faced):.1f}% of frames at worst, "
            f"RMSE {max(fs.rmse(r) for r in faced):.2f} eye px at worst, "
            f"{sum(t is not None for r in results if r.stream.follow is None for t in r.targets)} "
            f"frames following a non-face; over all frames median {statistics.median(ms):.1f} ms, "
            f"mean {statistics.mean(ms):.1f} ms, p95 {percentile(ms, 0.95):.1f} ms"
        )


if __name__ == "__main__":
    report()
