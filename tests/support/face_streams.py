"""Synthetic camera streams for following a face, made from photos scikit-image ships.

Each stream is a few seconds of 640x400 BGR frames at 30 a second: real faces
(scikit-image's astronaut portrait, its mirror image, small LFW photos) cut out
with a soft elliptical mask and pasted with cv2.warpAffine at a known centre,
width and tilt over real backgrounds (rocket, coffee, brick, grass), with
whole-frame brightness changes and a little sensor noise, plus distractors
(the cat photo, text posters). Every frame records the truth: the centre of
the face to follow in the image and the eye target that looks at it, by the
pinhole geometry written out again here (not imported from the library), so
the tests check the library against it.

Everything is seeded and deterministic. Frames are generated lazily, so a
stream costs no memory; one of 150 frames takes about half a second to a second.
"""

from __future__ import annotations

import functools
import math
import time
from typing import Callable, Dict, Iterator, List, NamedTuple, Optional, Sequence, Tuple, Union

import cv2
import numpy as np
from skimage import data

from baxterface_cli.core.geometry import clamp_to_ellipse

WIDTH, HEIGHT = 640, 400
FPS = 30.0
HFOV = 76.0  # Baxter's head camera at 640x400
PIXELS_PER_ELEVATION = 76.394
DEGREES_PER_RADIAN = 57.294
FAR_FACES = (0, 15, 21, 22, 47, 82)  # faces of scikit-image's LFW subset
# Where OpenCV's cascades put each of those faces on its head (_head), on average over pictures
# 80 to 120 pixels wide on two backgrounds: its width, and its centre's offset right and down, in
# widths of the face as pasted. The streams' truth is the cascades' face, as for the astronaut.
FAR_FACE_BOXES = {
    0: (1.056, -0.008, -0.022),
    15: (1.100, -0.022, 0.008),
    21: (0.922, -0.131, -0.027),
    22: (1.143, -0.066, 0.021),
    47: (0.991, -0.133, -0.002),
    82: (1.038, -0.074, -0.046),
}
NOT_FACES = (106, 122, 138, 147, 153, 181)  # pictures of it that are not faces


def eye_truth(u: float, v: float, width: int = WIDTH, height: int = HEIGHT, hfov: float = HFOV):
    """The eye target that looks at image point (u, v): pinhole geometry, as the issue states it."""
    f = (width / 2.0) / math.tan(math.radians(hfov) / 2.0)
    azimuth = math.atan((width / 2.0 - u) / f)
    elevation = math.atan((height / 2.0 - v) / f)
    return clamp_to_ellipse(azimuth * DEGREES_PER_RADIAN, -PIXELS_PER_ELEVATION * elevation)


class Sprite(NamedTuple):
    """A picture cut out with a soft mask; (cx, cy) and `size` are its face's centre and width."""

    bgr: np.ndarray  # float32, premultiplied by alpha
    alpha: np.ndarray  # float32 0..1
    cx: float
    cy: float
    size: float


class Placed(NamedTuple):
    sprite: str
    u: float  # where the sprite's centre lands in the frame
    v: float
    width: float  # the face's (or picture's) width in frame pixels
    angle: float = 0.0  # degrees, counter-clockwise in the image


class Frame(NamedTuple):
    image: np.ndarray  # HxWx3 uint8 BGR
    t: float
    centre: Optional[Tuple[float, float]]  # the face to follow, in image pixels, when fully in view
    target: Optional[Tuple[float, float]]  # the eye target that looks at it
    width: float  # its width in pixels (0 when none)


def _soft_ellipse(h: int, w: int, cx: float, cy: float, ax: float, ay: float, soft: float) -> np.ndarray:
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
    r = np.sqrt(((xx - cx) / ax) ** 2 + ((yy - cy) / ay) ** 2)
    # 1 inside, falling to 0 over `soft` of the radius at the edge.
    return np.clip((1.0 - r) / soft + 0.5, 0.0, 1.0).astype(np.float32)


def _sprite(bgr: np.ndarray, alpha: np.ndarray, cx: float, cy: float, size: float) -> Sprite:
    bgr = bgr.astype(np.float32) * alpha[:, :, None]
    return Sprite(bgr, alpha, cx, cy, size)


