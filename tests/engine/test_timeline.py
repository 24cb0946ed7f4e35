"""The timeline engine: when things happen and where tracks are, at any time."""

from __future__ import annotations

import math

import pytest

from baxterface_cli import parse
from baxterface_cli.core.face_constants import EMOTIONS
from baxterface_cli.core.face_state import FaceState, Parts
from baxterface_cli.engine import effects as fx
from baxterface_cli.engine.animation import Animation, Idle
from baxterface_cli.engine.compiler import compile_script
from baxterface_cli.engine.effects import Cue


def timeline(text, **options):
    return compile_script(parse(text), **options)


def test_a_linear_look_in_1s_is_halfway_at_half_a_second():
    tl = timeline("look 40 -20 in 1s")
    assert tl.sample(0.5).eye_x == pytest.approx(20)
    assert tl.sample(0.5).eye_y == pytest.approx(-10)
    assert tl.sample(1.0).eye_x == pytest.approx(40)
    assert tl.duration == pytest.approx(1.0)


def test_look_defaults_to_half_a_second_linear():
    tl = timeline("look_40_0")
    assert tl.duration == pytest.approx(0.5)
    assert tl.sample(0.25).eye_x == pytest.approx(20)


def test_easing_shapes_the_move_but_not_its_ends():
    tl = timeline("look 80 0 in 1s ease-in")
    assert tl.sample(0.5).eye_x < 40 and tl.sample(1.0).eye_x == pytest.approx(80)
    tl = timeline("look 80 0 in 1s ease-out")
    assert tl.sample(0.5).eye_x > 40


def test_statements_run_in_sequence():
    tl = timeline("look 40 0 in 1s; wait 1s; look 0 0 in 1s")
    assert tl.sample(1.5).eye_x == pytest.approx(40)  # waiting
    assert tl.sample(2.5).eye_x == pytest.approx(20)
    assert tl.duration == pytest.approx(3.0)


def test_together_runs_children_at_once_and_lasts_as_long_as_the_longest():
    tl = timeline("together { look 40 0 in 1s; wobble 1 in 2s }; look 0 0 in 1s")
    assert tl.sample(0.5).eye_x == pytest.approx(20)
    assert tl.sample(0.5).head_pan == pytest.approx(0.25)
    assert tl.sample(1.5).eye_x == pytest.approx(40)  # the block waits for the wobble
    assert tl.sample(2.5).eye_x == pytest.approx(20)


def test_repeat_and_define_unroll_in_time():
    tl = timeline("define there { look 40 0 in 1s; look 0 0 in 1s }\nrepeat 3 { there }")
    assert tl.duration == pytest.approx(6.0)
    for k in range(3):
        assert tl.sample(2 * k + 1).eye_x == pytest.approx(40)
        assert tl.sample(2 * k + 0.5).eye_x == pytest.approx(20)


def test_a_move_starts_from_wherever_its_track_is():
    tl = timeline("define later { wait 1s; look 0 0 in 1s }\ntogether { look 80 0 in 2s; later }")
    # The second look starts at 1 s, where the first had got to (40), and takes over.
    assert tl.sample(1.0).eye_x == pytest.approx(40)
    assert tl.sample(1.5).eye_x == pytest.approx(20)
    assert tl.sample(2.0).eye_x == pytest.approx(0)


def test_in_a_together_the_later_move_on_one_track_wins():
    tl = timeline("together { look 40 0 in 1s; look -40 0 in 1s }")
    assert tl.sample(1.0).eye_x == pytest.approx(-40)


@pytest.mark.parametrize("name", list(EMOTIONS))
def test_emotions_move_the_lids_first_then_change_the_parts(name):
    spec = EMOTIONS[name]
    start = FaceState(skin=2 if spec.skin != 2 else 0)
    tl = compile_script(parse(name if name != "wake up" else "wake_up"), start=start, crossfade=0)
    before, after = tl.sample(spec.lid_seconds - 0.01), tl.sample(spec.lid_seconds)
    assert before.skin == start.skin and after.skin == spec.skin
    assert after.eyelids == pytest.approx(spec.eyelids)
    assert after.mouth in spec.mouths and after.brows in spec.brows
    assert tl.duration == pytest.approx(spec.lid_seconds)


