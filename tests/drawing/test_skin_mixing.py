"""Skins between the named ones: the palette's mix is the per-pixel mix, to the last bit."""

from __future__ import annotations

import numpy as np
import pytest

from baxterface_cli.drawing.compositing import div255
from baxterface_cli.drawing.skin_mixing import TINTS, SkinPalette, mixed_colour
from baxterface_cli.drawing.theme import Theme


@pytest.fixture(scope="module")
def skins():
    drawn = Theme.default().layers((512, 300)).drawn
    plain = [drawn._plain(i) for i in range(TINTS)]
    cheeky = [drawn.skins[i] for i in range(TINTS + 1)]
    return plain, cheeky, SkinPalette.of(plain, cheeky)


@pytest.mark.parametrize(
    "tint, cheeks, sleepy", [(2.3, 1.0, 0.0), (3.9, 2.5, 0.3), (0.0, 0.0, 1.0), (4.0, 1.0, 0.5)]
)
def test_the_palette_mixes_what_mixing_every_pixel_gives(skins, tint, cheeks, sleepy):
    plain, cheeky, palette = skins
    every_pixel = mixed_colour([s.rgb_a for s in plain], [s.rgb_a for s in cheeky], tint, cheeks, sleepy)
    sprite = palette.sprite(tint, cheeks, sleepy)
    assert np.array_equal(sprite.rgb_a, every_pixel)
    assert np.array_equal(sprite.inv, cheeky[0].inv)
    assert np.array_equal(palette.stacked(tint, cheeks, sleepy), div255(every_pixel).astype(np.uint8))


def test_a_named_skins_numbers_give_that_skin(skins):
    plain, cheeky, palette = skins
    for i in range(TINTS):
        assert np.array_equal(palette.sprite(float(i), 1.0, 0.0).rgb_a, cheeky[i].rgb_a), i
        assert np.array_equal(palette.sprite(float(i), 0.0, 0.0).rgb_a, plain[i].rgb_a), i
    assert np.array_equal(palette.sprite(2.0, 1.0, 1.0).rgb_a, cheeky[5].rgb_a)


def test_few_distinct_pixels_stand_for_the_whole_screen(skins):
    palette = skins[2]
    assert len(palette._plain[0]) < palette.index.size / 20  # a gradient's shades, outlines


def test_skins_of_different_outlines_get_no_palette(skins):
    plain, cheeky, _ = skins
    moved = cheeky[1]._replace(x=cheeky[1].x + 1)
    assert SkinPalette.of(plain, [cheeky[0], moved] + cheeky[2:]) is None
