"""The face: how it looks, where the eyes go, colour order, sizes, the API."""

from __future__ import annotations

import dataclasses
import math
import os
import random

import numpy as np
import pytest
from PIL import Image

from baxterface_cli import Face, FaceState
from baxterface_cli.core.face_constants import EMOTIONS
from baxterface_cli.core.geometry import clamp_to_ellipse
from baxterface_cli.drawing.artwork import EYE_DX, EYE_Y, draw_theme
from baxterface_cli.drawing.stacks import compose
from baxterface_cli.resources import resource
from conftest import ROOT

GOLDEN = ROOT / "tests" / "golden" / "faces"
UPDATE = os.environ.get("BAXTERFACE_UPDATE_GOLDEN") == "1"
SMALL = (256, 150)  # golden images are the 1024x600 face, box-filtered down 4x


@pytest.fixture(scope="module")
def face():
    return Face()


def small(rgb: np.ndarray) -> np.ndarray:
    return np.asarray(Image.fromarray(rgb, "RGB").resize(SMALL, Image.BOX), np.int16)


@pytest.mark.parametrize("emotion", list(EMOTIONS), ids=[e.replace(" ", "_") for e in EMOTIONS])
def test_each_emotion_matches_its_golden_image(face, emotion):
    face.set_emotion(emotion, variant=0)
    face.look_at(0, 0)
    got = small(face.frame_rgb())
    path = GOLDEN / f"{emotion.replace(' ', '_')}.png"
    if UPDATE:
        Image.fromarray(got.astype(np.uint8), "RGB").save(path, optimize=True)
    want = np.asarray(Image.open(path).convert("RGB"), np.int16)
    diff = np.abs(got - want)
    # Tolerance for anti-aliasing that differs between Pillow versions, but
    # far below what a changed part, colour or position would make.
    assert diff.mean() < 1.0 and (diff > 24).mean() < 0.002, (diff.mean(), (diff > 24).mean())


def test_emotions_look_different_from_each_other(face):
    frames = {}
    for emotion in EMOTIONS:
        face.set_emotion(emotion, variant=0)
        frames[emotion] = small(face.frame_rgb())
    names = list(frames)
    for i, a in enumerate(names):
        for b in names[i + 1 :]:
            changed = (np.abs(frames[a] - frames[b]) > 30).any(axis=2).mean()
            assert changed > 0.003, (a, b, changed)


def test_sleep_closes_the_eyes_and_bored_half_closes_them(face):
    face.set_emotion("sleep", 0)
    assert face.state.eyelids == 0.0 and face.state.skin == 5
    face.set_emotion("bored", 0)
    assert 0.4 < face.state.eyelids < 0.6


@pytest.mark.parametrize(
    "x, y",
    [(0, 0), (79, 0), (0, -119), (40, 60), (-56, 84), (80, 0), (0, 120)],
)
def test_points_inside_the_ellipse_are_unchanged(x, y):
    assert clamp_to_ellipse(x, y) == (x, y)


@pytest.mark.parametrize("x, y", [(200, 0), (0, -500), (100, 100), (-300, 45), (1e9, -1e9)])
def test_points_outside_are_pulled_onto_the_ellipse_along_their_direction(x, y):
    cx, cy = clamp_to_ellipse(x, y)
    assert math.isclose((cx / 80) ** 2 + (cy / 120) ** 2, 1.0, rel_tol=1e-9)
    assert math.isclose(math.atan2(cy, cx), math.atan2(y, x), abs_tol=1e-12)


def test_look_at_clamps_and_reports_where_the_eyes_went(face):
    assert face.look_at(160, 0) == (80.0, 0.0)
    assert face.state.eye_x == 80.0


def dark_centroid(rgb: np.ndarray, box):
    """Centre of the pupil-dark pixels in a box of the frame."""
    x0, y0, x1, y1 = box
    region = rgb[y0:y1, x0:x1].astype(int)
    dark = region.sum(axis=2) < 110  # the pupil (24, 24, 34), not the ink of the rims (62, 36, 38)
    ys, xs = np.nonzero(dark)
    return x0 + xs.mean(), y0 + ys.mean()


