"""The integer compositing every frame is made with, held to plain floating-point alpha blending."""

from __future__ import annotations

import numpy as np
import pytest

from baxterface_cli.drawing.compositing import (
    div255,
    div255_inplace,
    finish,
    lay,
    split_columns,
    sprite_from_rgba,
)


def test_div255_is_round_x_over_255_for_every_value_it_meets():
    x = np.arange(255 * 255 + 1, dtype=np.uint16)
    expected = np.floor(x / 255 + 0.5).astype(np.uint16)
    assert np.array_equal(div255(x), expected)
    y = x.copy()
    div255_inplace(y)
    assert np.array_equal(y, expected)


def over(dst_bgr: np.ndarray, rgba: np.ndarray, x: int, y: int) -> np.ndarray:
    """The reference: straight alpha over, in floating point, rounded at the end."""
    out = dst_bgr.astype(float).copy()
    h, w = rgba.shape[:2]
    y0, x0 = max(0, y), max(0, x)
    y1, x1 = min(out.shape[0], y + h), min(out.shape[1], x + w)
    if y0 >= y1 or x0 >= x1:  # off the screen
        return dst_bgr.copy()
    src = rgba[y0 - y : y1 - y, x0 - x : x1 - x].astype(float)
    a = src[..., 3:4] / 255
    out[y0:y1, x0:x1] = src[..., 2::-1] * a + out[y0:y1, x0:x1] * (1 - a)
    return np.floor(out + 0.5).astype(np.uint8)


@pytest.mark.parametrize("dx, dy", [(0, 0), (5, -3), (-12, 0), (24, 15), (30, 22)])  # in, over edges, off
def test_laying_a_sprite_matches_alpha_blending_to_within_one_level(dx, dy):
    rng = np.random.default_rng(abs(dx * 100 + dy))
    background = rng.integers(0, 256, (24, 32, 3), dtype=np.uint8)
    layer = np.zeros((20, 16, 4), np.uint8)
    layer[3:17, 2:14] = rng.integers(0, 256, (14, 12, 4), dtype=np.uint8)
    sprite = sprite_from_rgba(layer, x=4, y=2)
    assert (sprite.x, sprite.y, sprite.width, sprite.height) == (6, 5, 12, 14)  # cropped to what it draws
    dst = background.astype(np.uint16)
    lay(dst, (0, 0, 32, 24), sprite, dx, dy)
    expected = over(background, layer, 4 + dx, 2 + dy)
    assert np.abs(dst.astype(int) - expected.astype(int)).max() <= 1


def test_a_layer_with_nothing_drawn_is_no_sprite():
    assert sprite_from_rgba(np.zeros((8, 8, 4), np.uint8)) is None


def test_a_sprite_splits_at_its_empty_columns_into_tight_boxes():
    rgba = np.zeros((10, 20, 4), np.uint8)
    rgba[2:4, 1:5] = (255, 0, 0, 255)  # a left eye
    rgba[5:9, 12:18] = (0, 0, 255, 128)  # a right eye
    left, right = split_columns(sprite_from_rgba(rgba))
    assert (left.x, left.y, left.width, left.height) == (1, 2, 4, 2)
    assert (right.x, right.y, right.width, right.height) == (12, 5, 6, 4)


def test_finish_lays_the_premultiplied_top_over_the_opaque_bottom():
    under = np.full((2, 2, 3), 200, np.uint16)
    prem = np.full((2, 2, 3), 100 * 128 // 255, np.uint16)  # colour 100 at alpha 128, premultiplied
    inv = np.full((2, 2, 3), 255 - 128, np.uint16)
    out = finish(prem, inv, under)
    assert out.dtype == np.uint8
    assert np.abs(out.astype(int) - round(100 * 128 / 255 + 200 * 127 / 255)).max() <= 1
