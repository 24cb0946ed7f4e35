"""The drawn face: any expression drawn from its numbers, presets as before, morphs, winks."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from baxterface_cli import Face
from baxterface_cli.core.expression import MOUTH_FIELDS
from baxterface_cli.core.face_constants import BROWS, EMOTIONS, MOUTHS
from baxterface_cli.core.face_state import FaceState, Parts
from baxterface_cli.core.presets import BROW_PRESETS, MOUTH_PRESETS, emotion_preset, from_parts
from baxterface_cli.drawing.drawn_parts import STEPS
from baxterface_cli.drawing.renderer import Renderer
from baxterface_cli.drawing.stacks import compose
from baxterface_cli.drawing.theme import Theme

SMALL = (256, 150)


@pytest.fixture(scope="module")
def layers():
    return Theme.default().layers((1024, 600))


def small(bgr: np.ndarray) -> np.ndarray:
    return np.asarray(Image.fromarray(bgr[..., ::-1].copy(), "RGB").resize(SMALL, Image.BOX), np.int16)


def looks_alike(a: np.ndarray, b: np.ndarray) -> bool:
    """The golden pictures' tolerance: what antialiasing may change, not a shape."""
    diff = np.abs(small(a) - small(b))
    return diff.mean() < 1.0 and (diff > 24).mean() < 0.002


@pytest.mark.parametrize("name", list(EMOTIONS))
def test_each_emotion_at_full_strength_is_its_picture(layers, name):
    spec = EMOTIONS[name]
    for variant, (mouth, brows) in enumerate(spec.variants):
        parts = FaceState(skin=spec.skin, mouth=mouth, brows=brows)
        drawn = parts.replace(expression=emotion_preset(name, variant))
        assert np.array_equal(compose(layers, drawn), compose(layers, parts)), (name, variant)


@pytest.mark.parametrize("kind, name", [("mouth", m) for m in MOUTHS] + [("brows", b) for b in BROWS])
def test_the_numbers_draw_the_named_parts_as_their_pictures(layers, kind, name):
    """Nudged a step off its preset, a part is drawn from its numbers, not taken from the
    theme's picture: it must look the same."""
    preset = from_parts(Parts(**{kind: name}))
    field = MOUTH_FIELDS[0] if kind == "mouth" else "brow_left_height"
    nudged = preset._replace(**{field: getattr(preset, field) + 1 / STEPS})
    picture = compose(layers, FaceState(**{kind: name}))
    drawn = compose(layers, FaceState(**{kind: name}).replace(expression=nudged))
    assert not np.array_equal(picture, drawn)  # really drawn anew
    assert looks_alike(picture, drawn), name


def mouth_ink_row(frame: np.ndarray, x: int = 512) -> float:
    """The mean row of the mouth's dark ink down the column at x."""
    column = frame[400:600, x].astype(int).sum(axis=1)
    rows = np.flatnonzero(column < 250)
    return 400 + float(rows.mean())


def test_a_morph_bends_the_mouth_through_the_shapes_between(layers):
    smile, frown = from_parts(Parts(mouth="smile")), from_parts(Parts(mouth="sad"))
    renderer = Renderer(layers)
    rows = [
        mouth_ink_row(renderer.render(FaceState(expression=smile.mix(frown, u))).copy()) for u in (0, 0.5, 1)
    ]
    # The smile's middle hangs low, the frown's rises: halfway, the line is in between.
    assert rows[0] > rows[1] > rows[2]
    a, b = (compose(layers, FaceState(expression=e)).astype(int) for e in (smile, frown))
    middle = compose(layers, FaceState(expression=smile.mix(frown, 0.5))).astype(int)
    # Not a crossfade: somewhere the middle frame is far from the average of its ends.
    assert np.abs(middle - (a + b) / 2).max() > 60


def test_a_wink_shuts_the_robots_left_eye_which_is_on_the_viewers_right(layers):
    open_face = compose(layers, FaceState(expression=emotion_preset("default")))
    wink = compose(layers, FaceState(expression=emotion_preset("default")._replace(lid_left=0.0)))
    changed = np.abs(open_face.astype(int) - wink.astype(int)).max(axis=2) > 30
    columns = np.flatnonzero(changed.any(axis=0))
    assert columns.size and columns.min() > 512  # the viewer's right half only
    both = compose(layers, FaceState(eyelids=0.0))
    assert np.array_equal(wink[:, 512:], both[:, 512:])  # shut as the lids shut both


