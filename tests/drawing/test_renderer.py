"""The cached renderer draws exactly what a full recomposite draws, and keeps little."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from baxterface_cli import FaceState, Parts
from baxterface_cli.core.face_constants import BROWS, MOUTHS, SKINS
from baxterface_cli.drawing.renderer import PARTS_KEPT, Renderer
from baxterface_cli.drawing.stacks import compose
from baxterface_cli.drawing.theme import Theme

parts = st.builds(Parts, st.sampled_from(list(SKINS)), st.sampled_from(MOUTHS), st.sampled_from(BROWS))
coordinate = st.one_of(st.floats(-130, 130), st.sampled_from([0.0, 80.0, -80.0, 120.0, 400.0]))
states = st.builds(
    lambda p, x, y, lids, fade_from, fade: FaceState(
        p.skin, p.mouth, p.brows, x, y, lids, 0.0, fade_from, fade if fade_from else 1.0
    ),
    parts,
    coordinate,
    coordinate,
    st.one_of(st.floats(0, 1), st.sampled_from([0.0, 0.4545, 1.0])),
    st.one_of(st.none(), parts),
    st.floats(0, 1),
)


def nearby(state: FaceState) -> st.SearchStrategy:
    """Small moves from a state, as an animation makes them."""
    return st.builds(
        lambda dx, dy, dl: state.replace(
            eye_x=state.eye_x + dx, eye_y=state.eye_y + dy, eyelids=min(1.0, max(0.0, state.eyelids + dl))
        ),
        st.floats(-6, 6),
        st.floats(-6, 6),
        st.floats(-0.1, 0.1),
    )


@st.composite
def animations(draw):
    """A run of states: jumps, part swaps, crossfades and small moves mixed."""
    out = [draw(states)]
    for _ in range(draw(st.integers(1, 12))):
        out.append(draw(st.one_of(states, nearby(out[-1]), nearby(out[-1]))))
    return out


@pytest.fixture(scope="module")
def small_layers():
    return Theme.default().layers((256, 150))


@settings(max_examples=60, deadline=None, suppress_health_check=list(HealthCheck))
@given(animations())
def test_cached_frames_equal_full_recomposites_small(small_layers, run):
    renderer = Renderer(small_layers)
    for state in run:
        assert np.array_equal(renderer.render(state), compose(small_layers, state)), state


@settings(max_examples=8, deadline=None, suppress_health_check=list(HealthCheck))
@given(animations())
def test_cached_frames_equal_full_recomposites_full_size(run):
    layers = Theme.default().layers((1024, 600))
    renderer = Renderer(layers)
    for state in run:
        assert np.array_equal(renderer.render(state), compose(layers, state)), state


@settings(max_examples=40, deadline=None, suppress_health_check=list(HealthCheck))
@given(animations())
def test_changed_says_where_the_frame_changed(small_layers, run):
    renderer = Renderer(small_layers)
    kept = renderer.render(run[0]).copy()
    for state in run[1:]:
        frame = renderer.render(state)
        if renderer.changed is None:
            kept = frame.copy()
        for x0, y0, x1, y1 in renderer.changed or []:
            kept[y0:y1, x0:x1] = frame[y0:y1, x0:x1]
        assert np.array_equal(kept, frame), state


def test_a_blink_redraws_only_inside_the_sockets():
    layers = Theme.default().layers((1024, 600))
    renderer = Renderer(layers)
    before = renderer.render(FaceState()).copy()
    after = renderer.render(FaceState(eyelids=0.0))
    changed = np.argwhere((before != after).any(axis=2))
    (y0, x0), (y1, x1) = changed.min(axis=0), changed.max(axis=0)
    # Both sockets, nothing of the mouth (y > 430) or the screen's edges.
    assert y0 > 100 and y1 < 430 and x0 > 150 and x1 < 875


def test_rendered_frames_are_read_only_views():
    renderer = Renderer(Theme.default().layers((256, 150)))
    frame = renderer.render(FaceState())
    with pytest.raises(ValueError):
        frame[0, 0] = 0


def held_bytes(renderer: Renderer) -> int:
    total = sum(
        c.frame.nbytes + sum(t.prem.nbytes + t.inv.nbytes for t in c.tops)
        for c in renderer._canvases.values()
    )
    total += sum(top.prem.nbytes + top.inv.nbytes for top, _ in renderer._skins.values())
    return total + (renderer._mix.nbytes if renderer._mix is not None else 0)


def test_caches_hold_a_few_dozen_frames_at_most():
    layers = Theme.default().layers((1024, 600))
    renderer = Renderer(layers)
    one_frame = 1024 * 600 * 3
    for i, mouth in enumerate(MOUTHS * 3):
        state = FaceState(skin=i % 6, mouth=mouth, brows=BROWS[i % 5], fade_from=Parts(), fade=0.5)
        renderer.render(state)
    assert len(renderer._canvases) <= PARTS_KEPT
    assert held_bytes(renderer) <= 36 * one_frame, held_bytes(renderer) / one_frame  # three dozen at most
