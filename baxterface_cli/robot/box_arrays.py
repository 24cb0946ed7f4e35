"""Boxes as MTCNN's networks give them, an Nx5 float array of rows (x0, y0, x1, y1, score): made
square, thinned by non-maximum suppression, and told apart from faces the follower knows already.
numpy is imported where it is used, and OpenCV (for its NMSBoxes) too: importing this needs neither.
"""

from __future__ import annotations

from typing import Any, List, Sequence, Tuple

KNOWN_REACH, KNOWN_SIZES = 0.5, (0.75, 1.33)  # a box this near a known face, of about its size, is it


def square(boxes: Any) -> Any:
    """The boxes made square about their centres, on their longer side."""
    import numpy as np

    boxes = boxes.copy()
    w, h = boxes[:, 2] - boxes[:, 0], boxes[:, 3] - boxes[:, 1]
    side = np.maximum(w, h)
    boxes[:, 0] += (w - side) / 2
    boxes[:, 1] += (h - side) / 2
    boxes[:, 2], boxes[:, 3] = boxes[:, 0] + side, boxes[:, 1] + side
    return boxes


def nms(boxes: Any, overlap: float, smaller: bool = False) -> Any:
    """The indices of the boxes kept, surest first: each box that overlaps a surer one by more than
    `overlap` (of their union: OpenCV's NMSBoxes; or of the `smaller` one's area) is dropped."""
    import numpy as np

    if len(boxes) == 0:
        return np.empty(0, int)
    if not smaller:
        import cv2

        rects = np.stack(
            [boxes[:, 0], boxes[:, 1], boxes[:, 2] - boxes[:, 0], boxes[:, 3] - boxes[:, 1]], axis=1
        )
        kept = cv2.dnn.NMSBoxes(rects.tolist(), boxes[:, 4].tolist(), 0.0, overlap)
        return np.array(kept, int).reshape(-1)
    order = list((-boxes[:, 4]).argsort(kind="stable"))
    area = (boxes[:, 2] - boxes[:, 0] + 1) * (boxes[:, 3] - boxes[:, 1] + 1)
    chosen: List[int] = []
    while order:
        i, rest = order[0], np.array(order[1:], int)
        chosen.append(i)
        if not len(rest):
            break
        w = np.maximum(
            0.0, np.minimum(boxes[i, 2], boxes[rest, 2]) - np.maximum(boxes[i, 0], boxes[rest, 0]) + 1
        )
        h = np.maximum(
            0.0, np.minimum(boxes[i, 3], boxes[rest, 3]) - np.maximum(boxes[i, 1], boxes[rest, 1]) + 1
        )
        inter = w * h
        order = list(rest[inter / np.minimum(area[i], area[rest]) <= overlap])
    return np.array(chosen, int)


def of_known(boxes: Any, known: Sequence[Tuple[float, float, float]]) -> Any:
    """Which of `boxes` are of a known face (x, y, width): centred within KNOWN_REACH of its width,
    of about its size (the follower would take them for it: `same_face`)."""
    import numpy as np

    cx, cy, side = (boxes[:, 0] + boxes[:, 2]) / 2, (boxes[:, 1] + boxes[:, 3]) / 2, boxes[:, 2] - boxes[:, 0]
    near = [
        (np.hypot(cx - x, cy - y) < KNOWN_REACH * s)
        & (side > KNOWN_SIZES[0] * s)
        & (side < KNOWN_SIZES[1] * s)
        for x, y, s in known
    ]
    return np.any(near, axis=0)
