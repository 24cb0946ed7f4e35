"""Following: the sonar pipeline against the original on generated traces, and arm geometry."""

from __future__ import annotations

import math

import pytest

from baxterface_cli.following import ArmFollower, HumanFollower
from traces import OriginalFollower, jitter, lag, rms_error, run, standing, walks

WALKS = walks()


@pytest.mark.parametrize("name", list(WALKS))
def test_a_walking_person_is_followed_closer_and_sooner_than_by_the_original(name):
    readings = WALKS[name]
    ours, original = run(HumanFollower(), readings), run(OriginalFollower(), readings)
    assert rms_error(ours) < 0.75 * rms_error(original), (rms_error(ours), rms_error(original))
    assert lag(ours) < lag(original), (lag(ours), lag(original))


@pytest.mark.parametrize("seed", [6, 8, 9])
def test_a_still_person_does_not_make_the_eyes_tremble_more_than_the_original(seed):
    readings = standing(seed)
    ours, original = run(HumanFollower(), readings), run(OriginalFollower(), readings)
    assert jitter(ours) <= jitter(original), (jitter(ours), jitter(original))
    assert rms_error(ours, after=5.0) <= rms_error(original, after=5.0) + 1.0


def test_with_no_process_noise_it_stalls_like_the_original():
    readings = WALKS["walk (twice as fast)"]
    stalled = run(HumanFollower(process_noise=0.0, deadband=0.0), readings)
    assert rms_error(stalled) > 2 * rms_error(run(HumanFollower(), readings))


def test_only_front_sensors_near_enough_count():
    follower = HumanFollower()
    assert follower.measure([4, 5, 6, 7, 8], [1.0] * 5) is None  # behind the robot
    assert follower.measure([0, 1], [2.5, 3.0]) is None  # too far
    assert follower.measure([9], [1.0]) == 3.0
    assert follower.measure([3, 9], [1.0, 1.5]) == -3.0  # the further one is outside the 30 % gate


def test_outliers_are_really_removed():
    follower = HumanFollower()
    # Five sensors agree round 1-2; one stray at -3, within the gate.
    z = follower.measure([11, 10, 11, 10, 11, 3], [1.0, 1.05, 1.0, 1.05, 1.02, 1.1])
    assert 1.0 <= z <= 2.0


@pytest.mark.parametrize(
    "ids, distances",
    [
        ([], []),
        ([float("nan")], [1.0]),
        ([0], [float("inf")]),
        ([0], [float("nan")]),
        ([12, -1, 99], [1.0] * 3),
        ([0.5], [1.0]),
        ([0], [-1.0]),
    ],
)
def test_nonsense_readings_see_nobody_and_raise_nothing(ids, distances):
    assert HumanFollower().update(ids, distances) is None


def test_eye_x_stays_within_the_eye_range():
    follower = HumanFollower()
    for _ in range(100):
        x = follower.update([3], [0.8])
    assert x == pytest.approx(-80.0)


arm = ArmFollower()


def test_a_hand_straight_ahead_at_face_height_is_looked_at_straight_on():
    assert arm.eye_target(0.8, 0.0, 0.75) == pytest.approx((0.0, 0.0))


def test_a_hand_to_the_robots_left_is_looked_at_on_the_screens_right():
    x, y = arm.eye_target(0.5, 0.5, 0.75)
    assert x == pytest.approx(45.0, abs=0.01)  # 45 degrees
    assert y == pytest.approx(0.0)


def test_a_hand_above_is_looked_at_upward_and_below_downward():
    assert arm.eye_target(0.6, 0.0, 1.2)[1] < 0
    assert arm.eye_target(0.6, 0.0, 0.2)[1] > 0


@pytest.mark.parametrize("x, y, z", [(0.0, 0.0, 0.75), (0.0, 0.3, 0.75), (0.0, 0.0, 2.0), (1e-12, 0.0, 0.75)])
def test_the_singular_points_do_not_raise(x, y, z):
    ex, ey = arm.eye_target(x, y, z)
    assert math.isfinite(ex) and math.isfinite(ey)
    assert (ex / 80) ** 2 + (ey / 120) ** 2 <= 1 + 1e-9


def test_a_hand_behind_the_robot_is_looked_at_as_if_in_front():
    assert arm.eye_target(-0.5, 0.3, 1.0) == pytest.approx(arm.eye_target(0.5, 0.3, 1.0))


def test_nonsense_positions_are_refused():
    with pytest.raises(ValueError):
        arm.eye_target(float("nan"), 0, 0)
