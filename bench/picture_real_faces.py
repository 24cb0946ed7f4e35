"""docs/images/real-faces-24.png: real faces 24 pixels wide, and what MTCNN's networks find of them.

    python bench/picture_real_faces.py [OUT.png]

A 640x400 camera frame made as the tests make them (tests/support/face_streams.py):
scikit-image's astronaut and five faces of its LFW subset, each 24 pixels wide,
two of them tilted 15 degrees, over its workshop photo with sensor noise. Whole
sweeps of the follower's (`Networks.sweep` over every job of `plan`, upright and
turned) over its first three frames, which differ only in their noise, mark each
face they find with a green square. Below, each face cut out around where it was put and
shown about four times larger, with the square found. No photo is committed: the
picture is made from the photos scikit-image ships.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import List

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests" / "support"))

import cv2  # noqa: E402
import numpy as np  # noqa: E402

import face_streams as fs  # noqa: E402
from baxterface_cli.robot.haar_detector import Box  # noqa: E402
from baxterface_cli.robot.mtcnn_detector import Networks, plan  # noqa: E402

FACES = [("astronaut", 90, 110, 0), ("lfw21", 230, 260, 15), ("lfw47", 330, 120, 0),
         ("lfw0", 430, 300, -15), ("lfw82", 520, 150, 0), ("lfw15", 590, 330, 0)]  # fmt: skip
WIDTH = 24
FRAMES = 3  # whole sweeps, one a frame: at 24 pixels a face can fall between P-Net's steps in one


def frames() -> List[np.ndarray]:
    """The first FRAMES frames of the still scene (only their sensor noise differs)."""

    def scene(t):
        return 1.0, [fs.Placed(name, u, v, WIDTH, angle) for name, u, v, angle in FACES]

    stream = fs.Stream("real faces", FRAMES / fs.FPS, scene, "motorcycle", seed=3)
    return [frame.image for frame in stream.frames()]


def main() -> None:
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else HERE.parent / "docs" / "images" / "real-faces-24.png"
    images = frames()
    image = images[0]
    nets = Networks(cv2)
    found: List[Box] = []
    for each in images:
        for job in [job for jobs in plan(image.shape[1], image.shape[0]).passes for job in jobs]:
            for box in nets.sweep(each, job):
                if not any(abs(box.x - f.x) < 6 and abs(box.y - f.y) < 6 for f in found):
                    found.append(box)
    marked = image.copy()
    for box in found:
        half = box.size / 2.0
        cv2.rectangle(
            marked,
            (int(box.x - half), int(box.y - half)),
            (int(box.x + half), int(box.y + half)),
            (60, 220, 60),
            1,
        )
    side = 3 * WIDTH  # each inset: three face widths around where the face was put
    insets = []
    for _, u, v, _ in FACES:
        x0, y0 = int(u - side / 2), int(v - side / 2)
        crop = marked[max(0, y0) : y0 + side, max(0, x0) : x0 + side]
        crop = cv2.copyMakeBorder(crop, 0, side - crop.shape[0], 0, side - crop.shape[1], cv2.BORDER_CONSTANT)
        inset = 640 // len(FACES)  # about ZOOM times the face's pixels, side by side across the frame
        insets.append(cv2.resize(crop, (inset, inset), interpolation=cv2.INTER_NEAREST))
    strip = np.hstack(insets)
    strip = cv2.copyMakeBorder(strip, 0, 0, 0, 640 - strip.shape[1], cv2.BORDER_CONSTANT)
    picture = np.vstack([marked, np.full((6, 640, 3), 255, np.uint8), strip])
    cv2.imwrite(str(out), picture)
    print(f"wrote {out}: {len(found)} faces found of {len(FACES)}, each {WIDTH} pixels wide")


if __name__ == "__main__":
    main()
