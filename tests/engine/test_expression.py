"""The continuous face on the timeline: intensity, blends, morphs, mood, winks and controls."""

from __future__ import annotations

import pytest

from baxterface_cli import parse
from baxterface_cli.core.expression import Expression
from baxterface_cli.core.face_constants import EMOTIONS
from baxterface_cli.core.face_state import FaceState, Parts
from baxterface_cli.core.presets import (
    DEFAULT_FACE,
    MOOD_CIRCLE,
    blend,
    emotion_preset,
    from_parts,
    mood_weights,
    nearest_parts,
    speech_mouth,
)
from baxterface_cli.engine.compiler import compile_script
from baxterface_cli.language import syntax_tree as n


def timeline(text, **options):
    return compile_script(parse(text), **options)


def close(a: Expression, b: Expression, tolerance: float = 1e-6) -> bool:
    return all(abs(x - y) <= tolerance for x, y in zip(a, b))


def variants(name):
    """Each way an emotion may look (the compiler picks one of its variants)."""
    return [emotion_preset(name, i) for i in range(len(EMOTIONS[name].variants))]


def test_full_and_no_intensity_are_the_emotion_and_the_default_face():
    assert parse("happy 1") == parse("happy")
    assert parse("happy 100%") == parse("happy")
    assert parse("sad 0") == parse("default")


@pytest.mark.parametrize("seed", range(4))
def test_intensity_goes_part_of_the_way_from_the_default_face(seed):
    end = timeline("sad 0.4", seed=seed).sample(10.0)
    sad = emotion_preset("sad", 1)  # the frown: sad's usual variant, whatever the seed
    assert close(end.expression, blend([(sad, 0.4)]))
    mild = blend([(sad, 0.4)])
    for field in ("mouth_width", "brow_left_angle", "tint"):
        linear = 0.6 * getattr(DEFAULT_FACE, field) + 0.4 * getattr(sad, field)
        assert getattr(mild, field) == pytest.approx(linear)
    # ...but for the mouth's curve, which leaves the smile faster: a milder frown, not a smile.
    assert sad.mouth_curve < mild.mouth_curve < 0.0
    assert end.emotion == "sad"


def test_a_blend_adds_each_emotion_at_its_weight():
    end = timeline("happy 0.6 + confused 0.4").sample(10.0).expression
    assert any(
        close(end, blend([(h, 0.6), (c, 0.4)])) for h in variants("happy") for c in variants("confused")
    )
    assert 0 < end.mouth_skew < emotion_preset("confused").mouth_skew  # some of confused's wave


def test_a_timed_emotion_morphs_through_the_shapes_between():
    tl = timeline("sad in 1.5s ease-in-out", seed=1)
    start = from_parts(FaceState().parts)
    (sad,) = [v for v in variants("sad") if close(tl.sample(1.5).expression, v)]
    middle = tl.sample(0.75).expression
    # ease-in-out is halfway at half time: every number is halfway, the mouth half bent.
    assert close(middle, start.mix(sad, 0.5))
    assert middle.mouth_curve == pytest.approx((start.mouth_curve + sad.mouth_curve) / 2)
    assert close(tl.sample(1.5).expression, sad)
    assert tl.duration == pytest.approx(1.5)


def test_an_untimed_intensity_morphs_at_once_over_its_lids_time():
    tl = timeline("sleep 0.5")
    lids = EMOTIONS["sleep"]
    assert tl.sample(lids.lid_seconds).eyelids == pytest.approx(1 - 0.5 * (1 - lids.eyelids))
    start, end = from_parts(FaceState().parts), tl.sample(lids.lid_seconds).expression
    # Linear, lids and face together: halfway at half the lids' time, where `sleep` alone waits.
    assert close(tl.sample(lids.lid_seconds / 2).expression, start.mix(end, 0.5))
    assert tl.sample(lids.lid_seconds / 2).eyelids == pytest.approx(1 - 0.25 * (1 - lids.eyelids))
    assert close(timeline("sleep").sample(lids.lid_seconds - 0.01).expression, start)


@pytest.mark.parametrize("name, angle", MOOD_CIRCLE)
def test_a_mood_on_the_circle_at_full_strength_is_its_emotion(name, angle):
    import math

    valence, arousal = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    weights = dict(mood_weights(valence, arousal))
    assert weights[name] == pytest.approx(1.0)


def test_a_mood_grows_stronger_toward_the_edge_and_is_the_neutral_face_at_the_centre():
    weak = timeline("mood 0.3 0 in 1s").sample(1.0).expression
    strong = timeline("mood 1 0 in 1s").sample(1.0).expression
    assert 0 < weak.mouth_open < strong.mouth_open  # pleasant: a smile opening toward happy's
    assert close(timeline("happy; mood 0 0 in 1s").sample(5.0).expression, DEFAULT_FACE)
    asleep = timeline("mood 0 -1 in 2s").sample(2.0)
    assert asleep.eyelids == pytest.approx(0.0) and asleep.expression.sleepy == pytest.approx(1.0)


