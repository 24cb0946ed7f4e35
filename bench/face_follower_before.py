"""The face follower before far faces (baxterface_cli/robot/face_finder.py at cac3c8e, verbatim
but for its imports): the baseline bench/follow_camera.py measures the new one against.

Where the eyes should look to follow a face the head camera sees.

`FaceFollower.update(image)` takes a camera image (HxWx3 uint8 BGR, or HxW
grey) and returns the eye target `(x, y)` that looks at the face in it, or
None when there is no face to follow. It needs OpenCV (`pip install
'baxterface[camera]'`) and the Haar cascades its 4.x wheels ship; importing
this module does not.

The geometry. The camera is a pinhole whose axis is where the eyes look when
centred, with focal length f = (W/2) / tan(hfov/2) pixels. A face centred at
pixel (u, v) is at azimuth atan((W/2 - u) / f), positive to the image's left,
which is the robot's left and, as for `ArmFollower`, positive eye x: eye x is
the azimuth in degrees. Its elevation atan((H/2 - v) / f) is positive up; eye
y is -76.394 times it in radians (a quarter turn up is 120 pixels up, which is
negative). The point is then clamped to the eye ellipse. A face at the image's
centre gives (0, 0).

The pipeline, and why each step is there:

1. Search the whole image, shrunk, with the frontalface_alt2 cascade (its
   20x20 window finds the smallest faces) at a coarse scale step. A full
   search costs several tracking steps, so it runs every 0.1 s while no face
   is followed, every 0.3 s while one is; then only faces clearly larger than
   it matter, so the image is shrunk further and the search is cheaper still.
2. Check what it finds: the frontalface_default cascade (trained apart, so
   its mistakes are other ones) must find a face there too, and either the
   frontalface_alt cascade must agree strongly as well or the eye cascade
   must find an eye on each side of the upper half. A cat's face fools the
   face cascades now and then, but not all three strongly, and has no eyes
   where a person's are.
3. Confirm: a checked face is followed only once it has been found in two of
   the last three searches at about the same place and size, so one mistake
   never moves the eyes.
4. Track on every frame: the cascade only in a region around where the face
   is expected (its filtered position and speed), at only the scales near its
   size, with the region shrunk so the face is about 48 pixels wide, which
   costs a few milliseconds whatever the face's size. An upright cascade
   misses a tilted head, so when the upright search fails the region is
   turned by +-25 degrees (first by the turn that worked last) and the face's
   centre turned back. Every full search also checks the tracked face (turned
   upright), so the tracker cannot drift onto something else for long.
5. Smooth the centre with a small alpha-beta filter (position and speed),
   light enough not to lag behind a moving face.
6. Choose between faces with hysteresis: another face takes over only when
   its area is more than 1.3 times the followed one's in three searches
   running (which then come every 0.1 s), so two faces of about the same size
   never swap the eyes between them, and the nearest (largest) face wins.
7. Let go: a face not found for `hold` seconds (0.5) is dropped, and the eyes
   are free (None) well within a second of a face leaving.

Time is the caller's (`at`, seconds) or, without it, frames `rate` a second
apart; there is no wall clock inside, so a run is repeatable.
"""

from __future__ import annotations

import math
from collections import deque
from typing import Any, Deque, List, NamedTuple, Optional, Tuple

from baxterface_cli.core.geometry import clamp_to_ellipse
from baxterface_cli.extras import MissingTool, need
from baxterface_cli.robot.following import DEGREES_PER_RADIAN, PIXELS_PER_ELEVATION

# Baxter's cameras have a focal length of about 410 pixels on their 1280x800 sensor (the
# head camera's camera_info: K = [410, 0, 640, 0, 410, 400, ...]; calibrated hand cameras give
# 403-406), and at 640x400 they crop the sensor's centre at the same focal length (roi offset
# 320, 200, binning 1): 2 * atan(320 / 410) = 75.94 degrees across (76.5 at f = 406).
BAXTER_HEAD_CAMERA_HFOV = 76.0

Point = Tuple[float, float]


