"""The speech mouths (visemes): drawn in the default theme, optional in others."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest

from baxterface_cli import Face, parse
from baxterface_cli.core.face_constants import MOUTHS, VISEMES, viseme_mouth
from baxterface_cli.core.face_state import FaceState, Parts
from baxterface_cli.drawing import artwork, mouth_drawing
from baxterface_cli.drawing.renderer import Renderer
from baxterface_cli.drawing.stacks import compose
from baxterface_cli.drawing.theme import OPTIONAL, Theme
from baxterface_cli.language.diagnostics import ScriptError
from conftest import baxterface

# One worker runs the module, so the exported theme is made once, not once a worker.
pytestmark = pytest.mark.xdist_group("speech_mouths")

SIZE = (256, 150)
SPEECH = [viseme_mouth(shape) for shape in VISEMES]


def layer(name):
    """A mouth layer of the committed default theme, as an (h, w, 4) array."""
    return np.asarray(Theme.default().images[("mouth", name)].image)


def dark_inside(name):
    """Pixels of a mouth layer that show the mouth's dark inside."""
    rgba = layer(name).astype(int)
    near = np.abs(rgba[..., :3] - np.array(mouth_drawing.MOUTH_INSIDE)).max(axis=2) < 40
    return int((near & (rgba[..., 3] > 200)).sum())


def test_the_default_theme_has_every_speech_mouth_and_each_is_its_own():
    theme = Theme.default()
    assert theme.stand_ins == {}
    assert [name for kind, name in artwork.layer_names() if name.startswith("speak-")] == SPEECH
    shown = {name: layer(name) for name in SPEECH + list(MOUTHS)}
    for name in SPEECH:
        assert shown[name][..., 3].any(), name
        for other, image in shown.items():
            assert other == name or not np.array_equal(shown[name], image), (name, other)


def test_openness_shows_as_the_dark_inside():
    area = {shape: dark_inside(viseme_mouth(shape)) for shape in VISEMES}
    assert area["closed"] == 0
    assert 0 < area["slight"] < min(area["fv"], area["lth"])
    assert max(area["fv"], area["lth"]) < min(area["wide"], area["round"])
    assert max(area["wide"], area["round"]) < area["open"]


def test_the_speech_mouths_sit_where_the_emotions_mouths_do():
    """So that a crossfade between the two looks like one mouth moving."""

    def box(name):
        ys, xs = np.nonzero(layer(name)[..., 3] > 128)
        return xs.min(), ys.min(), xs.max(), ys.max()

    x0, y0, x1, y1 = box("smile-open")
    for name in SPEECH:
        a0, b0, a1, b1 = box(name)
        assert abs((a0 + a1) / 2 - (x0 + x1) / 2) <= 1, name  # centred
        assert y0 - 20 <= b0 and b1 <= y1 + 40 and a0 >= x0 - 10 and a1 <= x1 + 10, name


def test_the_default_theme_draws_them_at_any_size():
    for size in [(1024, 600), SIZE]:
        mouths = Theme.default().layers(size).mouths
        for shape, fallback in VISEMES.items():
            assert mouths[viseme_mouth(shape)] is not mouths[fallback]
        frames = [compose(Theme.default().layers(size), FaceState(mouth=name)) for name in SPEECH]
        assert all(not np.array_equal(frames[0], f) for f in frames[1:])


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    folder = tmp_path_factory.mktemp("speech") / "full"
    Theme.default().export(folder, SIZE)
    return folder


def without_speech(exported, folder, keep=()):
    """An exported theme from before the speech mouths: their layers and files gone."""
    shutil.copytree(exported, folder)
    manifest = json.loads((folder / "theme.json").read_text())
    gone = [e for e in manifest["layers"] if e["name"].startswith("speak-") and e["name"] not in keep]
    assert len(gone) == len(VISEMES) - len(keep)
    for entry in gone:
        manifest["layers"].remove(entry)
        (folder / entry["file"]).unlink()
    (folder / "theme.json").write_text(json.dumps(manifest))
    return folder


def test_a_theme_without_them_shows_the_tables_mouth_instead(exported, tmp_path):
    folder = without_speech(exported, tmp_path / "old")
    theme = Theme.load(folder)
    assert theme.stand_ins == OPTIONAL
    layers = theme.layers(SIZE)
    renderer = Renderer(layers)
    for shape, fallback in VISEMES.items():
        for brows, skin in [("normal", 2), ("angry", 4)]:
            spoken = FaceState(skin=skin, mouth=viseme_mouth(shape), brows=brows, eye_x=20)
            instead = FaceState(skin=skin, mouth=fallback, brows=brows, eye_x=20)
            drawn = renderer.render(spoken).copy()
            assert np.array_equal(drawn, renderer.render(instead)), shape
            assert np.array_equal(compose(layers, spoken), compose(layers, instead)), shape
    # Crossfading into and out of speech works too, and at another size.
    fading = FaceState(mouth="speak-open", fade_from=Parts(2, "speak-closed", "normal"), fade=0.5)
    assert np.array_equal(renderer.render(fading), compose(layers, fading))
    bigger = theme.layers((512, 300))
    assert bigger.mouths["speak-wide"] is bigger.mouths["teeth"]


def test_a_theme_may_have_some_of_them(exported, tmp_path):
    folder = without_speech(exported, tmp_path / "some", keep=("speak-open",))
    theme = Theme.load(folder)
    mouths = theme.layers(SIZE).mouths
    assert ("mouth", "speak-open") not in theme.stand_ins
    assert mouths["speak-open"] is not mouths["smile-open"]
    assert mouths["speak-round"] is mouths["smile-open"]  # the table's mouth, not speak-open


def test_a_theme_without_them_checks_silently_and_exports_as_it_is(exported, tmp_path):
    folder = without_speech(exported, tmp_path / "old")
    run = baxterface("theme", "check", str(folder))
    assert run.code == 0 and run.out == "" and run.err == "", run.err
    Theme.load(folder).export(tmp_path / "again")
    assert not list((tmp_path / "again").glob("*speak*"))
    assert Face(theme=tmp_path / "again", size=SIZE).frame().shape == (SIZE[1], SIZE[0], 3)


def test_a_broken_speech_mouth_is_an_error_like_any_layer(exported, tmp_path):
    folder = tmp_path / "broken"
    shutil.copytree(exported, folder)
    (folder / "mouth-speak-round.png").unlink()
    run = baxterface("theme", "check", str(folder))
    assert run.code == 1 and "mouth-speak-round.png: missing (named in theme.json)" in run.err


def test_scripts_cannot_name_a_speech_mouth():
    """They come with speech; `mouth` takes the emotions' mouths only."""
    with pytest.raises(ScriptError, match="unknown mouth 'speak-open'"):
        parse("mouth speak-open")
    with pytest.raises(ValueError, match="unknown mouth"):
        Face(size=SIZE).set_mouth("speak-open")