def test_eye_coordinates_keep_their_meaning_at_any_size():
    for size in [(1024, 600), (800, 600)]:  # the face's own, and one letterboxed and scaled down
        face = Face(size=size)
        s = min(size[0] / 1024, size[1] / 600)
        ox, oy = (size[0] - 1024 * s) / 2, (size[1] - 600 * s) / 2
        cx, cy = ox + (512 - EYE_DX) * s, oy + EYE_Y * s
        box = tuple(int(v) for v in (cx - 100 * s, cy - 130 * s, cx + 100 * s, cy + 130 * s))
        at_rest = dark_centroid(face.frame_rgb(), box)
        face.look_at(40, -20)
        moved = dark_centroid(face.frame_rgb(), box)
        assert face.frame().shape == (size[1], size[0], 3)
        assert moved[0] - at_rest[0] == pytest.approx(40 * s, abs=1.5 * s)
        assert moved[1] - at_rest[1] == pytest.approx(-20 * s, abs=1.5 * s)


def test_positive_x_moves_the_eyes_to_the_viewers_right(face):
    face.set_emotion("default", 0)
    face.look_at(0, 0)
    box = (312 - 100, 255 - 130, 312 + 100, 255 + 130)
    rest = dark_centroid(face.frame_rgb(), box)
    face.look_at(50, 0)
    assert dark_centroid(face.frame_rgb(), box)[0] > rest[0] + 40


def test_skin_pixels_are_warm_in_rgb_and_bgr_in_the_frame(face):
    face.set_emotion("default", 0)
    rgb, bgr = face.frame_rgb(), face.frame()
    r, g, b = (int(v) for v in rgb[300, 512])  # between the eyes: skin
    assert r > b + 60 and r > 200
    assert tuple(bgr[300, 512]) == (b, g, r)
    assert bgr.dtype == np.uint8 and bgr.flags["C_CONTIGUOUS"]


def test_equal_states_give_equal_frames():
    a, b = Face(), Face()
    for f in (a, b):
        f.set_emotion("crafty", 1)
        f.look_at(-30, 25)
        f.set_eyelids(0.7)
    b.look_at(50, 50)
    b.look_at(-30, 25)  # b got there by another route
    assert np.array_equal(a.frame(), b.frame())


def test_frame_is_the_callers_and_read_only():
    face = Face()  # its own: the module's shared face may have been left with its eyes shut
    first = face.frame()
    face.look_at(-60, 0)
    second = face.frame()
    assert not np.array_equal(first, second)
    with pytest.raises(ValueError):
        first[:] = 0  # read-only: a copy is the caller's to scribble on
    scribbled = first.copy()
    scribbled[:] = 0
    face.look_at(60, 0)
    third = face.frame()
    assert not np.array_equal(second, third)
    face.look_at(-60, 0)
    assert np.array_equal(face.frame(), second)  # a frame held is never changed
    assert np.array_equal(second, compose(face._renderer.layers, face.state))


def frames_dropped_at_once(face: Face, steps) -> None:
    """Each step changes the face; each frame is checked against the plain recomposite, then
    dropped, so the next one reuses its array and copies in only what changed."""
    layers = face._renderer.layers
    for step in steps:
        step(face)
        assert np.array_equal(face.frame(), compose(layers, face.state)), step


def test_a_dropped_frame_reused_draws_every_change_right():
    face = Face(size=(512, 300))
    start = face.expression
    end = start._replace(mouth_curve=-1.0, brow_left_height=0.8)
    steps = [lambda f, x=x: f.look_at(x, -x / 2) for x in range(-60, 61, 7)]
    steps += [lambda f, o=o: f.set_eyelids(o) for o in (0.8, 0.3, 0.0, 0.6, 1.0)]
    steps += [lambda f, k=k: f.set_expression(start.mix(end, k / 6)) for k in range(7)]
    steps += [lambda f, e=e: f.set_emotion(e, variant=0) for e in ("happy", "sad", "angry", "sleep")]
    steps += [lambda f, v=v: f.set_mood(v, -v / 2) for v in (-0.9, -0.3, 0.4, 0.9)]
    steps += [lambda f: f.wink("left"), lambda f: f.wink(None), lambda f: f.look_at(0, 0)]
    steps += [lambda f: None, lambda f: f.frame_rgb(), lambda f: f.look_at(20, 20)]  # a render between
    frames_dropped_at_once(face, steps)