@functools.lru_cache(maxsize=None)
def sprites() -> Dict[str, Sprite]:
    """The pictures the streams are made of, each cut out once."""
    out = {}
    # The astronaut: OpenCV's cascades find her face at (177, 66) 95x95 in the 512x512 photo;
    # the head (hair to chin) is cut out around it.
    astro = data.astronaut()[:, :, ::-1]
    x0, y0, x1, y1 = 124, 0, 326, 226
    head = np.ascontiguousarray(astro[y0:y1, x0:x1])
    cx, cy = 224.5 - x0, 113.5 - y0
    alpha = _soft_ellipse(head.shape[0], head.shape[1], cx, cy - 8, 72, 100, 0.12)
    out["astronaut"] = _sprite(head, alpha, cx, cy, 95.0)
    mirror = np.ascontiguousarray(head[:, ::-1])
    out["mirror"] = _sprite(mirror, alpha[:, ::-1].copy(), head.shape[1] - 1 - cx, cy, 95.0)
    # Small real faces (LFW, 25x25 grey, tinted): the cascades' box is about the whole photo. lfw7,
    # and six of its pictures that are not faces (seed 26) as distractors; six faces drawn at
    # random (seed 25) for the far streams, each given a head (see _head).
    for index in (7, *NOT_FACES):
        tinted, alpha = _lfw(index)
        out[f"lfw{index}"] = _sprite(tinted, alpha, 50.0, 46.0, 92.0)
    for k, index in enumerate(FAR_FACES):
        head = _head(*_lfw(index), HAIR[k % len(HAIR)])
        width, right, down = FAR_FACE_BOXES[index]
        out[f"lfw{index}"] = head._replace(
            cx=head.cx + right * head.size, cy=head.cy + down * head.size, size=head.size * width
        )
    # Distractors, as posters with soft corners: the cat and two pages of text.
    cat = data.chelsea()[:, :, ::-1]
    out["cat"] = _poster(cat)
    for name in ("text", "page"):
        out[name] = _poster(cv2.cvtColor(getattr(data, name)(), cv2.COLOR_GRAY2BGR))
    return out


def _lfw(index: int) -> Tuple[np.ndarray, np.ndarray]:
    """LFW's picture `index`, 100 pixels square, tinted, and a soft oval mask that leaves its face."""
    grey = cv2.resize(
        (data.lfw_subset()[index] * 255).astype(np.uint8), (100, 100), interpolation=cv2.INTER_CUBIC
    )
    tinted = np.clip(grey[:, :, None] * np.array([0.85, 0.95, 1.1]), 0, 255).astype(np.float32)
    return tinted, _soft_ellipse(100, 100, 50, 50, 52, 60, 0.15)


HAIR = ((40, 50, 62), (30, 32, 36), (70, 95, 120), (55, 60, 70))  # BGR: browns, black, fair, grey


def _head(face: np.ndarray, mask: np.ndarray, hair: Tuple[int, int, int]) -> Sprite:
    """An LFW face (cut close: brows to chin) on a head: hair around and above it, a neck below, as a
    person has, so its edges meet a head as a real face's do, not the clutter behind it."""
    h, w = 190, 150
    x0, y0 = 25, 45  # where the 100x100 face goes
    colour = np.zeros((h, w, 3), np.float32)
    alpha = np.zeros((h, w), np.float32)
    skin = face[30:70, 30:70].reshape(-1, 3).mean(axis=0)
    for paint, cover in (
        (np.array(hair, np.float32), _soft_ellipse(h, w, 75, 76, 64, 72, 0.12)),
        (skin * 0.85, _soft_ellipse(h, w, 75, 172, 26, 34, 0.25)),  # the neck
    ):
        colour = colour * (1.0 - cover[:, :, None]) + paint * cover[:, :, None]
        alpha = alpha + cover * (1.0 - alpha)
    over = np.zeros((h, w), np.float32)
    over[y0 : y0 + 100, x0 : x0 + 100] = mask
    placed = np.zeros((h, w, 3), np.float32)
    placed[y0 : y0 + 100, x0 : x0 + 100] = face
    colour = colour * (1.0 - over[:, :, None]) + placed * over[:, :, None]
    alpha = alpha + over * (1.0 - alpha)
    return Sprite(colour * alpha[:, :, None], alpha, x0 + 50.0, y0 + 46.0, 92.0)


