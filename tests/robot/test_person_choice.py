"""Which face the eyes follow among several: the three policies, their hysteresis, confirmation."""

from __future__ import annotations

import pytest

from baxterface_cli.robot.haar_detector import Box
from baxterface_cli.robot.person_choice import FACE_POLICIES, Person, PersonChoice, check_face_policy

W, H = 640, 400


def person(x, y, size, first=0.0, sure=True):
    p = Person(Box(x, y, size), first=first, seen=first, checked=first)
    p.sure = sure
    return p


def test_each_policy_chooses_its_face_among_three():
    early = person(500, 250, 30, first=0.0)  # seen first, off the middle, small
    near = person(150, 170, 46, first=0.6)  # the largest: the nearest person
    middle = person(330, 200, 32, first=0.6)  # the most central
    chosen = {
        policy: PersonChoice(policy).choose([early, near, middle], 1.0, W, H) for policy in FACE_POLICIES
    }
    assert chosen == {"nearest": near, "central": middle, "longest": early}


def test_a_clearly_nearer_face_takes_over_after_a_tenth_of_a_second_and_a_little_nearer_one_never():
    choice = PersonChoice("nearest")
    first, other = person(200, 200, 40), person(450, 200, 44)  # 1.21 times the area: not clearly
    assert choice.choose([first], 0.0, W, H) is first
    for k in range(30):
        assert choice.choose([first, other], k / 30, W, H) is first
    nearer = person(450, 200, 46)  # 1.32 times the area
    at = [choice.choose([first, nearer], 1.0 + k / 30, W, H) for k in range(6)]
    assert at[:3] == [first] * 3 and at[3:] == [nearer] * 3  # after 0.1 s, for good


def test_a_rival_that_is_clearly_better_only_now_and_then_never_takes_over():
    choice = PersonChoice("nearest")
    first, big, small = person(200, 200, 40), person(450, 200, 50), person(450, 200, 41)
    choice.choose([first], 0.0, W, H)
    for k in range(60):  # clearly nearer in every other image: never for a tenth of a second
        assert choice.choose([first, big if k % 3 == 0 else small], k / 30, W, H) is first


def test_central_switches_when_another_is_nearer_the_middle_by_more_than_a_face():
    choice = PersonChoice("central")
    followed, other = person(250, 200, 30), person(380, 200, 30)  # 70 and 60 px off the middle
    assert choice.choose([followed, other], 0.0, W, H) is other
    choice = PersonChoice("central")
    assert choice.choose([followed], 0.0, W, H) is followed
    for k in range(1, 10):
        assert choice.choose([followed, other], k / 30, W, H) is followed  # 10 px: not a face's width
    centre = person(325, 205, 30)
    assert [choice.choose([followed, centre], 1 + k / 30, W, H) for k in range(4)][-1] is centre


def test_longest_keeps_the_face_while_it_is_seen_then_takes_the_next_oldest():
    choice = PersonChoice("longest")
    old, newer, newest = (
        person(100, 200, 24, first=0.0),
        person(300, 200, 60, first=1.0),
        person(500, 200, 40, 2),
    )
    assert choice.choose([old, newer, newest], 3.0, W, H) is old
    assert choice.choose([newer, newest], 4.0, W, H) is newer  # the old one gone


def test_only_confirmed_faces_are_followed_and_a_better_one_about_to_be_is_waited_for():
    choice = PersonChoice("nearest")
    small, large = person(200, 200, 30), person(450, 200, 60, first=0.0, sure=False)
    assert choice.choose([small, large], 0.1, W, H) is None  # the larger may be confirmed soon
    assert choice.choose([small, large], 0.35, W, H) is small  # it was not: take what there is
    large.sure = True
    choice = PersonChoice("nearest")
    assert choice.choose([small, large], 0.4, W, H) is large


def test_a_face_is_confirmed_by_two_strict_checks_passed_at_least_as_often_as_failed():
    p = person(0, 0, 30, sure=False)  # passed once when found
    p.checked_now(True, False, 0.1)
    p.checked_now(True, False, 0.2)
    assert not p.confirmed and not p.doubtful  # one pass, two fails
    p.checked_now(True, True, 0.3)
    assert p.confirmed  # two passes, two fails
    p.checked_now(False, False, 0.4)
    assert p.confirmed and p.checked == 0.3  # confirmed for good; not found: not checked since
    q = person(0, 0, 30, sure=False)
    q.checks, q.fails = 0, 1
    for k in range(3):
        q.checked_now(True, False, k)
    assert q.doubtful and not q.confirmed


def test_a_policy_that_does_not_exist_is_a_value_error_naming_the_three():
    assert check_face_policy("central") == "central"
    with pytest.raises(ValueError, match="nearest, central or longest, not 'tallest'"):
        PersonChoice("tallest")
