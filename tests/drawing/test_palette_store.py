"""Palettes kept between runs: a face started again mixes the same skins without making them."""

from __future__ import annotations

import numpy as np
import pytest

from baxterface_cli.drawing import drawn_parts, eye_sizes
from baxterface_cli.drawing.theme import Theme
from baxterface_cli.resources import resource

SIZE = (256, 150)
MOOD = (1.3, 0.4, 0.2)  # tint, cheeks, sleepiness: a skin between the named ones


def mixes():
    """The whole skin and an eye of another size, as a mood mixes them, by a face of its own
    (as a new process has: the default theme keeps the faces it fitted)."""
    theme = Theme.load(resource("assets/default"))
    theme.builtin = True
    drawn = theme.layers(SIZE).drawn
    return drawn.palette().sprite(*MOOD), drawn.eye_sizes.cut(1, 1.1, MOOD)


def same(a, b):
    (skin_a, (rect_a, *eye_a)), (skin_b, (rect_b, *eye_b)) = a, b
    return (
        np.array_equal(skin_a.rgb_a, skin_b.rgb_a)
        and np.array_equal(skin_a.inv, skin_b.inv)
        and rect_a == rect_b
        and all(np.array_equal(x, y) for x, y in zip(eye_a, eye_b))
    )


def cannot_draw(*args, **kwargs):
    raise AssertionError("a kept palette was drawn again")


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    return tmp_path / "baxterface" / "palettes"


def test_a_face_started_again_loads_its_palettes_and_mixes_the_same(cache, monkeypatch):
    first = mixes()
    assert sorted(p.name.split("-")[0] for p in cache.glob("*.npz")) == ["eye1", "skin"]
    monkeypatch.setattr(drawn_parts, "draw_skin", cannot_draw)
    monkeypatch.setattr(eye_sizes, "draw_skin", cannot_draw)
    assert same(mixes(), first)


def test_a_damaged_palette_is_made_again_and_another_versions_is_kept_beside_it(cache):
    first = mixes()
    skin = next(cache.glob("skin-*.npz"))
    skin.write_bytes(skin.read_bytes()[:1000])  # cut short, as by a full disk
    eye = next(cache.glob("eye1-*.npz"))
    stale = eye.with_name("eye1-256x150-0123456789abcdef0123.npz")
    eye.rename(stale)  # as another environment's baxterface left it (another numpy)
    assert same(mixes(), first)
    assert skin.stat().st_size > 1000  # written whole again
    assert eye.exists() and stale.exists()  # the last three versions used are kept (array_cache)


def test_where_nothing_can_be_kept_the_palettes_are_still_made(tmp_path, monkeypatch):
    blocked = tmp_path / "a-file"
    blocked.write_text("")
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocked))  # no folder can be made under a file
    skin, (rect, colour, clear) = mixes()
    assert skin.rgb_a.shape[:2] == (SIZE[1], SIZE[0]) and colour.shape == clear.shape