def _poster(bgr: np.ndarray) -> Sprite:
    h, w = bgr.shape[:2]
    alpha = np.ones((h, w), np.float32)
    alpha[[0, -1], :] = 0.0
    alpha[:, [0, -1]] = 0.0
    alpha = cv2.GaussianBlur(alpha, (0, 0), 1.5)
    return _sprite(bgr, alpha, (w - 1) / 2.0, (h - 1) / 2.0, float(w))


@functools.lru_cache(maxsize=None)
def background(name: str) -> np.ndarray:
    """A real scene from scikit-image, fitted to 640x400 BGR."""
    picture = data.stereo_motorcycle()[0] if name == "motorcycle" else getattr(data, name)()
    picture = cv2.cvtColor(picture, cv2.COLOR_GRAY2BGR) if picture.ndim == 2 else picture[:, :, ::-1]
    h, w = picture.shape[:2]
    scale = max(WIDTH / w, HEIGHT / h)
    picture = cv2.resize(picture, (math.ceil(w * scale), math.ceil(h * scale)), interpolation=cv2.INTER_AREA)
    y0 = (picture.shape[0] - HEIGHT) // 2
    x0 = (picture.shape[1] - WIDTH) // 2
    return np.ascontiguousarray(picture[y0 : y0 + HEIGHT, x0 : x0 + WIDTH])


@functools.lru_cache(maxsize=None)
def _noise(seed: int) -> List[np.ndarray]:
    rng = np.random.default_rng(seed)
    return [rng.normal(0.0, 3.0, (HEIGHT, WIDTH, 3)).astype(np.float32) for _ in range(4)]


def paste(frame: np.ndarray, sprite: Sprite, u: float, v: float, width: float, angle: float) -> None:
    """Paste `sprite` into `frame` (float32) with its centre at (u, v), `width` wide, tilted `angle`."""
    scale = width / sprite.size
    if scale < 0.5:  # shrunk as a lens would, averaging, not sampled: a far face keeps its features
        bgr = cv2.resize(sprite.bgr, None, fx=scale, fy=scale, interpolation=cv2.INTER_AREA)
        alpha = cv2.resize(sprite.alpha, None, fx=scale, fy=scale, interpolation=cv2.INTER_AREA)
        sx, sy = bgr.shape[1] / sprite.bgr.shape[1], bgr.shape[0] / sprite.bgr.shape[0]
        sprite = Sprite(
            bgr, alpha, (sprite.cx + 0.5) * sx - 0.5, (sprite.cy + 0.5) * sy - 0.5, sprite.size * sx
        )
        scale = width / sprite.size
    m = cv2.getRotationMatrix2D((sprite.cx, sprite.cy), angle, scale)
    m[:, 2] += (u - sprite.cx, v - sprite.cy)
    h, w = sprite.alpha.shape
    corners = np.array([[0, 0, 1], [w, 0, 1], [0, h, 1], [w, h, 1]], np.float64) @ m.T
    x0, y0 = np.floor(corners.min(axis=0)).astype(int)
    x1, y1 = np.ceil(corners.max(axis=0)).astype(int)
    x0, y0, x1, y1 = max(x0, 0), max(y0, 0), min(x1, WIDTH), min(y1, HEIGHT)
    if x1 <= x0 or y1 <= y0:
        return
    m[:, 2] -= (x0, y0)
    size = (x1 - x0, y1 - y0)
    colour = cv2.warpAffine(sprite.bgr, m, size, flags=cv2.INTER_LINEAR)
    alpha = cv2.warpAffine(sprite.alpha, m, size, flags=cv2.INTER_LINEAR)
    roi = frame[y0:y1, x0:x1]
    roi *= 1.0 - alpha[:, :, None]
    roi += colour