def test_the_cached_renderer_draws_what_the_plain_recomposite_draws(layers):
    renderer = Renderer(layers)
    start = emotion_preset("happy")
    for i, u in enumerate(np.linspace(0, 1, 7)):
        expression = start.mix(emotion_preset("angry"), float(u))._replace(lid_right=1 - u / 2)
        state = FaceState(eye_x=10.0 * i, eye_y=-5.0 * i, eyelids=0.8, expression=expression)
        assert np.array_equal(renderer.render(state), compose(layers, state)), u


def test_a_morph_that_keeps_its_skin_redraws_only_what_moved_and_draws_it_right(layers):
    # One skin throughout: the renderer repaints its one moving canvas where the mouth or the
    # brows were or are, between named faces it keeps; every frame as the plain recomposite.
    renderer = Renderer(layers)
    happy = emotion_preset("happy")
    steps = [happy._replace(mouth_curve=1 - u) for u in np.linspace(0, 2, 5)]
    steps += [happy._replace(brow_left_height=u, brow_right_angle=-u) for u in np.linspace(0, 1, 4)]
    steps += [happy, happy._replace(mouth_open=0.2, brow_left_curve=0.5), emotion_preset("default")]
    for i, expression in enumerate(steps):
        state = FaceState(eye_x=6.0 * (i % 3), eyelids=1.0 - 0.1 * (i % 2), expression=expression)
        assert np.array_equal(renderer.render(state), compose(layers, state)), i


def test_the_lower_lids_rise_into_each_eye_on_its_own(layers):
    # The robot's left eye is on the viewer's right; a risen lower lid covers the eye's white
    # below the pupil, and the cached renderer follows it rising and sinking.
    white_below_pupil = (slice(330, 360), slice(650, 780))  # the viewer's right eye, low
    other_eye = (slice(330, 360), slice(250, 380))
    rest = compose(layers, FaceState(expression=emotion_preset("default")))
    risen = compose(layers, FaceState(expression=emotion_preset("default")._replace(lower_lid_left=1.0)))
    assert np.abs(risen[white_below_pupil].astype(int) - rest[white_below_pupil]).mean() > 40
    assert np.array_equal(risen[other_eye], rest[other_eye])
    renderer = Renderer(layers)
    for i, u in enumerate([0.0, 0.3, 1.0, 0.6, 0.0, 0.8]):
        e = emotion_preset("happy")._replace(lower_lid_left=u, lower_lid_right=1 - u)
        state = FaceState(eye_x=5.0 * i, eyelids=0.9, expression=e)
        assert np.array_equal(renderer.render(state), compose(layers, state)), u
    state = FaceState(expression=None)
    assert np.array_equal(renderer.render(state), compose(layers, state))


def test_each_eye_grows_and_shrinks_on_its_own_and_its_lids_still_shut_it(layers):
    happy = emotion_preset("happy")
    rest = compose(layers, FaceState(expression=happy))
    big = compose(layers, FaceState(expression=happy._replace(eye_left=1.2)))
    # The robot's left eye, on the viewer's right, shows white above where its socket was.
    above = (slice(100, 112), slice(700, 724))
    assert rest[above].mean() < 200 < big[above].mean()
    assert np.array_equal(big[:, :450], rest[:, :450])  # the other eye as it was
    shut = compose(layers, FaceState(eyelids=0.0, expression=happy._replace(eye_left=1.2, eye_right=0.8)))
    white = np.all(shut[60:460] > 235, axis=-1)  # the whites' colour: none shows through shut lids
    assert white.sum() == 0
    renderer = Renderer(layers)
    sizes = [(1.0, 1.0), (1.1, 0.9), (1.2, 0.8), (1.2, 0.8), (0.9, 1.15), (1.0, 1.0)]
    for i, (left, right) in enumerate(sizes):
        e = happy._replace(eye_left=left, eye_right=right, lower_lid_left=0.1 * i)
        state = FaceState(eye_x=7.0 * i, eye_y=-3.0 * i, eyelids=1.0 - 0.15 * (i % 3), expression=e)
        assert np.array_equal(renderer.render(state), compose(layers, state)), (left, right)


def test_numbers_out_of_range_or_not_finite_still_draw(layers):
    wild = emotion_preset("happy")._replace(
        mouth_open=50.0, mouth_width=-3.0, brow_left_height=float("nan"), tint=99.0, sleepy=-1.0
    )
    frame = Renderer(layers).render(FaceState(expression=wild))
    assert frame.shape == (600, 1024, 3)