def test_wink_shuts_one_eye_and_opens_it_again():
    tl = timeline("wink left")
    shut = min(
        (tl.sample(i / 100).expression for i in range(int(tl.duration * 100) + 1)), key=lambda e: e.lid_left
    )
    assert shut.lid_left == 0.0 and shut.lid_right == 1.0
    assert tl.sample(tl.duration).expression.lid_left == 1.0
    assert parse("wink right").body[0] == n.Wink("right")


def test_controls_of_different_parts_move_together():
    tl = timeline("together { mouth curve -1 in 1s; brows height 1 in 1s; brows left angle -0.5 in 1s }")
    end = tl.sample(1.0).expression
    assert end.mouth_curve == -1.0 and end.brow_left_height == 1.0 and end.brow_right_height == 1.0
    assert end.brow_left_angle == -0.5 and end.brow_right_angle == 0.0
    assert tl.sample(0.5).expression.mouth_curve == pytest.approx(0.0)  # from the smile's 1


def test_a_named_part_keeps_the_other_parts_numbers():
    end = timeline("brows height 0.8 in 0.1s; mouth sad").sample(5.0).expression
    assert end.brow_left_height == 0.8  # the mouth's change leaves the brows' control alone
    assert end.mouth_curve == from_parts(Parts(mouth="sad")).mouth_curve


def test_one_brow_by_name_moves_that_side_only():
    end = timeline("brows left raised").sample(5.0).expression
    raised = from_parts(Parts(brows="raised"))
    assert end.brow_left_height == raised.brow_left_height
    assert end.brow_right_height == 0.0


def test_themes_of_pictures_get_the_nearest_named_parts():
    for variant in (1, 4):
        near = timeline(f"happy 0.9 variant {variant}", seed=1).sample(5.0).parts
        assert near == timeline(f"happy variant {variant}", seed=1).sample(5.0).parts
    assert timeline("happy 0.1").sample(5.0).parts == FaceState().parts
    assert nearest_parts(emotion_preset("angry", 3)) == Parts(4, "sad", "angry")


def test_speech_moves_the_drawn_mouth_through_its_shapes(monkeypatch):
    import numpy as np

    from baxterface_cli.speech.synthesis import Utterance
    from baxterface_cli.speech.visemes import MouthKey

    utterance = Utterance("mama", "en", 175, np.zeros(22050, np.int16), 22050, (), ())
    keys = (
        MouthKey(0.1, "closed", 0.0),
        MouthKey(0.3, "open", 0.04),
        MouthKey(0.5, "wide", 0.0),  # a near shape: a cut in a theme of pictures
        MouthKey(0.55, "closed", 0.0),
        MouthKey(0.6, "rest", 0.0),
    )
    monkeypatch.setattr("baxterface_cli.speech.natural_voices.mouth_track", lambda u, *rules: keys)
    tl = timeline('happy; say "mama"', speak=lambda text, voice, rate: utterance)
    start = tl.speech[0].at
    face = tl.sample(start + 0.2).expression
    assert close(face, speech_mouth(face, "closed"))  # the closed lips of p, b, m
    between = tl.sample(start + 0.32).expression  # halfway through the 40 ms tween to "open"
    assert (
        speech_mouth(face, "closed").mouth_open < between.mouth_open < speech_mouth(face, "open").mouth_open
    )
    assert tl.sample(start + 0.7).expression.mouth_curve == tl.sample(start - 0.01).expression.mouth_curve
    # Drawn from numbers, the mouth moves into a near shape too (coarticulation)...
    into_wide = tl.sample(start + 0.51).expression
    assert (
        speech_mouth(face, "wide").mouth_open < into_wide.mouth_open < speech_mouth(face, "open").mouth_open
    )
    assert tl.sample(start + 0.51).mouth == "speak-wide"  # where a picture theme cuts
    # ...but the lips of p, b and m shut at once.
    assert close(tl.sample(start + 0.551).expression, speech_mouth(face, "closed"))


def idle_life(text: str, seconds: float = 120.0):
    from baxterface_cli.engine.animation import Idle

    tl = timeline(text + "; wait 200s")
    return Idle(tl, seed=3, until=seconds)


def test_arousal_quickens_the_blinks_and_calm_slows_them():
    calm, usual, alert = (len(idle_life(f"mood 0 {a} in 0.1s").blinks) for a in (-1, 0, 1))
    assert calm < usual < alert
    assert len(idle_life("happy").blinks) == usual  # an emotion alone leaves the pace as it was


def test_a_low_valence_now_and_then_looks_down_and_away():
    downcast = [d for d in idle_life("mood -1 0 in 0.1s").darts if d.dy >= 40]
    assert downcast and all(abs(d.dx) >= 15 for d in downcast)
    assert not [d for d in idle_life("mood 1 0 in 0.1s").darts if d.dy >= 40]


def test_the_mood_carries_into_the_next_script():
    end = timeline("mood -0.5 0.8 in 0.2s").sample(1.0)
    assert end.mood == (-0.5, 0.8)
    assert compile_script(parse("blink"), start=end).mood_at(0.5) == (-0.5, 0.8)
