"""OpenCV's face cascades, and the three searches the face follower makes with them.

The cascades are the Haar ones OpenCV's wheels ship in `cv2.data`, or Debian's
`opencv-data` package in /usr/share/opencv4/haarcascades (nothing is downloaded;
see `cascade_path`). All sizes are in the image's pixels; a face's size is its width.

- **Sweep** (`sweep`): the whole image, one `Job` at a time. A job is a few
  face sizes, each searched on the image shrunk so that size becomes the
  cascade's 20-pixel window (the cascade then steps 2 pixels, a tenth of a
  face, at every size), upright or turned by +-20 degrees, on some rows of it.
  `plan` cuts a whole search into jobs of about equal cost, so the follower
  can spread it over frames: faces 24 pixels wide (at 640 across) cost far
  more than all the larger ones together.
- **Near** (`near`): the region around where a tracked face is expected,
  scaled so the face is 48 pixels wide and turned to show it upright: a few
  milliseconds at any size.
- **Check** (`verdict`): other cascades, trained apart, on the face turned
  upright and scaled so it is 48 pixels wide: frontalface_default and
  frontalface_alt must both find it (FOUND); strictly (SURE), alt must also
  agree strongly over the face as it is, mirrored, turned 10 degrees either
  way and seen a little nearer and further. A face stays a face in all of
  them; a cat, a page of text or a patch of a busy photo that fools one
  cascade seldom does.
"""

from __future__ import annotations

import math
import os
from typing import Any, List, NamedTuple, Optional, Sequence, Tuple

from ..extras import MissingTool

WINDOW = 20  # pixels: the face cascades' window
REFERENCE_WIDTH = 640.0  # face sizes below are for an image this wide, and scale with it
SMALLEST = 22.0  # the smallest face size searched: a face 24 pixels wide is found at 22 to 27
SMALLEST_TURNED = 25.0  # ... and turned
FINE_STEP = 1.15  # between the sizes of the small faces (up to COARSE), the hard ones to find ...
COARSE = 58.0
COARSE_STEP = 1.2  # ... and of the larger ones, easily found at any size near theirs
TURNS = (20.0, -20.0)  # degrees the image is turned to show a tilted face upright ...
TURNED_STEP = 1.2  # ... at fewer sizes, as such a face, once found, is tracked at any tilt
TURNED = 1.15  # the cost of searching a turned image, for the one upright
NOT_A_FACE, FOUND, SURE = 0, 1, 2  # the check's verdicts
JOB_WINDOWS = 15_000  # cascade windows a job looks at: 4 to 12 ms on a slow machine's core


class Box(NamedTuple):
    """A face: its centre and width in image pixels, and the turn (degrees) that showed it upright."""

    x: float
    y: float
    size: float
    turn: float = 0.0


class Region(NamedTuple):
    """Part of an image, scaled and turned: `scale` its pixels per image pixel, (x0, y0) its corner
    in the image, (cx, cy) the face's centre in it, `back` the affine map that turns it back."""

    pixels: Any
    scale: float
    x0: int
    y0: int
    cx: float
    cy: float
    back: Any


class Job(NamedTuple):
    """A slice of a whole-image search: faces of `sizes` (image pixels), the image turned by
    `turn` degrees, the rows from `rows[0]` to `rows[1]` (fractions of its height)."""

    sizes: Tuple[float, ...]
    turn: float = 0.0
    rows: Tuple[float, float] = (0.0, 1.0)


def same_face(a: Box, b: Box, reach: float = 0.5) -> bool:
    """Whether two boxes are plausibly one face, `reach` of its width apart at most, of about one size."""
    return math.hypot(a.x - b.x, a.y - b.y) < reach * max(a.size, b.size) and 0.67 < a.size / b.size < 1.5


def _sizes(low: float, high: float, step: float) -> List[float]:
    sizes, size = [], low
    while size < high:
        sizes.append(size)
        size *= step
    return sizes


