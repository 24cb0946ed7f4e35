"""FaceState.replace: a state changed in its look is the state built again with the change."""

from __future__ import annotations

import dataclasses

import pytest

from baxterface_cli import FaceState, Parts
from baxterface_cli.core.expression import Expression

STATES = [
    FaceState(),
    FaceState(mouth="teeth", brows="angry", eye_x=12.0, eyelids=0.4),
    FaceState(2, "smile", "normal", fade_from=Parts(4, "angry", "angry"), fade=0.3),
    FaceState(expression=Expression(mouth_curve=-0.5), emotion="sad", mood=(0.2, -0.4)),
]
CHANGES = [
    {"eye_x": -40.0, "eye_y": 25.5},
    {"eyelids": 0.0},
    {"head_pan": 0.7, "mood": (0.5, 0.5), "emotion": "happy"},
    {"mouth": "sad"},  # a part: worked out again
]


@pytest.mark.parametrize("state", STATES)
@pytest.mark.parametrize("changes", CHANGES)
def test_replace_gives_the_state_built_again(state, changes):
    fast, built = state.replace(**changes), dataclasses.replace(state, **changes)
    assert fast == built and hash(fast) == hash(built) and vars(fast) == vars(built)
    with pytest.raises(dataclasses.FrozenInstanceError):
        fast.eye_x = 1.0