def test_emotion_lid_times_follow_the_original():
    assert timeline("sleep", crossfade=0.15).duration == pytest.approx(0.6 + 0.15)
    assert timeline("wake up", crossfade=0).duration == pytest.approx(0.8)
    tl = timeline("sleep", crossfade=0)
    assert tl.sample(0.3).eyelids == pytest.approx(0.5)


def test_a_blink_closes_in_0_3s_and_opens_in_0_2s_to_where_the_lids_were():
    tl = timeline("eyelids 0.8 in 0s; blink")
    assert tl.sample(0.15).eyelids == pytest.approx(0.4)
    assert tl.sample(0.3).eyelids == pytest.approx(0.0)
    assert tl.sample(0.4).eyelids == pytest.approx(0.4)
    assert tl.sample(0.5).eyelids == pytest.approx(0.8)
    assert tl.duration == pytest.approx(0.5)


def test_wobble_clamps_to_1_5_radians_and_is_a_robot_effect():
    tl = timeline("wobble_2.0")
    assert tl.sample(tl.duration).head_pan == pytest.approx(1.5)
    (cue,) = tl.cues
    assert cue == Cue(0.0, fx.HeadPan(1.5, speed=1.0, duration=0.5))  # 1.5 rad in 0.5 s: top speed


def test_a_head_pan_carries_the_speed_that_keeps_pace_with_the_script():
    tl = timeline("wobble 0.5 in 2s; wobble -0.5 in 4s; wobble -0.5 in 1s")
    speeds = [c.effect.speed for c in tl.cues]
    assert speeds == pytest.approx([0.25, 0.25, 0.05])  # 0.5 rad in 2 s; 1 rad in 4 s; no move: the floor


def test_dynamic_look_far_away_turns_the_head_and_recentres_the_eyes():
    tl = timeline("dynamic look 80 30 in 1s")
    end = tl.sample(1.0)
    assert end.head_pan == pytest.approx(1.5)  # 3 * 80 / 160
    assert (end.eye_x, end.eye_y) == pytest.approx((0, 30))


def test_dynamic_look_near_the_head_moves_only_the_eyes_by_the_difference():
    tl = timeline("wobble 0.3 in 0s; dynamic look 20 0 in 1s")
    end = tl.sample(tl.duration)
    # 20 px is 0.375 rad; the head is at 0.3, within 0.25: the eyes take the 0.075 rad left.
    assert end.head_pan == pytest.approx(0.3)
    assert end.eye_x == pytest.approx(0.075 * 160 / 3)


def test_crossfades_blend_part_changes_and_can_be_switched_off():
    tl = timeline("mouth teeth", crossfade=0.2)
    mid = tl.sample(0.1)
    assert mid.mouth == "teeth" and mid.fade_from == Parts() and mid.fade == pytest.approx(0.5)
    assert tl.sample(0.2).fade_from is None
    cut = timeline("mouth teeth", crossfade=0).sample(0.0)
    assert cut.mouth == "teeth" and cut.fade_from is None


def test_robot_actions_show_in_the_status():
    tl = timeline("enable; follow human dynamic; wait 1s; follow off; nod; disable")
    assert tl.status(0.5).enabled is True
    assert tl.status(0.5).following == "human" and tl.status(0.5).follow_dynamic
    assert tl.status(1.5).following is None and tl.status(1.5).nodding(1.5)
    assert tl.status(tl.duration).enabled is False


def test_exit_shows_the_sleep_face_and_ends_the_script():
    tl = timeline("happy; exit; sad")
    last = tl.sample(tl.duration)
    assert last.skin == EMOTIONS["sleep"].skin and last.eyelids == 0 and last.fade_from is None
    assert tl.status(tl.duration).exited
    assert all(s.text != "sad" for s in tl.spans)