class Stream:
    """A scenario: what is where at time t; frames and truth made on demand."""

    def __init__(
        self,
        name: str,
        seconds: float,
        scene: Callable[[float], Tuple[float, List[Placed]]],
        backdrop: str,
        seed: int = 0,
        follow: Union[None, int, Callable[[float], int]] = 0,
        left_at: Optional[float] = None,
        switch: Optional[Tuple[float, float]] = None,
    ) -> None:
        self.name = name
        self.seconds = seconds
        self.scene = scene  # t -> (brightness gain, placed sprites, back to front)
        self.backdrop = backdrop
        self.seed = seed
        self.follow = follow  # which placed sprite is the face to follow (None: none; or a function of t)
        self.left_at = left_at  # when the face to follow is no longer fully in view
        # When `follow` changes its face: the eyes should move within this window, in which
        # neither face is the truth.
        self.switch = switch
        self.fps = FPS

    def __len__(self) -> int:
        return int(round(self.seconds * self.fps))

    def truth(self, t: float) -> Tuple[Optional[Tuple[float, float]], float]:
        """The followed face's centre in the image, when it is fully in view, and its width."""
        if self.follow is None or (self.switch and self.switch[0] <= t < self.switch[1]):
            return None, 0.0
        face = self.scene(t)[1][self.follow(t) if callable(self.follow) else self.follow]
        half = face.width / 2.0
        inside = half <= face.u <= WIDTH - half and half <= face.v <= HEIGHT - half
        return ((face.u, face.v) if inside else None), face.width

    def frames(self) -> Iterator[Frame]:
        art = sprites()
        back = background(self.backdrop).astype(np.float32)
        noise = _noise(self.seed)
        for k in range(len(self)):
            t = k / self.fps
            gain, placed = self.scene(t)
            frame = back.copy()
            for p in placed:
                paste(frame, art[p.sprite], p.u, p.v, p.width, p.angle)
            frame *= gain
            frame += noise[k % len(noise)]
            image = np.clip(frame, 0, 255).astype(np.uint8)
            centre, width = self.truth(t)
            target = eye_truth(*centre) if centre is not None else None
            yield Frame(image, t, centre, target, width if centre is not None else 0.0)


# Paths: smooth, seeded wanderings within the frame.


def _wander(seed: int, speed: float = 1.0) -> Callable[[float], Tuple[float, float]]:
    rng = np.random.default_rng(seed)
    fx = rng.uniform(0.25, 0.40, 2) * speed
    fy = rng.uniform(0.20, 0.35, 2) * speed
    px, py = rng.uniform(0, 2 * math.pi, 2), rng.uniform(0, 2 * math.pi, 2)

    def at(t: float) -> Tuple[float, float]:
        x = 0.7 * math.sin(2 * math.pi * fx[0] * t + px[0]) + 0.3 * math.sin(2 * math.pi * fx[1] * t + px[1])
        y = 0.7 * math.sin(2 * math.pi * fy[0] * t + py[0]) + 0.3 * math.sin(2 * math.pi * fy[1] * t + py[1])
        return x, y

    return at


def moving() -> Stream:
    """One face wandering over most of the frame, up and down too, at up to ~250 px/s."""
    path = _wander(1)

    def scene(t):
        x, y = path(t)
        return 1.0, [Placed("astronaut", 320 + 230 * x, 200 + 120 * y, 95)]

    return Stream("moving", 5.0, scene, "rocket", seed=1)


def tilting() -> Stream:
    """A face moving a little and tilting up to 25 degrees each way, about once in 2 s."""
    path = _wander(2, 0.6)

    def scene(t):
        x, y = path(t)
        return 1.0, [
            Placed("astronaut", 320 + 150 * x, 200 + 80 * y, 90, 25 * math.sin(2 * math.pi * t / 2.2))
        ]

    return Stream("tilting", 5.0, scene, "coffee", seed=2)


def shrinking() -> Stream:
    """A face walking away: 110 px wide down to 40 px in 3 s, then staying there, moving slowly."""
    path = _wander(3, 0.5)

    def scene(t):
        x, y = path(t)
        width = 110 - 70 * min(1.0, t / 3.0)
        return 1.0, [Placed("astronaut", 320 + 200 * x, 200 + 110 * y, width, 8 * math.sin(1.3 * t))]

    return Stream("shrinking", 5.0, scene, "brick", seed=3)


