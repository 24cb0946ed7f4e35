"""Far faces: synthetic camera streams of people 1.5 to 3.5 m from Baxter's head camera.

At 640x400 and a focal length of 410 pixels, a face (about 15 cm across) is 24
pixels wide at 2.5 m and 40 at 1.5 m. These streams, built as face_streams'
are (real faces from scikit-image pasted at a known centre, width and tilt),
have faces 24 to 46 pixels wide, tilted up to 20 degrees either way, in light
from half to 1.4 times as bright, over real photographs full of detail (the
motorcycle in a workshop, gravel, the coffee cup, the rocket on its pad), and
among small distractors: the cat, pages of text, and pictures of LFW's that are
not faces. The faces are the astronaut and six LFW faces drawn at random.
"""

from __future__ import annotations

import math
from typing import Callable, Sequence

from face_streams import FAR_FACES, HEIGHT, NOT_FACES, WIDTH, Placed, Stream, _wander

A, B, C, D, E, F = (f"lfw{index}" for index in FAR_FACES)  # C, the hardest, is the bench's alone


def far_moving() -> Stream:
    """A face 30 px wide wandering over the workshop, tilting a little, in light from x0.5 to x1.4."""
    path = _wander(21, 0.6)

    def scene(t):
        x, y = path(t)
        gain = 0.95 + 0.45 * math.sin(2 * math.pi * t / 3.0 + 1.0)
        return gain, [Placed(A, 320 + 230 * x, 200 + 120 * y, 30, 6 * math.sin(1.1 * t))]

    return Stream("far moving", 4.0, scene, "motorcycle", seed=21)


def far_tilting() -> Stream:
    """The astronaut's face, 28 px wide, tilting 20 degrees each way about once in 2.5 s, over gravel."""
    path = _wander(22, 0.5)

    def scene(t):
        x, y = path(t)
        return 1.0, [
            Placed("astronaut", 320 + 200 * x, 200 + 100 * y, 28, 20 * math.sin(2 * math.pi * t / 2.5))
        ]

    return Stream("far tilting", 4.0, scene, "gravel", seed=22)


def far_tilted() -> Stream:
    """A face 26 px wide held tilted 20 degrees from the start, in dim light (x0.6), over the rocket."""
    path = _wander(23, 0.4)

    def scene(t):
        x, y = path(t)
        return 0.6, [Placed(B, 320 + 180 * x, 200 + 90 * y, 26, -20 + 2 * math.sin(t))]

    return Stream("far tilted", 3.5, scene, "rocket", seed=23)


def walking_away() -> Stream:
    """The astronaut walking away: 64 px wide down to 24 px in 3 s, then staying there, over the
    workshop."""
    path = _wander(24, 0.5)

    def scene(t):
        x, y = path(t)
        width = 64 - 40 * min(1.0, t / 3.0)
        return 1.2, [Placed("mirror", 320 + 200 * x, 200 + 100 * y, width, 8 * math.sin(1.3 * t))]

    return Stream("walking away", 5.0, scene, "motorcycle", seed=24)


def far_two() -> Stream:
    """Two far faces of about the same size (30 px, and 0.85 times that at first, then up to as
    large): the first, the nearer at the start, is kept. (Up to 1.0, not 1.1 as for the near faces:
    at 30 pixels the detectors' boxes of these two faces differ by a tenth either way, MTCNN's
    making the second 4 % larger than it is drawn, the cascades' 13 % smaller.)"""

    def scene(t):
        sway = 25 * math.sin(2 * math.pi * t / 3.0)
        ratio = 0.925 - 0.075 * math.cos(2 * math.pi * t / 2.5)
        return 1.0, [
            Placed(D, 220 + sway, 190 + 10 * math.sin(1.7 * t), 30),
            Placed(E, 430 + sway, 210 - 10 * math.sin(1.3 * t), 30 * ratio, 5),
        ]

    return Stream("far two", 4.0, scene, "coffee", seed=25)


