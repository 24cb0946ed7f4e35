"""The default theme fitted to a screen, kept between runs: a face started again draws the same
frames without reading its pictures."""

from __future__ import annotations

import os

import numpy as np
import pytest

from baxterface_cli.core.face_state import FaceState
from baxterface_cli.drawing import array_cache, layer_store, theme_manifest
from baxterface_cli.drawing import theme as theme_module
from baxterface_cli.drawing.renderer import Renderer
from baxterface_cli.drawing.theme import Theme
from baxterface_cli.drawing.theme_fitting import prepare_layers
from baxterface_cli.resources import resource

SIZE = (320, 188)


def fresh_default() -> Theme:
    """The default theme as a new process finds it (the process keeps the one it made)."""
    theme_module._default_theme.cache_clear()
    return Theme.default()


def frame(layers, **state) -> np.ndarray:
    return Renderer(layers).render(FaceState(**state)).copy()


def cannot_read(*args, **kwargs):
    raise AssertionError("a picture of the theme was read")


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    yield tmp_path / "baxterface" / "themes"
    theme_module._default_theme.cache_clear()


def test_a_face_started_again_draws_the_same_without_reading_its_pictures(cache, monkeypatch):
    first = fresh_default().layers(SIZE)
    assert [p.name.split("-")[1] for p in cache.glob("*.npz")] == ["320x188"]
    monkeypatch.setattr(theme_manifest, "read_image", cannot_read)
    monkeypatch.setattr(theme_module, "read_image", cannot_read)
    again = fresh_default().layers(SIZE)
    angry = {"skin": 4, "mouth": "sad", "brows": "angry", "eye_x": 30.0, "eyelids": 0.4}
    for state in ({}, angry, {"skin": 5}):
        assert np.array_equal(frame(again, **state), frame(first, **state))


def test_the_kept_layers_are_the_fitted_ones_sprite_for_sprite(cache):
    theme = Theme.load(resource("assets/default"))  # read from its pictures, drawn at SIZE
    theme.builtin = True
    made = prepare_layers(theme.placed_at(SIZE), SIZE, theme.lid_travel)
    kept = fresh_default().layers(SIZE)  # kept now, then loaded back below
    kept = fresh_default().layers(SIZE)
    assert (kept.size, kept.scale, kept.lid_travel, kept.lid_bands) == (
        made.size,
        made.scale,
        made.lid_travel,
        made.lid_bands,
    )
    assert np.array_equal(kept.background, made.background)
    pairs = list(zip(kept.eyes + kept.lids, made.eyes + made.lids))
    for kind in ("skins", "mouths", "brows"):
        ours, theirs = getattr(kept, kind), getattr(made, kind)
        assert sorted(ours) == sorted(theirs)
        pairs += [(ours[name], theirs[name]) for name in theirs]
    for a, b in pairs:
        assert (a.x, a.y) == (b.x, b.y)
        assert np.array_equal(a.rgb_a, b.rgb_a) and np.array_equal(a.inv, b.inv)
        assert a.inv.dtype == b.inv.dtype and a.rgb_a.dtype == b.rgb_a.dtype


def test_a_damaged_kept_theme_is_made_again_and_only_the_last_versions_used_are_kept(cache):
    first = frame(fresh_default().layers(SIZE), mouth="smile-open", brows="raised")
    (kept,) = cache.glob("*.npz")
    kept.write_bytes(kept.read_bytes()[:5000])  # cut short, as by a full disk
    others = [kept.with_name(f"default-320x188-{k:020d}.npz") for k in range(3)]
    for age, other in enumerate(others):  # older baxterfaces', or another numpy's, used in turn
        other.write_bytes(b"another version's")
        os.utime(other, (1000 + age, 1000 + age))
    assert np.array_equal(frame(fresh_default().layers(SIZE), mouth="smile-open", brows="raised"), first)
    assert kept.stat().st_size > 5000
    assert sorted(cache.glob("*.npz")) == sorted([kept, *others[1:]])  # the least lately used is gone


def test_two_environments_used_in_turn_each_find_their_theme_kept(cache, monkeypatch):
    """The node in ROS's Python, `play` in another with another numpy: a fingerprint each. Keeping
    one, each remade the theme the other had just replaced (a second's work at the node's start)."""
    made = []

    def counted(folder, name, size, make, *rest):
        return array_cache.kept(folder, name, size, lambda: made.append(name) or make(), *rest)

    monkeypatch.setattr(layer_store, "kept", counted)
    for environment in ("ros", "play", "ros", "play"):
        monkeypatch.setattr(array_cache, "fingerprint", lambda e=environment: f"{e:0>20}")
        fresh_default().layers(SIZE)
    assert len(made) == 2 and len(list(cache.glob("*.npz"))) == 2


def test_where_nothing_can_be_kept_the_theme_is_still_fitted(tmp_path, monkeypatch):
    blocked = tmp_path / "a-file"
    blocked.write_text("")
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocked))  # no folder can be made under a file
    try:
        assert frame(fresh_default().layers(SIZE), mouth="sad").shape == (SIZE[1], SIZE[0], 3)
    finally:
        theme_module._default_theme.cache_clear()