def eye_target(
    u: float, v: float, width: int, height: int, hfov_deg: float = BAXTER_HEAD_CAMERA_HFOV
) -> Point:
    """The eye target that looks at pixel (u, v) of a `width` x `height` image (see the module's doc)."""
    f = (width / 2.0) / math.tan(math.radians(hfov_deg) / 2.0)
    azimuth = math.atan((width / 2.0 - u) / f)
    elevation = math.atan((height / 2.0 - v) / f)
    return clamp_to_ellipse(azimuth * DEGREES_PER_RADIAN, -PIXELS_PER_ELEVATION * elevation)


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


def _same(a: Box, b: Box, reach: float = 0.5) -> bool:
    """Whether two boxes are plausibly one face, moved less than `reach` of its width."""
    return math.hypot(a.x - b.x, a.y - b.y) < reach * max(a.size, b.size) and 0.67 < a.size / b.size < 1.5


class FaceFollower:
    """Camera images in, the eye target of the nearest face out (None when there is none).

    `hfov_deg` is the camera's horizontal field of view (Baxter's head camera's
    by default), `rate` the frame rate taken when `update` is not told the
    time, `hold` how long (seconds) a face no longer found is still looked at.
    """

    FIND = "haarcascade_frontalface_alt2.xml"
    CHECK = "haarcascade_frontalface_default.xml"
    AGREE = "haarcascade_frontalface_alt.xml"
    EYE = "haarcascade_eye.xml"
    STRONG = 12  # windows of both other face cascades that make a face sure without its eyes
    SMALLEST = 40.0  # pixels: the narrowest face looked for (the 20-pixel window, at half size)
    STEP = 1.2  # the full search's scale step: coarse, as a face missed is found 0.1 s later
    TRACK_SIZE = 48.0  # pixels: the face's width in the region searched while tracking
    TURNS = (0.0, 25.0, -25.0)  # degrees the tracking region is turned to show a tilted face upright
    SEARCH_EVERY = 0.3  # seconds between full searches while a face is followed and found ...
    SEARCH_OFTEN = 0.1  # ... and while none is, it is not being found or another may take over
    CONFIRM_REACH = 1.5  # face widths a face may move between the searches that confirm it
    SWITCH_AREA = 1.3  # another face must be this much larger (area) ...
    SWITCH_SEARCHES = 3  # ... in this many full searches running, to take over
    UNCHECKED = 1.5  # seconds a tracked face may go without passing the check, before it is dropped
    ALPHA, BETA = 0.6, 0.1  # the alpha-beta filter on the face's centre

    def __init__(
        self, hfov_deg: float = BAXTER_HEAD_CAMERA_HFOV, rate: float = 30.0, hold: float = 0.5
    ) -> None:
        if not 0.0 < hfov_deg < 180.0:
            raise ValueError(f"the field of view must be between 0 and 180 degrees, not {hfov_deg}")
        if rate <= 0.0:
            raise ValueError(f"the frame rate must be positive, not {rate}")
        self.cv2 = need("cv2", "camera", "following a face")
        self.hfov_deg = hfov_deg
        self.rate = rate
        self.hold = hold
        self._frames = 0  # images seen: the clock when `update` is not told the time
        self._now = -math.inf  # the time of the latest image
        self._find = self._cascade(self.FIND)
        self._check = self._cascade(self.CHECK)
        self._agree = self._cascade(self.AGREE)
        self._eye = self._cascade(self.EYE)
        self.reset()

    def _cascade(self, name: str) -> Any:
        folder = getattr(getattr(self.cv2, "data", None), "haarcascades", "")
        cascade = self.cv2.CascadeClassifier(folder + name)
        if cascade.empty():
            raise MissingTool(
                f"following a face needs OpenCV's {name} (opencv-python-headless 4.x ships it): "
                "pip install 'baxterface[camera]'"
            )
        return cascade

    def reset(self) -> None:
        """Forget every face seen so far."""
        self._shape: Optional[Tuple[int, ...]] = None
        self._face: Optional[Box] = None  # the face followed, filtered
        self._speed = (0.0, 0.0)  # its centre's, pixels a second
        self._t = 0.0  # when it was last found
        self._checked_at = 0.0  # when it last passed the check
        self._recent: Deque[List[Box]] = deque(maxlen=3)  # checked faces of the last full searches
        self._next_search = -math.inf
        self._rival = 0  # full searches running that found a clearly larger face

    @property
    def face(self) -> Optional[Box]:
        """The face followed (centre and width in image pixels), or None."""
        return self._face

    def update(self, image: Any, at: Optional[float] = None) -> Optional[Point]:
        """Look at one camera image, taken at `at` seconds; return the eye target, or None."""
        grey = self._grey(image)
        t = self._frames / self.rate if at is None else float(at)
        if not math.isfinite(t):
            raise ValueError(f"the time of a camera image must be a finite number, not {at}")
        if self._shape != grey.shape or t < self._now:  # another camera or size, or a clock set back
            self.reset()
            self._shape = grey.shape
        self._frames += 1
        self._now = t
        tracked = self._track(grey, t) if self._face is not None else None
        if t >= self._next_search:
            busy = self._search(grey, t, tracked)
            self._next_search = t + (self.SEARCH_OFTEN if busy else self.SEARCH_EVERY)
        if self._face is not None and (t - self._t > self.hold or t - self._checked_at > self.UNCHECKED):
            self._face = None
        if self._face is None:
            return None
        return eye_target(self._face.x, self._face.y, grey.shape[1], grey.shape[0], self.hfov_deg)

    def _grey(self, image: Any) -> Any:
        import numpy as np

        if not isinstance(image, np.ndarray) or image.dtype != np.uint8:
            what = f"{image.dtype} array" if isinstance(image, np.ndarray) else type(image).__name__
            raise ValueError(f"a camera image must be a uint8 numpy array, not a {what}")
        if image.ndim == 3 and image.shape[2] == 3:
            image = self.cv2.cvtColor(image, self.cv2.COLOR_BGR2GRAY)
        elif image.ndim != 2:
            raise ValueError(f"a camera image must be HxWx3 (BGR) or HxW (grey), not {image.shape}")
        if image.size == 0:
            raise ValueError(f"a camera image must not be empty, not {image.shape}")
        return image

    # -- tracking: the followed face, near where it is expected -----------------------------------

    def _track(self, grey: Any, t: float) -> Optional[Box]:
        face = self._face
        assert face is not None
        ahead = max(0.0, min(t - self._t, 0.2))
        x, y = face.x + self._speed[0] * ahead, face.y + self._speed[1] * ahead
        for turn in (face.turn, *(turn for turn in self.TURNS if turn != face.turn)):
            box = self._near(grey, x, y, face.size, turn)
            if box is not None:
                self._follow(box, t)
                return box
        return None

    def _near(self, grey: Any, x: float, y: float, size: float, turn: float) -> Optional[Box]:
        """The face about `size` wide near (x, y), looked for in a region turned by `turn` degrees."""
        region = self._region(grey, x, y, size, 1.2, self.TRACK_SIZE, turn)
        if region is None:
            return None
        low, high = int(0.75 * self.TRACK_SIZE), int(1.35 * self.TRACK_SIZE) + 1
        boxes = self._find.detectMultiScale(region.pixels, 1.1, 3, minSize=(low, low), maxSize=(high, high))
        if len(boxes) == 0:
            return None
        centres = [(bx + bw / 2.0, by + bw / 2.0, bw) for bx, by, bw, _ in boxes]
        u, v, w = min(centres, key=lambda c: math.hypot(c[0] - region.cx, c[1] - region.cy))
        return Box(*self._unturn(region, u, v), float(w / region.scale), turn)

    def _region(
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

    def _unturn(self, region: Region, u: float, v: float) -> Tuple[float, float]:
        """A point of the region, in the image."""
        back = region.back
        x = back[0][0] * u + back[0][1] * v + back[0][2]
        y = back[1][0] * u + back[1][1] * v + back[1][2]
        return float(region.x0 + x / region.scale), float(region.y0 + y / region.scale)

    def _follow(self, box: Box, t: float) -> None:
        """Take `box` as the followed face's new position, through the alpha-beta filter."""
        face, dt = self._face, t - self._t
        if face is None or dt <= 0.0 or not _same(face, box):
            self._face, self._speed = box, (0.0, 0.0)
        else:
            px, py = face.x + self._speed[0] * dt, face.y + self._speed[1] * dt
            rx, ry = box.x - px, box.y - py
            size = face.size + 0.5 * (box.size - face.size)
            self._face = Box(px + self.ALPHA * rx, py + self.ALPHA * ry, size, box.turn)
            self._speed = (self._speed[0] + self.BETA * rx / dt, self._speed[1] + self.BETA * ry / dt)
        self._t = t

    # -- searching: the whole image, for a face to follow or a nearer one -------------------------

    def _search(self, grey: Any, t: float, tracked: Optional[Box]) -> bool:
        """One full search; returns whether the next should come soon (see SEARCH_OFTEN)."""
        face = self._face
        if face is not None and tracked is not None and self._checked(grey, tracked):
            self._checked_at = t
        # While a face is followed and found, only clearly larger ones matter: a coarser search.
        smallest = self.SMALLEST if tracked is None else max(self.SMALLEST, 1.1 * tracked.size)
        faces = self._everywhere(grey, smallest)
        self._recent.append(faces)
        confirmed = [box for box in faces if self._confirmed(box)]
        if face is None:
            if confirmed:
                self._take(max(confirmed, key=lambda box: box.size), t)
            return True
        if tracked is None:  # tracking missed it; the full search may have found it
            again = [box for box in faces if _same(box, face, 1.0)]
            if again:
                self._follow(min(again, key=lambda box: math.hypot(box.x - face.x, box.y - face.y)), t)
                self._checked_at = t
        larger = [
            box for box in faces if not _same(box, face) and box.size**2 > self.SWITCH_AREA * face.size**2
        ]
        sure = [box for box in larger if box in confirmed]
        self._rival = self._rival + 1 if sure else 0
        if self._rival >= self.SWITCH_SEARCHES:
            self._take(max(sure, key=lambda box: box.size), t)
        return tracked is None or bool(larger)

    def _take(self, box: Box, t: float) -> None:
        """Follow `box` from now on, forgetting the face followed before."""
        self._face, self._rival = None, 0
        self._follow(box, t)
        self._checked_at = t

    def _everywhere(self, grey: Any, smallest: float) -> List[Box]:
        """Checked faces at least about `smallest` pixels wide anywhere in the image."""
        cv2 = self.cv2
        scale = min(1.0, 20.0 / smallest)
        if min(grey.shape) * scale < 20:
            return []
        small = (
            cv2.resize(grey, None, fx=scale, fy=scale, interpolation=cv2.INTER_AREA) if scale < 1.0 else grey
        )
        found = []
        for bx, by, bw, _ in self._find.detectMultiScale(small, self.STEP, 3, minSize=(20, 20)):
            box = Box(float((bx + bw / 2.0) / scale), float((by + bw / 2.0) / scale), float(bw / scale))
            if self._checked(grey, box):
                found.append(box)
        return found

    def _confirmed(self, box: Box) -> bool:
        """Whether `box` was found by one of the two searches before this one, too."""
        earlier = list(self._recent)[:-1]
        return any(_same(box, other, self.CONFIRM_REACH) for boxes in earlier for other in boxes)

    # -- checking: is it a face? -------------------------------------------------------------------

    def _checked(self, grey: Any, box: Box) -> bool:
        """Whether the other cascades agree that `box` (turned upright) is a face (step 2)."""
        region = self._region(grey, box.x, box.y, box.size, 0.8, self.TRACK_SIZE, box.turn)
        if region is None:
            return False
        votes = self._votes(self._check, region.pixels)
        if votes == 0:
            return False
        if votes >= self.STRONG and self._votes(self._agree, region.pixels) >= self.STRONG:
            return True
        return self._two_eyes(grey, box)

    def _votes(self, cascade: Any, region: Any) -> int:
        """How many of `cascade`'s windows agree on the face in the region (0: it finds none)."""
        low, high = int(0.7 * self.TRACK_SIZE), int(1.45 * self.TRACK_SIZE) + 1
        _, votes = cascade.detectMultiScale2(region, 1.1, 1, minSize=(low, low), maxSize=(high, high))
        return int(max(votes)) if len(votes) else 0

    def _two_eyes(self, grey: Any, box: Box) -> bool:
        """Whether the eye cascade finds an eye on each side of the face's upper half."""
        region = self._region(grey, box.x, box.y, box.size, 0.5, 100.0, box.turn)
        if region is None:
            return False
        upper = region.pixels[: int(region.cy)]
        eyes = self._eye.detectMultiScale(upper, 1.1, 1, minSize=(20, 20), maxSize=(40, 40))
        centres = [x + w / 2.0 for x, _, w, _ in eyes]
        return any(c < region.cx - 8 for c in centres) and any(c > region.cx + 8 for c in centres)
