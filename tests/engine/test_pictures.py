"""The named parts are a view of the expression's numbers: what a theme of pictures shows, when
it crossfades, what `explain` lists and what the Python API's `Face` shows all read them off."""

from __future__ import annotations

import numpy as np
import pytest

from baxterface_cli import Face, parse
from baxterface_cli.core.face_constants import EMOTIONS
from baxterface_cli.core.face_state import FaceState, Parts
from baxterface_cli.core.presets import from_parts
from baxterface_cli.drawing.renderer import Renderer
from baxterface_cli.drawing.stacks import compose, crossfade
from baxterface_cli.drawing.theme import Theme
from baxterface_cli.engine.compiler import compile_script
from baxterface_cli.engine.explanation import explained
from baxterface_cli.engine.timeline import CROSSFADE


def timeline(text):
    return compile_script(parse(text))


def test_parts_swapped_at_one_moment_crossfade_from_what_the_face_showed():
    # Two swaps at the same moment are one change of the pictures: from the default face's, not
    # from a face with the new mouth and the old skin that was never shown.
    mid = timeline("mouth teeth\nskin 3").sample(CROSSFADE / 2)
    assert mid.parts == Parts(3, "teeth", "normal")
    assert mid.fade_from == Parts() and mid.fade == pytest.approx(0.5)
    assert mid.expression == from_parts(Parts()).mix(from_parts(Parts(3, "teeth")), 0.5)


def test_explain_lists_a_face_change_only_where_the_pictures_change():
    faces = lambda text: [line.split("face  ")[1] for line in explained(timeline(text)) if "face  " in line]  # noqa: E731
    assert faces("mouth smile\nskin 2") == []  # the default face already
    assert faces("mouth teeth\nbrows raised") == ["skin 2, mouth teeth, brows raised"]
    # A small move of the numbers keeps the nearest pictures; a large one changes them.
    assert faces("mouth curve 0.8 in 1s") == []
    assert faces("mouth curve -1 in 1s") == ["skin 2, mouth sad, brows normal"]


@pytest.fixture(scope="module")
def pictures(tmp_path_factory):
    folder = tmp_path_factory.mktemp("theme") / "pictures"
    Face().theme.export(folder)
    layers = Theme.load(folder).layers((1024, 600))
    assert layers.drawn is None
    return layers


def test_a_theme_of_pictures_crossfades_a_scripts_swap_read_off_the_numbers(pictures):
    state = timeline("mouth teeth").sample(CROSSFADE / 2)
    assert state.fade_from == Parts() and state.parts == Parts(mouth="teeth")
    expected = crossfade(compose(pictures, FaceState()), compose(pictures, FaceState(mouth="teeth")), 0.5)
    assert np.array_equal(Renderer(pictures).render(state), expected)
    assert np.array_equal(compose(pictures, state), expected)


def test_a_theme_of_pictures_shows_the_parts_nearest_a_morph_where_it_heads(pictures):
    # `mouth curve -1 in 1s`: the pictures change as the move begins, and fade over its second.
    tl = timeline("mouth curve -1 in 1s")
    early, late = tl.sample(0.1), tl.sample(1.0)
    assert early.parts.mouth == "sad" and early.fade_from == Parts() and early.fade == pytest.approx(0.1)
    assert late.fade_from is None
    assert np.array_equal(compose(pictures, late), compose(pictures, FaceState(mouth="sad")))


@pytest.mark.parametrize("name", ["sad", "sleep", "happy"])
def test_the_python_api_shows_what_a_script_leaves(name):
    face = Face()
    variant = len(EMOTIONS[name].variants) - 1
    face.set_emotion(name, variant)
    script = timeline(f"{name} variant {variant + 1}")
    end = script.sample(script.duration)
    assert face.state.emotion == name and face.state.parts == end.parts
    assert face.state.expression == end.expression and face.state.eyelids == end.eyelids


def test_the_python_api_keeps_a_wink_through_an_emotion_and_a_blend():
    face = Face()
    face.wink("left")
    face.set_emotion("angry", 0)
    face.blend({"happy": 0.6, "confused": 0.4})
    assert face.state.expression.lid_left == 0.0 and face.state.expression.lid_right == 1.0
    assert face.state.emotion == "happy"
    face.set_mouth("teeth")
    assert face.state.mouth == "teeth" and face.state.expression.lid_left == 0.0
