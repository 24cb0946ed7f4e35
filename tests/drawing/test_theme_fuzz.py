"""Fuzzed theme folders: a clear ThemeError, or a theme that draws a right frame.

Each example is an exported theme with a few things changed: values in
theme.json swapped for JSON of any type, keys removed, the manifest replaced
outright, layer files replaced by other images, bytes or folders, or removed.
"""

from __future__ import annotations

import io
import json
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from PIL import Image

from baxterface_cli import ThemeError
from baxterface_cli.core.face_state import FaceState
from baxterface_cli.drawing import artwork
from baxterface_cli.drawing.renderer import Renderer
from baxterface_cli.drawing.stacks import compose
from baxterface_cli.drawing.theme import Theme

# One worker runs the module, so the base theme is made once, not once a worker.
pytestmark = pytest.mark.xdist_group("theme_fuzz")

SIZE = (48, 28)
FILES = sorted(
    f"{kind}.png" if kind == name else f"{kind}-{name}.png" for kind, name in artwork.layer_names()
)


@pytest.fixture(scope="module")
def base(tmp_path_factory):
    """One exported theme, the start of every example."""
    folder = tmp_path_factory.mktemp("fuzz") / "theme"
    Theme.default().export(folder, SIZE)
    assert sorted(p.name for p in folder.glob("*.png")) == FILES
    return folder


BIG = "<5000 digits>"  # written into the text: json.dumps refuses such ints on Python 3.11+
ODD_NAMES = ["../theme/eyes.png", "/etc/hostname", ".", "", "eyes.png/x", "a\0b", "\ud800", "x" * 300]
SPECIAL = [True, False, None, 0, -1, 15, 16, 48, 28, 8192, 10**6, 2.5, float("nan"), 1e309, BIG, *ODD_NAMES]
scalars = st.one_of(
    st.sampled_from(SPECIAL),
    st.sampled_from(FILES),
    st.integers(-(10**40), 10**40),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=12),
)
json_values = st.recursive(
    scalars,
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=6), inner, max_size=3),
    max_leaves=6,
)
# Mostly no: a rare choice, that shrinks to the common one.
rarely = st.sampled_from([False] * 9 + [True])


def paths_in(value, here=()):
    """Every place in a JSON value, as a tuple of keys and indexes."""
    yield here
    items = value.items() if isinstance(value, dict) else enumerate(value) if isinstance(value, list) else []
    for key, inner in items:
        yield from paths_in(inner, (*here, key))


@st.composite
def manifests(draw, valid):
    """Text for theme.json: the valid manifest changed a little, or a lot."""
    manifest = json.loads(valid)
    for _ in range(draw(st.integers(0, 3))):
        places = [p for p in paths_in(manifest) if p]
        if not places or draw(rarely):
            manifest = draw(json_values)  # the whole manifest, something else
            continue
        layers = manifest.get("layers") if isinstance(manifest, dict) else None
        if draw(st.booleans()) and isinstance(layers, list) and layers:
            # A field the loader reads, whatever it holds now.
            field = draw(st.sampled_from(["size", "lid_travel", "name", "kind", "file", "anchor"]))
            if field in ("kind", "file", "anchor"):
                place = ("layers", draw(st.integers(0, len(layers) - 1)), field)
                if not isinstance(layers[place[1]], dict):
                    continue
            else:
                place = (field,)
        else:
            place = draw(st.sampled_from(places))
        parent = manifest
        for key in place[:-1]:
            parent = parent[key]
        if draw(st.booleans()) or place[-1] not in (
            parent if isinstance(parent, dict) else range(len(parent))
        ):
            parent[place[-1]] = draw(json_values)
        elif isinstance(parent, dict):
            del parent[place[-1]]
        else:
            parent.pop(place[-1])
    text = json.dumps(manifest).replace(json.dumps(BIG), "9" * 5000)
    if draw(rarely):
        text = text[: draw(st.integers(0, len(text)))]  # cut short: not JSON at all
    return text


COLOURS = {
    "RGBA": (200, 10, 10, 128),
    "RGB": (200, 10, 10),
    "LA": (90, 128),
    "L": 90,
    "P": 3,
    "1": 1,
    "I;16": 3000,
}


def png(size, mode="RGBA"):
    data = io.BytesIO()
    Image.new(mode, size, COLOURS[mode]).save(data, "PNG")
    return data.getvalue()


file_changes = st.tuples(
    st.sampled_from(FILES),
    st.one_of(
        st.binary(max_size=64),
        st.builds(png, st.tuples(st.integers(1, 60), st.integers(1, 40))),
        st.builds(png, st.just(SIZE), st.sampled_from(sorted(COLOURS))),
        st.sampled_from(["remove", "folder", "truncate"]),
    ),
)


def apply(folder, name, change):
    path = folder / name
    if isinstance(change, bytes):
        path.write_bytes(change)
    elif change == "remove":
        path.unlink()
    elif change == "folder":
        path.unlink()
        path.mkdir()
    else:
        path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])


# The search is the main suite's; under Python 3.8 (make test runs this there too) a quarter as many
# show that damaged themes fail clearly there as well.
EXAMPLES = 150 if sys.version_info >= (3, 9) else 40


@settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=list(HealthCheck))
@given(data=st.data(), changes=st.lists(file_changes, max_size=2))
def test_a_damaged_theme_fails_clearly_or_draws_right(base, data, changes):
    manifest = data.draw(manifests((base / "theme.json").read_text()), label="theme.json")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp) / "theme"
        shutil.copytree(base, folder)
        (folder / "theme.json").write_text(manifest)
        for name, change in changes:
            if (folder / name).is_file():
                apply(folder, name, change)
        try:
            theme = Theme.load(folder)
            layers = theme.layers(SIZE)
        except ThemeError as e:
            message = str(e)
            assert message.startswith(str(folder)) and "\n" not in message and len(message) < 400
            return
        state = FaceState(skin=3, mouth="teeth", brows="angry", eye_x=30, eye_y=-20, eyelids=0.6)
        frame = Renderer(layers).render(state)
        assert frame.shape == (SIZE[1], SIZE[0], 3) and frame.dtype == np.uint8
        assert np.array_equal(frame, compose(layers, state))