def test_a_frame_made_writable_and_scribbled_on_is_not_reused_as_it_is():
    face = Face(size=(512, 300))
    frame = face.frame()
    frame.flags.writeable = True  # numpy allows it on an array that owns its memory
    frame[:] = 0
    del frame
    face.look_at(30, 0)
    assert np.array_equal(face.frame(), compose(face._renderer.layers, face.state))


def test_bad_part_names_and_values_are_refused_clearly(face):
    with pytest.raises(ValueError, match="did you mean 'smile'"):
        face.set_mouth("smil")
    with pytest.raises(ValueError, match="skin must be from 0 to 5"):
        face.set_skin(7)
    with pytest.raises(ValueError, match="variants"):
        face.set_emotion("default", variant=3)
    with pytest.raises(ValueError, match="from 0 to 1"):
        face.set_eyelids(1.5)
    with pytest.raises(ValueError, match="finite"):
        face.look_at(float("inf"), 0)
    with pytest.raises(ValueError, match="finite"):
        face.look_at(float("nan"), 0)
    with pytest.raises(ValueError, match="skin"):
        face.set_skin(True)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="size 0x600 is too small"):
        Face(size=(0, 600))
    face.frame()  # still drawable after every refusal


def test_a_state_with_numbers_that_are_not_finite_still_draws():
    face = Face(size=(256, 150))
    face.state = face.state.replace(eye_x=float("nan"), eyelids=float("inf"))
    assert face.frame().shape == (150, 256, 3)


def test_head_pan_is_clamped_like_wobble(face):
    face.set_head_pan(3.0)
    assert face.state.head_pan == 1.5


def test_random_variants_come_from_the_rng(face):
    picks = set()
    rng = random.Random(7)
    for _ in range(40):
        face.set_emotion("bored", rng=rng)
        picks.add(face.state.brows)
    assert picks == set(EMOTIONS["bored"].brows)
    face.set_emotion("wake_up", 0)  # the legacy spelling is accepted too
    assert face.state.skin == EMOTIONS["wake up"].skin


def test_the_committed_theme_is_what_the_drawing_script_draws():
    drawn = draw_theme((1024, 600))
    folder = resource("assets/default")
    for (kind, name), image in drawn.items():
        filename = f"{kind}.png" if kind == name else f"{kind}-{name}.png"
        committed = np.asarray(Image.open(folder / filename).convert("RGBA"), np.int16)
        diff = np.abs(np.asarray(image, np.int16) - committed)
        assert diff.mean() < 0.5 and (diff > 32).mean() < 0.001, filename


def test_a_crossfade_is_between_its_ends(tmp_path):
    # Themes of pictures crossfade; the drawn face morphs instead (tests/drawing/test_morph.py).
    Face().theme.export(tmp_path / "pictures")
    face = Face(theme=tmp_path / "pictures")
    face.set_emotion("happy", 0)
    start = face.state
    face.set_emotion("sad", 0)
    end = face.state.replace(eyelids=start.eyelids)
    layers = face.theme.layers(face.size)
    assert layers.drawn is None
    mid = compose(layers, end.replace(fade_from=start.parts, fade=0.5)).astype(int)
    a, b = compose(layers, start).astype(int), compose(layers, end).astype(int)
    assert np.all(mid >= np.minimum(a, b) - 1) and np.all(mid <= np.maximum(a, b) + 1)
    assert np.abs(mid - (a + b) / 2).max() <= 1.0
    assert np.array_equal(
        compose(layers, end.replace(fade_from=start.parts, fade=0.0)), compose(layers, start)
    )


def test_face_state_is_immutable():
    state = FaceState()
    with pytest.raises(dataclasses.FrozenInstanceError):
        state.eye_x = 3  # type: ignore[misc]
