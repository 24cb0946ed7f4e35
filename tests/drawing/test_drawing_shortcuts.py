"""The drawing's short ways, held to the plain ones they stand for, to the last bit."""

from __future__ import annotations

import numpy as np
import pytest

from baxterface_cli.core.expression import Expression
from baxterface_cli.drawing.artwork import brows_window, draw_brows_numbers
from baxterface_cli.drawing.drawn_parts import _BROWS, STEPS, DrawnBrowsKey, DrawnParts, _drawn_sprite
from baxterface_cli.drawing.vector_shapes import Canvas, _straight, ellipse


def plain_straight(rgba: np.ndarray) -> np.ndarray:
    alpha = rgba[..., 3:4]
    rgb = np.where(alpha > 0, rgba[..., :3] / np.maximum(alpha, 1e-6), 0.0)
    return np.clip(np.concatenate([rgb, alpha], axis=2) * 255.0 + 0.5, 0, 255).astype(np.uint8)


def test_straight_alpha_is_the_plain_division():
    canvas = Canvas((300, 200))
    canvas.shape(ellipse(500, 300, 200, 120), (290, 170, 710, 430), (200, 40, 90))
    canvas.shape(ellipse(560, 280, 90, 200), (460, 70, 660, 490), (20, 160, 230), opacity=0.6)
    assert np.array_equal(_straight(canvas.rgba), plain_straight(canvas.rgba))


def test_a_first_shape_over_nothing_is_laid_as_any_other():
    """The first shape takes one pass; laid by the general step over the zeros it is the same."""
    quick, plain = Canvas((400, 240)), Canvas((400, 240))
    plain._blank = False  # the general step, over a layer of zeros
    for canvas in (quick, plain):
        canvas.shape(ellipse(500, 300, 150, 100), (340, 190, 660, 410), (30, 60, 90), opacity=0.8)
        canvas.shape(ellipse(540, 320, 150, 100), (380, 210, 700, 430), (250, 220, 10))
    assert np.array_equal(quick.rgba, plain.rgba)


@pytest.mark.parametrize("size", [(1024, 600), (800, 480), (1920, 1200)])
@pytest.mark.parametrize("seed", range(4))
def test_brows_drawn_from_their_coverage_are_the_brows_drawn_in_floats(size, seed):
    numbers = tuple(int(n) for n in np.random.default_rng(seed).integers(-STEPS, STEPS, len(_BROWS)))
    parts = DrawnParts(size, {}, {}, {})
    quick = parts._brows(DrawnBrowsKey(numbers))
    e = Expression()._replace(**{f: n / STEPS for f, n in zip(_BROWS, numbers)})
    plain = _drawn_sprite(size, brows_window(e), lambda c: draw_brows_numbers(c, e))
    assert (quick.x, quick.y) == (plain.x, plain.y)
    assert np.array_equal(quick.rgb_a, plain.rgb_a) and np.array_equal(quick.inv, plain.inv)