def brightness() -> Stream:
    """The whole frame getting darker and brighter (x0.5 to x1.4) while a face moves."""
    path = _wander(4, 0.6)

    def scene(t):
        x, y = path(t)
        gain = 0.95 + 0.45 * math.sin(2 * math.pi * t / 3.0 + 1.0)
        return gain, [Placed("astronaut", 320 + 200 * x, 200 + 100 * y, 85)]

    return Stream("brightness", 5.0, scene, "grass", seed=4)


def two_faces() -> Stream:
    """Two faces side by side, of similar size (0.85x to 1.1x): the first must be kept."""

    def scene(t):
        sway = 30 * math.sin(2 * math.pi * t / 3.0)
        ratio = 0.975 - 0.125 * math.cos(2 * math.pi * t / 2.5)  # 0.85 at the start, up to 1.1
        return 1.0, [
            Placed("astronaut", 200 + sway, 190 + 15 * math.sin(1.7 * t), 90),
            Placed("mirror", 440 + sway, 205 - 15 * math.sin(1.3 * t), 90 * ratio),
        ]

    return Stream("two faces", 5.0, scene, "rocket", seed=5)


def leaving() -> Stream:
    """A face that moves about, then walks out of the frame to the right at 2.5 s."""
    path = _wander(6, 0.6)
    start = 2.5

    def scene(t):
        x, y = path(min(t, start))
        u = 320 + 150 * x + max(0.0, t - start) * 450
        return 1.0, [Placed("astronaut", u, 200 + 80 * y, 90)]

    # Fully in view until its right edge (u + 45) reaches the frame's edge.
    x, _ = path(start)
    left_at = start + (WIDTH - 45 - (320 + 150 * x)) / 450
    return Stream("leaving", 4.5, scene, "coffee", seed=6, left_at=left_at)


def cat() -> Stream:
    """The cat photo as a poster, moving, from 50 to 350 px wide, over a coffee cup: never a face."""
    path = _wander(409, 0.7)

    def scene(t):
        x, y = path(t)
        width = 200 + 150 * math.sin(0.7 * t + 9)
        return 1.0 + 0.3 * math.sin(t), [
            Placed("cat", 320 + 150 * x, 200 + 80 * y, width, 6 * math.sin(t + 9))
        ]

    return Stream("cat", 5.0, scene, "coffee", seed=7, follow=None)


def text_poster() -> Stream:
    """Two pages of text, one still and one moving, over the rocket: never a face."""
    path = _wander(400, 0.7)

    def scene(t):
        x, y = path(t)
        return 1.0 + 0.3 * math.sin(t), [
            Placed("text", 320 - 150 * x, 200 - 60 * y, 250 + 80 * math.cos(t)),
            Placed("page", 150, 300, 200 + 60 * math.sin(0.5 * t)),
        ]

    return Stream("text poster", 5.0, scene, "rocket", seed=8, follow=None)


def posters(seed: int) -> Stream:
    """The cat and two pages of text together, moving and changing size: never a face. With a
    full search at a finer scale step (1.1) than FaceFollower's, seed 9 (over the coffee) has a
    small cat that fools two face cascades at once, which the eye check turns down, and seed 0
    (over the rocket) a page's corner that fools the first cascade again and again, which the
    second turns down."""
    path = _wander(400 + seed, 0.7)

    def scene(t):
        x, y = path(t)
        cat_width = 200 + 150 * math.sin(0.7 * t + seed)
        return 1.0 + 0.3 * math.sin(t), [
            Placed("cat", 320 + 150 * x, 200 + 80 * y, cat_width, 6 * math.sin(t + seed)),
            Placed("text", 320 - 150 * x, 200 - 60 * y, 250 + 80 * math.cos(t)),
            Placed("page", 150, 300, 200 + 60 * math.sin(0.5 * t)),
        ]

    backdrop = ("rocket", "coffee", "brick", "grass")[seed % 4]
    return Stream(f"posters {seed}", 5.0, scene, backdrop, seed=seed, follow=None)