NEARER_FROM, NEARER_TO, NEARER_SECONDS = 26.0, 52.0, 3.0  # the second face's width, over that long
NEARER_FIRST = 34.0  # the first face's
# When the second face's area passes 1.3 times the first's: from then the eyes should go to it.
NEARER_AT = 0.5 + NEARER_SECONDS * (NEARER_FIRST * math.sqrt(1.3) - NEARER_FROM) / (NEARER_TO - NEARER_FROM)


def far_nearer() -> Stream:
    """A face 34 px wide, and another walking nearer, 26 px to 52 px from 0.5 s to 3.5 s: the truth
    moves to it when its area passes 1.3 times the first's (NEARER_AT, 1.97 s); the eyes should
    follow within half a second (or a quarter of a second before, when it is 1.2 times)."""

    def scene(t):
        grow = min(1.0, max(0.0, (t - 0.5) / NEARER_SECONDS))
        return 1.0, [
            Placed(F, 200 + 15 * math.sin(t), 200 + 8 * math.sin(1.3 * t), NEARER_FIRST),
            Placed("mirror", 450 - 40 * grow, 210, NEARER_FROM + (NEARER_TO - NEARER_FROM) * grow, -6),
        ]

    return Stream(
        "far nearer",
        4.5,
        scene,
        "rocket",
        seed=26,
        follow=lambda t: 0 if t < NEARER_AT else 1,
        switch=(NEARER_AT - 0.25, NEARER_AT + 0.5),
    )


def far_leaving() -> Stream:
    """A face 30 px wide that moves about, then walks out of the frame to the left at 2 s."""
    path = _wander(27, 0.5)
    start = 2.0

    def scene(t):
        x, y = path(min(t, start))
        return 1.0, [Placed(A, 320 + 150 * x - max(0.0, t - start) * 300, 200 + 80 * y, 30, 4)]

    x, _ = path(start)
    left_at = start + (320 + 150 * x - 15) / 300  # fully in view until its left edge reaches the frame's
    return Stream("far leaving", 4.0, scene, "coffee", seed=27, left_at=left_at)


def far_distractors() -> Stream:
    """Small things that are not faces, moving over the workshop: the cat 60 to 110 px wide (its face
    about 20 to 40), a page of text, and four LFW pictures that are not faces, 24 to 44 px wide."""
    path = _wander(428, 0.6)

    def scene(t):
        x, y = path(t)
        patches = [
            Placed(
                f"lfw{index}",
                80 + 150 * k + 30 * math.sin(t + k),
                100 + 200 * (k % 2),
                24 + 5 * k,
                8 * k - 12,
            )
            for k, index in enumerate(NOT_FACES[:4])
        ]
        return 1.0 + 0.3 * math.sin(t), [
            Placed("cat", 320 + 200 * x, 200 + 100 * y, 85 + 25 * math.sin(0.9 * t), 6 * math.sin(t)),
            Placed("text", 560, 320, 90, 3),
            *patches,
        ]

    return Stream("far distractors", 4.0, scene, "motorcycle", seed=28, follow=None)


def crowd() -> Stream:
    """Three far faces: the first seen (from the start, off the middle), the nearest (46 px) and the
    most central (at the middle), both from 0.6 s: which is followed is the policy's to say. The
    truth is the nearest's (the default policy)."""

    def scene(t):
        faces = [Placed(A, 500, 250, 30)]
        if t >= 0.6:
            faces += [Placed("astronaut", 150, 170, 46), Placed(D, WIDTH / 2 + 10, HEIGHT / 2, 32, 4)]
        return 1.0, faces

    return Stream("crowd", 3.0, scene, "gravel", seed=29, follow=lambda t: 0 if t < 0.6 else 1)


FAR_SCENARIOS: Sequence[Callable[[], Stream]] = (
    far_moving,
    far_tilting,
    far_tilted,
    walking_away,
    far_two,
    far_nearer,
    far_leaving,
    far_distractors,
)