def turned_size(width: float, height: float, turn: float) -> Tuple[int, int]:
    """The size of the image `width` x `height` turned by `turn` degrees, whole."""
    c, s = abs(math.cos(math.radians(turn))), abs(math.sin(math.radians(turn)))
    return int(math.ceil(width * c + height * s)), int(math.ceil(width * s + height * c))


def _span(corners: Sequence[Tuple[float, float]], top: float, bottom: float) -> Tuple[float, float]:
    """The leftmost and rightmost x of the convex polygon `corners` between rows top and bottom."""
    xs = [x for x, y in corners if top <= y <= bottom]
    for (x0, y0), (x1, y1) in zip(corners, [*corners[1:], corners[0]]):
        for row in (top, bottom):
            if min(y0, y1) <= row <= max(y0, y1) and y0 != y1:
                xs.append(x0 + (x1 - x0) * (row - y0) / (y1 - y0))
    return (min(xs), max(xs)) if xs else (0.0, 0.0)


def _windows(width: int, height: int, size: float, turn: float) -> float:
    """About how many windows (2-pixel steps) a search for faces `size` wide looks at."""
    w, h = width * WINDOW / size, height * WINDOW / size
    return max(0.0, (w - WINDOW) / 2.0) * max(0.0, (h - WINDOW) / 2.0) * (TURNED if turn else 1.0)


class Plan(NamedTuple):
    """A whole-image search cut into jobs: the large faces upright (`large`, cheap and searched
    often) and three passes (`passes`): the small faces upright, then turned each way with the
    large ones."""

    large: List[Job]
    passes: List[List[Job]]


def plan(width: int, height: int, smallest: float = 0.0) -> Plan:
    """The jobs of a whole-image search of a `width` x `height` image, for faces `smallest` pixels
    wide or more. A job costs about JOB_WINDOWS: sizes are packed together, and a size that costs
    more is cut into bands of rows."""
    scale = width / REFERENCE_WIDTH

    def sized(low: float, high: float, step: float) -> List[float]:
        return [s * scale for s in _sizes(low, high, step) if s * scale >= max(WINDOW, smallest)]

    large = sized(COARSE, 0.9 * min(width, height) / scale, COARSE_STEP)
    upright = sized(SMALLEST, COARSE, FINE_STEP)
    passes = [_jobs(width, height, upright, 0.0)]
    for turn in TURNS:
        passes.append(_jobs(width, height, sized(SMALLEST_TURNED, COARSE, TURNED_STEP) + large, turn))
    return Plan(_jobs(width, height, large, 0.0), passes)


def _jobs(width: int, height: int, sizes: Sequence[float], turn: float) -> List[Job]:
    """`sizes` searched in jobs of about JOB_WINDOWS: in bands of rows while a band is worth more
    than a size (the small ones), then several sizes a job (the large ones)."""
    jobs: List[Job] = []
    rest = sorted(sizes)
    while rest:
        cost = sum(_windows(width, height, s, turn) for s in rest)
        cheap = [s for s in rest if _windows(width, height, s, turn) <= JOB_WINDOWS / 2]
        if cost <= JOB_WINDOWS or len(cheap) == len(rest) and cost <= 2 * JOB_WINDOWS:
            jobs.append(Job(tuple(rest), turn))
            break
        if len(cheap) == len(rest):  # every size cheap: as many as fit in a job
            taken: List[float] = []
            while rest and sum(_windows(width, height, s, turn) for s in taken + rest[:1]) <= JOB_WINDOWS:
                taken.append(rest.pop(0))
            jobs.append(Job(tuple(taken or [rest.pop(0)]), turn))
            continue
        # The costly sizes, every one in each band: a face is found where windows of nearby
        # sizes agree, so a band holds them all.
        costly = [s for s in rest if s not in cheap]
        bands = max(1, round(sum(_windows(width, height, s, turn) for s in costly) / JOB_WINDOWS))
        jobs += [Job(tuple(costly), turn, (k / bands, (k + 1) / bands)) for k in range(bands)]
        rest = cheap
    return jobs


# Where Debian's opencv-data puts the cascades, for its python3-opencv, which has no `cv2.data`.
SYSTEM_CASCADES = ("/usr/share/opencv4/haarcascades", "/usr/share/opencv/haarcascades")
SYSTEM_PYTHON = "/usr/lib/python3"  # where a distribution's python3-opencv is installed