def test_the_same_seed_picks_the_same_variants_and_seeds_differ():
    text = "happy; angry; bored; crafty; happy; angry; bored; crafty"
    picks = lambda seed: [c.parts for c in timeline(text, seed=seed).parts]  # noqa: E731
    assert picks(1) == picks(1)
    assert len({tuple(picks(seed)) for seed in range(8)}) > 1


def test_sampling_is_pure():
    tl = timeline("happy; look 40 -20 in 0.5s; blink; wobble 0.3")
    times = [i / 30 for i in range(int(tl.duration * 30) + 1)]
    first = [tl.sample(t) for t in times]
    assert [tl.sample(t) for t in reversed(times)] == list(reversed(first))


def test_idle_blinks_every_3_to_8_seconds_but_not_during_script_lid_moves():
    tl = timeline("wait 60s")
    idle = Idle(tl, seed=3)
    gaps = [b - a for a, b in zip(idle.blinks, idle.blinks[1:])]
    assert len(idle.blinks) >= 7 and all(3 <= g <= 8 for g in gaps)
    assert 3 <= idle.blinks[0] <= 8
    animation = Animation(tl, idle=True, seed=3)
    blink = idle.blinks[0]
    assert animation.sample(blink + 0.3).eyelids == pytest.approx(0.0)
    assert animation.sample(blink + 0.5).eyelids == pytest.approx(1.0)

    busy = timeline("repeat 30 { eyelids 0.2 in 1s; eyelids 1 in 1s }")
    assert Idle(busy, seed=3).blinks == []


def test_idle_darts_are_small_and_never_fight_a_look():
    tl = timeline("wait 30s; look 40 0 in 30s")
    idle = Idle(tl, seed=5)
    assert idle.darts
    for dart in idle.darts:
        assert abs(dart.dx) <= 8 and abs(dart.dy) <= 6
        assert dart.end <= 30.0 + 1e-9  # none while the eyes are moving
    asleep = timeline("sleep; wait 60s")
    assert Idle(asleep, seed=5).blinks == []


def test_idle_does_not_change_the_scripts_own_choices():
    text = "happy; wait 10s; angry; wait 10s; bored"
    plain = compile_script(parse(text), seed=4)
    assert [c.parts for c in plain.parts] == [
        c.parts for c in Animation(plain, idle=True, seed=4).timeline.parts
    ]


def test_frame_times_cover_the_end():
    tl = timeline("wait 1s")
    times = tl.frame_times(30)
    assert len(times) == 31 and times[-1] == pytest.approx(1.0)
    assert math.isclose(times[1], 1 / 30)


@pytest.mark.parametrize(
    "text, legacy",
    [
        ("happy", True),
        ("wake_up\nlook_40_-20_0.5\nskin_3\nhuman_follow_on", True),
        ("happy; blink", False),  # blink is new
        ("look 40 -20", False),
        ("mouth teeth", False),
        ("", False),
    ],
)
def test_the_old_nodes_commands_cut_and_scripts_crossfade_by_default(text, legacy):
    script = parse(text)
    assert script.legacy is legacy
    fades = {c.fade for c in compile_script(script).parts}
    assert fades <= ({0.0} if legacy else {0.15})
    assert {c.fade for c in compile_script(script, crossfade=0.3).parts} <= {0.3}


def test_follow_off_recentres_the_eyes():
    tl = timeline("look 40 20 in 0s; follow human; follow off")
    assert tl.sample(0.0).eye_x == pytest.approx(40)
    assert tl.sample(0.5).eye_x == pytest.approx(0) and tl.sample(0.5).eye_y == pytest.approx(0)


def test_every_statement_spans_as_long_as_its_kind_says():
    from baxterface_cli.language.statements import statement_seconds

    for text in (
        "happy",
        "sleep",
        "look left",
        "look 1 2 in 2s",
        "blink",
        "wait 0.7s",
        "wobble 0.3",
        "nod",
        "eyelids 0.5 in 1s",
        "skin 3",
        "enable",
        "follow human",
    ):
        (statement,) = parse(text).body
        (span,) = compile_script(parse(text)).spans
        assert span.end - span.start == pytest.approx(statement_seconds(statement)), text
