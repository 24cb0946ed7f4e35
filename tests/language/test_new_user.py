"""What a new user tripped on: variants, mistyped sides, a length at the limit, a mild anger."""

from __future__ import annotations

import numpy as np
import pytest

from baxterface_cli import ScriptError, parse
from baxterface_cli.core.face_constants import EMOTIONS
from baxterface_cli.core.presets import DEFAULT_FACE
from baxterface_cli.drawing.stacks import compose
from baxterface_cli.drawing.theme import Theme
from baxterface_cli.engine.compiler import compile_script
from baxterface_cli.language import syntax_tree as n
from baxterface_cli.language.statements import describe
from tests.conftest import baxterface

pytestmark = pytest.mark.language


def errors(text):
    with pytest.raises(ScriptError) as caught:
        parse(text, "t.face")
    return [(d.line, d.column, d.message) for d in caught.value.errors]


def end_of(text, seed=0):
    timeline = compile_script(parse(text), seed=seed)
    return timeline.sample(timeline.duration)


# -- variants


@pytest.mark.parametrize("seed", range(6))
def test_the_readmes_morph_ends_in_a_frown_whatever_the_seed(seed):
    face = end_of("sad in 1.5s", seed)
    assert face.expression.mouth_curve == pytest.approx(-1.0)
    assert face.mouth == "sad"


@pytest.mark.parametrize("seed", range(3))
def test_a_script_chooses_an_emotions_variant(seed):
    for i, (mouth, brows) in enumerate(EMOTIONS["angry"].variants, start=1):
        for text in (f"angry variant {i}", f"angry variant {i} in 1s", f"angry 1 variant {i} in 1s"):
            face = end_of(text, seed)
            assert (face.mouth, face.brows) == (mouth, brows), text


def test_a_variant_is_written_before_or_after_the_intensity_and_kept_in_the_tree():
    assert parse("sad variant 2").body == (n.Emotion("sad", variant=2),)
    blend = parse("happy variant 3 0.4 + confused 0.2 variant 2 in 1s").body[0]
    assert blend == parse("happy 0.4 variant 3 + confused variant 2 0.2 in 1s").body[0]
    assert blend.variants == (3, 2)
    assert describe(blend) == "happy variant 3 0.4 + confused variant 2 0.2 in 1s"
    assert n.to_json(parse("sad").body[0]) == {"type": "Emotion", "name": "sad", "line": 1, "column": 1}
    assert n.to_json(parse("sad variant 2").body[0])["variant"] == 2


@pytest.mark.parametrize(
    "text, where, message",
    [
        ("sad variant 3", (1, 13), "'sad' has variants 1 and 2, not 3"),
        ("happy variant 0", (1, 15), "'happy' has variants 1 to 4, not 0"),
        ("happy variant 1.5", (1, 15), "'happy' has variants 1 to 4, not 1.5"),
        ("wake_up variant 2", (1, 17), "'wake_up' has only variant 1, not 2"),
        ("sad variant 1 0.5 variant 2", (1, 27), "an emotion takes one 'variant'"),
        ("sad varient 2", (1, 5), "did you mean 'variant'?"),
    ],
)
def test_a_wrong_variant_says_which_there_are(text, where, message):
    found = errors(text)
    assert found and found[0][:2] == where and message in found[0][2]


# -- sides


@pytest.mark.parametrize(
    "text, column, message",
    [
        ("brows lft raised", 7, "unknown side 'lft'; did you mean 'left'?"),
        ("brows rigth angle 0.5", 7, "unknown side 'rigth'; did you mean 'right'?"),
        ("eyelids lft angle 0.5", 9, "unknown side 'lft'; did you mean 'left'?"),
        ("eyelids lft 0.5", 9, "did you mean 'left'?"),
        ("brows both raised", 7, "'both' is not a side: leave the side out for both brows"),
        ("brows xyzzy raised", 7, "use 'left' or 'right', or no side for both brows"),
    ],
)
def test_a_mistyped_side_gets_a_did_you_mean(text, column, message):
    found = errors(text)
    assert found[0][:2] == (1, column) and message in found[0][2]


def test_sides_spelled_right_still_parse():
    assert parse("brows left raised").body == (n.Brows("raised", "left"),)
    assert parse("eyelids right angle 0.5").body[0].side == "right"


# -- the hour


def test_a_script_of_exactly_an_hour_passes_and_one_a_millisecond_over_says_by_how_much():
    parse("repeat 6000 { wink left }")  # 6000 x 0.6 s, a hair over 3600 in floating point
    parse("wait 3600s")
    assert errors("sad in 3600.001s") == [(1, 1, "the script runs 1 hour 0.001 s; the limit is 1 hour")]
    assert errors("repeat 6001 { wink left }")[0][2] == "the script runs 1 hour 0.6 s; the limit is 1 hour"
    assert "runs 1 hour 1 minute;" in errors("wait 3660s")[0][2]


def test_check_accepts_the_hour_and_refuses_past_it():
    assert baxterface("check", "-", stdin="repeat 6000 { wink left }").code == 0
    run = baxterface("check", "-", stdin="sad in 3600.001s")
    assert run.code == 1 and "runs 1 hour 0.001 s;" in run.err


# -- a mild anger


def dip(frame):
    """How far below its sides, 70 pixels either way, the mouth's lowest ink is at its middle:
    12 face pixels for the default's smile, 0 or less for a flat or downturned mouth."""

    def lowest(x):
        return 380 + np.flatnonzero(frame[380:560, x].astype(int).max(axis=1) < 90).max()

    return lowest(512) - max(lowest(512 - 70), lowest(512 + 70))


@pytest.mark.parametrize("variant", [1, 2, 3, 4])
def test_a_little_anger_does_not_smile(variant):
    layers = Theme.default().layers((1024, 600))
    assert dip(compose(layers, end_of("default"))) > 8
    for amount in (0.3, 0.5):
        face = end_of(f"angry {amount} variant {variant}")
        assert face.expression.mouth_curve <= 0.0, amount
        assert dip(compose(layers, face)) <= 1, amount
    assert DEFAULT_FACE.mouth_curve == 1.0