def cascade_folders(cv2: Any) -> List[str]:
    """Where the cascades may be, absolute paths only, in order: the wheel's `cv2.data`, then
    Debian's. A bare name would be looked up in the working directory, where anyone may put one."""
    wheel = getattr(getattr(cv2, "data", None), "haarcascades", "")
    folders = [wheel] if isinstance(wheel, str) and os.path.isabs(wheel) else []
    return folders + list(SYSTEM_CASCADES)


def cascade_path(cv2: Any, name: str) -> str:
    """The absolute path of cascade `name`, or MissingTool saying what to install here."""
    for folder in cascade_folders(cv2):
        path = os.path.join(folder, name)
        if os.path.isfile(path):
            return path
    where = ", ".join(cascade_folders(cv2))
    raise MissingTool(f"following a face needs OpenCV's {name} (looked in {where}): {install_hint(cv2)}")


def install_hint(cv2: Any) -> str:
    """What installs the cascades for the OpenCV this Python imported."""
    if str(getattr(cv2, "__file__", "")).startswith(SYSTEM_PYTHON):
        return "this is the system's OpenCV, whose cascades are in 'apt install opencv-data'"
    return "opencv-python-headless 4.x ships them: pip install 'baxterface[camera]'"


class Cascades:
    """The face cascades, and the sweep, near and check searches made with them (see the module)."""

    FIND = "haarcascade_frontalface_alt2.xml"
    CHECK = "haarcascade_frontalface_default.xml"
    AGREE = "haarcascade_frontalface_alt.xml"
    NEIGHBOURS = 1  # more windows than this, of nearby places and sizes, make a face in a sweep
    AGREEMENT = 50  # windows of the agree cascade, over the face and its variants, that make a face
    TRACK_SIZE = 48.0  # pixels: the face's width in the region searched while tracking
    TRACK_TURNS = (0.0, 20.0, -20.0)  # degrees the tracking region is turned to show a tilted face upright
    NAME = "OpenCV's Haar cascades"
    plan = staticmethod(plan)

    def __init__(self, cv2: Any) -> None:
        self.cv2 = cv2
        self.find = self._cascade(self.FIND)
        self.check = self._cascade(self.CHECK)
        self.agree = self._cascade(self.AGREE)

    def prepare(self, image: Any) -> Any:
        """The image the searches look at: grey."""
        return self.cv2.cvtColor(image, self.cv2.COLOR_BGR2GRAY) if image.ndim == 3 else image

    def _cascade(self, name: str) -> Any:
        path = cascade_path(self.cv2, name)
        cascade = self.cv2.CascadeClassifier(path)
        if cascade.empty():
            raise MissingTool(
                f"following a face cannot read OpenCV's cascade {path}: {install_hint(self.cv2)}"
            )
        return cascade

    # -- sweep: the whole image, a job at a time ---------------------------------------------------

    def sweep(self, grey: Any, job: Job, known: Sequence[Box] = ()) -> List[Box]:
        """The faces the find cascade sees in `job`'s slice of the image (unchecked), the faces
        `known` among them (the networks' `sweep` leaves them out; a cascade costs the same).

        Every window that finds a face, at every size of the job, is kept, and the
        windows are grouped as OpenCV's own multi-scale search groups them: a face
        is where NEIGHBOURS windows or more, of nearby sizes and places, agree."""
        cv2 = self.cv2
        height, width = grey.shape
        rects: List[List[int]] = []
        # Large faces are searched on an image shrunk from one halved once, not from the whole.
        halved = cv2.pyrDown(grey) if not job.turn and min(job.sizes) >= 2 * WINDOW else None
        for size in job.sizes:
            r = WINDOW / size
            w, h = width * r, height * r
            cw, ch = turned_size(w, h, job.turn)
            # The windows whose tops lie in the job's rows of the (shrunk, turned) image, and a
            # few more, so that a face on the edge between two bands is whole in one of them.
            top = int(job.rows[0] * ch)
            bottom = min(ch, int(job.rows[1] * ch) + WINDOW + 4)
            if job.turn:  # shrink and turn at once, into the rows wanted only
                turned = cv2.getRotationMatrix2D((w / 2.0, h / 2.0), job.turn, 1.0)
                turned[:, 2] += ((cw - w) / 2.0, (ch - h) / 2.0)
                corners = [
                    (
                        turned[0][0] * x + turned[0][1] * y + turned[0][2],
                        turned[1][0] * x + turned[1][1] * y + turned[1][2],
                    )
                    for x, y in ((0, 0), (w, 0), (w, h), (0, h))
                ]
                left, right = _span(corners, top, bottom)
                left, right = max(0, int(left)), min(cw, int(math.ceil(right)))
                if right - left < WINDOW or bottom - top < WINDOW:
                    continue
                turned[:, 2] -= (left, top)
                forward = turned.copy()
                forward[:, :2] *= r
                band = cv2.warpAffine(
                    grey,
                    forward,
                    (right - left, bottom - top),
                    flags=cv2.INTER_LINEAR,
                    borderMode=cv2.BORDER_REPLICATE,
                )
                back = cv2.invertAffineTransform(turned)
            else:
                y0, y1 = int(top / r), min(height, int(math.ceil(bottom / r)))
                if (y1 - y0) * r < WINDOW or w < WINDOW:
                    continue
                source = grey[y0:y1] if halved is None else halved[y0 // 2 : (y1 + 1) // 2]
                shrink = w / source.shape[1]  # linear is enough down to half, and much faster
                band = cv2.resize(
                    source,
                    (int(round(w)), max(1, int(round((y1 - y0) * r)))),
                    interpolation=cv2.INTER_AREA if shrink < 0.5 else cv2.INTER_LINEAR,
                )
                back = [[1.0, 0.0, 0.0], [0.0, 1.0, y0 * r]]
            if min(band.shape) < WINDOW:
                continue
            found = self.find.detectMultiScale(
                band, 1.5, 0, minSize=(WINDOW, WINDOW), maxSize=(WINDOW, WINDOW)
            )
            for x, y, bw, _ in found:
                u, v = x + bw / 2.0, y + bw / 2.0
                bx = (back[0][0] * u + back[0][1] * v + back[0][2]) / r
                by = (back[1][0] * u + back[1][1] * v + back[1][2]) / r
                half = size / 2.0
                rects.append(
                    [int(round(bx - half)), int(round(by - half)), int(round(size)), int(round(size))]
                )
        if not rects:
            return []
        grouped, _ = cv2.groupRectangles(rects, self.NEIGHBOURS, 0.2)
        return [
            Box(x + w / 2.0, y + w / 2.0, float(w), job.turn)
            for x, y, w, _ in grouped
            if 0 <= x + w / 2.0 < width and 0 <= y + w / 2.0 < height
        ]

    # -- near: one face, around where it is expected -----------------------------------------------

    def near(self, grey: Any, x: float, y: float, size: float, turn: float) -> Optional[Box]:
        """The face about `size` wide nearest (x, y), looked for in a region turned by `turn` degrees."""
        region = self.region(grey, x, y, size, 1.2, self.TRACK_SIZE, turn)
        if region is None:
            return None
        low, high = int(0.7 * self.TRACK_SIZE), int(1.3 * self.TRACK_SIZE) + 1
        boxes, votes = self.find.detectMultiScale2(
            region.pixels, 1.15, 3, minSize=(low, low), maxSize=(high, high)
        )
        if len(boxes) == 0:
            return None
        found = [(bx + bw / 2.0, by + bw / 2.0, bw, vote) for (bx, by, bw, _), vote in zip(boxes, votes)]
        # Of the boxes about where the face is expected, the surest: a head and its hair may make
        # a larger box around the face's, which would let the size drift.
        close = [c for c in found if math.hypot(c[0] - region.cx, c[1] - region.cy) < 0.5 * self.TRACK_SIZE]
        u, v, w, _ = (
            max(close, key=lambda c: c[3])
            if close
            else min(found, key=lambda c: math.hypot(c[0] - region.cx, c[1] - region.cy))
        )
        return Box(*self.unturn(region, u, v), float(w / region.scale), turn)

    def region(
        self, grey: Any, x: float, y: float, size: float, reach: float, scaled: float, turn: float = 0.0
    ) -> Optional[Region]:
        """The square `reach` face widths either side of (x, y), scaled so the face (`size` wide)
        is `scaled` pixels wide and turned by `turn` degrees about it; None if mostly outside."""
        cv2 = self.cv2
        height, width = grey.shape
        half = reach * size
        x0, y0 = max(0, int(x - half)), max(0, int(y - half))
        x1, y1 = min(width, int(x + half) + 1), min(height, int(y + half) + 1)
        if x1 - x0 < 0.8 * size or y1 - y0 < 0.8 * size:
            return None
        scale = scaled / size
        pixels = grey[y0:y1, x0:x1]
        if abs(scale - 1.0) > 0.02:
            pixels = cv2.resize(
                pixels,
                None,
                fx=scale,
                fy=scale,
                interpolation=cv2.INTER_AREA if scale < 1.0 else cv2.INTER_LINEAR,
            )
        else:
            scale = 1.0
        cx, cy = (x - x0) * scale, (y - y0) * scale
        turned = cv2.getRotationMatrix2D((cx, cy), turn, 1.0)
        if turn:
            h, w = pixels.shape
            pixels = cv2.warpAffine(
                pixels, turned, (w, h), flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE
            )
        return Region(pixels, scale, x0, y0, cx, cy, cv2.invertAffineTransform(turned))

    @staticmethod
    def unturn(region: Region, u: float, v: float) -> Tuple[float, float]:
        """A point of the region, in the image."""
        back = region.back
        x = back[0][0] * u + back[0][1] * v + back[0][2]
        y = back[1][0] * u + back[1][1] * v + back[1][2]
        return float(region.x0 + x / region.scale), float(region.y0 + y / region.scale)

    # -- check: is it a face? ----------------------------------------------------------------------

    def verdict(self, grey: Any, box: Box, strict: bool = True) -> int:
        """How sure the other cascades are that `box` (turned upright) is a face (see the module):
        NOT_A_FACE, FOUND (both find it) or, looked at `strict`ly, SURE."""
        region = self.region(grey, box.x, box.y, box.size, 0.8, self.TRACK_SIZE, box.turn)
        if region is None or self.votes(self.check, region.pixels) == 0:
            return NOT_A_FACE
        agreed = self.votes(self.agree, region.pixels)
        if agreed == 0 or not strict:
            return FOUND if agreed else NOT_A_FACE
        # A face stays one mirrored, turned a little or seen a little nearer or further; a texture
        # that fools the cascades seldom does.
        for turn, scaled in ((0.0, 0.0), (-10.0, 1.0), (10.0, 1.0), (0.0, 0.85), (0.0, 1.25)):
            if agreed >= self.AGREEMENT:
                break
            if not scaled:
                agreed += self.votes(self.agree, self.cv2.flip(region.pixels, 1))
                continue
            size = self.TRACK_SIZE * scaled
            shifted = self.region(grey, box.x, box.y, box.size, 0.8, size, box.turn + turn)
            if shifted is not None:
                agreed += self.votes(self.agree, shifted.pixels, size)
        return SURE if agreed >= self.AGREEMENT else FOUND

    def votes(self, cascade: Any, pixels: Any, size: float = TRACK_SIZE) -> int:
        """How many of `cascade`'s windows agree on the face, `size` wide, in the region (0: none)."""
        low, high = int(0.7 * size), int(1.45 * size) + 1
        _, votes = cascade.detectMultiScale2(pixels, 1.1, 1, minSize=(low, low), maxSize=(high, high))
        return int(max(votes)) if len(votes) else 0


def sizes_of(jobs: Sequence[Job]) -> List[float]:
    """Every face size the jobs search, once each."""
    return sorted({size for job in jobs for size in job.sizes})