def combined() -> Stream:
    """Everything at once: a face moving, tilting, shrinking to 50 px and back, in changing light,
    with a smaller second face and the cat and text posters behind it."""
    path = _wander(9, 0.7)

    def scene(t):
        x, y = path(t)
        width = 100 - 50 * (0.5 - 0.5 * math.cos(2 * math.pi * t / 6.0))
        gain = 1.0 + 0.35 * math.sin(2 * math.pi * t / 4.0)
        return gain, [
            Placed("text", 530, 90, 200, 3),
            Placed("cat", 110, 320, 190),
            Placed("lfw7", 560 - 20 * x, 300, 46, 5 * math.sin(t)),
            Placed("astronaut", 300 + 160 * x, 190 + 90 * y, width, 20 * math.sin(2 * math.pi * t / 2.7)),
        ]

    return Stream("combined", 7.0, scene, "coffee", seed=9, follow=3)


def nearer() -> Stream:
    """A face 70 px wide, then at 1.5 s a nearer one (120 px, 2.9 times the area) steps in: the
    eyes should go to it within half a second (the truth switches at 2.0 s) and stay there."""

    def scene(t):
        first = Placed("astronaut", 200 + 20 * math.sin(t), 200 + 10 * math.sin(1.3 * t), 70)
        if t < 1.5:
            return 1.0, [first]
        return 1.0, [first, Placed("mirror", 450 - 15 * math.sin(0.8 * t), 190, 120)]

    return Stream(
        "nearer face", 4.0, scene, "rocket", seed=11, follow=lambda t: 0 if t < 2.0 else 1, switch=(1.5, 2.0)
    )


def centred() -> Stream:
    """A still face at the image's centre: the eyes should look straight ahead."""

    def scene(t):
        return 1.0, [Placed("astronaut", WIDTH / 2, HEIGHT / 2, 90)]

    return Stream("centred", 2.0, scene, "brick", seed=10)


SCENARIOS: Sequence[Callable[[], Stream]] = (
    moving,
    tilting,
    shrinking,
    brightness,
    two_faces,
    leaving,
    cat,
    text_poster,
    functools.partial(posters, 9),
    functools.partial(posters, 0),
    combined,
)


class Result(NamedTuple):
    stream: Stream
    truths: List[Optional[Tuple[float, float]]]  # eye truth per frame (None: no face in full view)
    targets: List[Optional[Tuple[float, float]]]  # what the follower said
    seconds: List[float]  # processing time per frame


def run(stream: Stream, update: Callable[[np.ndarray, float], Optional[Tuple[float, float]]]) -> Result:
    """Feed every frame of `stream` to `update(image, t)`; collect targets and time per frame."""
    truths, targets, seconds = [], [], []
    for frame in stream.frames():
        started = time.perf_counter()
        target = update(frame.image, frame.t)
        seconds.append(time.perf_counter() - started)
        truths.append(frame.target)
        targets.append(target)
    return Result(stream, truths, targets, seconds)


def coverage(result: Result, settle: float = 1.0) -> float:
    """The fraction of frames, after `settle` seconds, with a face in full view that got a target."""
    pairs = [
        (truth, target)
        for k, (truth, target) in enumerate(zip(result.truths, result.targets))
        if truth is not None and k / result.stream.fps >= settle
    ]
    if not pairs:
        return float("nan")
    return sum(target is not None for _, target in pairs) / len(pairs)


def rmse(result: Result, settle: float = 1.0) -> float:
    """RMS distance in eye pixels from the truth, over frames after `settle` s with both."""
    errors = [
        (truth[0] - target[0]) ** 2 + (truth[1] - target[1]) ** 2
        for k, (truth, target) in enumerate(zip(result.truths, result.targets))
        if truth is not None and target is not None and k / result.stream.fps >= settle
    ]
    return math.sqrt(sum(errors) / len(errors)) if errors else float("nan")


def let_go_after(result: Result) -> Optional[float]:
    """Seconds from the face leaving to the first None after it (None if it never let go)."""
    left = result.stream.left_at
    assert left is not None
    for k, target in enumerate(result.targets):
        t = k / result.stream.fps
        if t >= left and target is None and all(x is None for x in result.targets[k:]):
            return t - left
    return None