def test_a_theme_of_pictures_shows_the_named_parts(tmp_path):
    Face().theme.export(tmp_path / "pictures")
    layers = Theme.load(tmp_path / "pictures").layers((1024, 600))
    assert layers.drawn is None
    nudged = emotion_preset("sad", 1)._replace(mouth_curve=-0.8, brow_left_height=0.1)
    # The named parts are a view of the numbers: a picture theme draws the ones nearest them.
    sad = EMOTIONS["sad"]
    pictures = FaceState(skin=sad.skin, mouth=sad.variants[1][0], brows=sad.variants[1][1])
    assert np.array_equal(compose(layers, FaceState(expression=nudged)), compose(layers, pictures))
    assert not np.array_equal(compose(layers, pictures), compose(layers, FaceState()))


def test_every_preset_is_a_known_part():
    assert set(MOUTH_PRESETS) == set(MOUTHS) and set(BROW_PRESETS) == set(BROWS)


def dark_in_eye(frame: np.ndarray, index: int) -> int:
    x = 312 if index == 0 else 712  # the viewer's left eye is the robot's right
    return int((frame[180:330, x - 60 : x + 60].astype(int).sum(axis=2) < 150).sum())


def test_pupils_grow_and_shrink_each_on_its_own(layers):
    base = emotion_preset("default")
    plain = compose(layers, FaceState(expression=base))
    wide = compose(layers, FaceState(expression=base._replace(pupil_left=1.5)))
    assert dark_in_eye(wide, 1) > 1.5 * dark_in_eye(plain, 1)  # the robot's left: the viewer's right
    assert dark_in_eye(wide, 0) == dark_in_eye(plain, 0)
    small_ = compose(layers, FaceState(expression=base._replace(pupil_right=0.6)))
    assert dark_in_eye(small_, 0) < 0.6 * dark_in_eye(plain, 0)


def lid_rows(frame: np.ndarray, x: int) -> np.ndarray:
    """The rows of lid colour down column x, inside the socket (70 pixels either side of the
    eye's middle, the socket's top is at row 147) and above the eye's middle."""
    lid = np.array((126, 172, 226))  # LID_COLOR in B, G, R
    return 160 + np.flatnonzero(np.abs(frame[160:255, x].astype(int) - lid).max(axis=1) < 30)


@pytest.mark.parametrize("openness", [1.0, 0.8])
def test_a_tilted_lid_drops_its_inner_corner_across_the_eye_even_when_open(layers, openness):
    glare = emotion_preset("default")._replace(lid_left_angle=1.0, lid_right_angle=1.0)
    frame = compose(layers, FaceState(eyelids=openness, expression=glare))
    level = compose(layers, FaceState(eyelids=openness, expression=emotion_preset("default")))
    # The viewer's left eye: its inner corner is on its right, toward the face's middle.
    inner, outer = lid_rows(frame, 312 + 70), lid_rows(frame, 312 - 70)
    assert len(inner) and inner.max() - (outer.max() if len(outer) else 160) > 15
    assert not len(lid_rows(level, 312 + 70)) and not len(lid_rows(level, 312 - 70))


def test_a_sorrowful_tilt_drops_the_outer_corner_and_a_shut_lid_stays_shut(layers):
    sorrow = emotion_preset("default")._replace(lid_left_angle=-1.0, lid_right_angle=-1.0)
    frame = compose(layers, FaceState(expression=sorrow))
    inner, outer = lid_rows(frame, 312 + 70), lid_rows(frame, 312 - 70)
    assert len(outer) and outer.max() - (inner.max() if len(inner) else 160) > 15
    shut = compose(layers, FaceState(eyelids=0.0, expression=emotion_preset("default")))
    for tilt in (-1.0, 1.0):
        tilted = emotion_preset("default")._replace(lid_left_angle=tilt, lid_right_angle=tilt)
        assert np.array_equal(compose(layers, FaceState(eyelids=0.0, expression=tilted)), shut)


def test_the_cached_renderer_keeps_up_with_pupils_and_tilts(layers):
    renderer = Renderer(layers)
    base = emotion_preset("happy")
    for i, u in enumerate(np.linspace(0, 1, 6)):
        e = base._replace(pupil_left=1 + u / 2, pupil_right=1 - u / 3, lid_left_angle=u, lid_right_angle=-u)
        state = FaceState(eye_x=8.0 * i, eyelids=0.7 + 0.05 * i, expression=e)
        assert np.array_equal(renderer.render(state), compose(layers, state)), u
