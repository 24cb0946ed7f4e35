"""The robot's senses as events (robot/event_sensors.py), on a clock the test gives: a face seen
after 0.2 s found and lost after 0.8 s unseen, a person near the sonar, a navigator's presses, a
cuff's."""

from __future__ import annotations

from baxterface_cli.language import syntax_tree as n
from baxterface_cli.language.events import matches
from baxterface_cli.robot.event_sensors import CuffPresses, FaceSightings, NavigatorPresses, SonarPresence


def kinds(events):
    return [e.kind + (f" {e.arg}" if e.arg else "") for e in events]


def test_a_face_is_seen_once_found_for_0_2_s_and_a_flicker_raises_nothing():
    faces = FaceSightings()
    out = []
    for i in range(10):  # found every other image at 30 a second: never 0.2 s together
        out += faces.reading(i % 2 == 0, i / 30)
    assert out == []
    at = 1.0
    while not out:  # found in every image from 1 s on
        out = faces.reading(True, at)
        at += 1 / 30
    assert kinds(out) == ["face seen"] and abs(at - 1 / 30 - 1.2) < 1 / 30 + 1e-9


def test_a_face_is_lost_after_0_8_s_unseen_even_when_no_image_comes():
    faces = FaceSightings()
    faces.reading(True, 0.0)
    assert kinds(faces.reading(True, 0.25)) == ["face seen"]
    assert faces.reading(False, 0.5) == [] and faces.check(1.0) == []  # 0.75 s unseen: still there
    assert faces.reading(True, 1.0) == []  # found again: the count starts over
    assert faces.check(1.79) == []
    assert kinds(faces.check(1.8)) == ["face lost"]  # the camera stopped giving images
    assert faces.check(5.0) == []  # lost once


def test_the_times_are_settings():
    faces = FaceSightings(seen_after=0.0, lost_after=2.0)
    assert kinds(faces.reading(True, 0.0)) == ["face seen"]
    assert faces.check(1.9) == [] and kinds(faces.check(2.0)) == ["face lost"]


def test_a_person_near_the_front_sonar_and_gone_after_a_second_out_of_reach():
    sonar = SonarPresence(near=1.0)
    assert sonar.reading([0, 5], [1.5, 0.3], 0.0) == []  # sensor 5 looks backwards: not in front
    assert kinds(sonar.reading([10], [0.9], 0.1)) == ["person near"]
    assert sonar.reading([10], [1.1], 0.2) == []  # a little farther: still near (no flicker)
    assert sonar.reading([10], [1.5], 0.5) == []
    assert sonar.check(1.19) == []
    assert kinds(sonar.check(1.2)) == ["person gone"]  # a second since the last reading in reach


def test_a_navigator_press_is_one_event_and_the_wheel_clicks_each_way():
    presses = NavigatorPresses()
    assert kinds(presses.reading("left", [True, False, False], 10)) == ["button left ok"]
    assert presses.reading("left", [True, False, False], 10) == []  # held: no second press
    assert (
        kinds(presses.reading("left", [False, False, True], 12))
        == ["button left down"] + ["button wheel up"] * 2
    )
    presses.reading("right", [], 254)
    assert kinds(presses.reading("right", [], 1)) == ["button wheel up"] * 3  # it wraps at 256
    assert presses.reading("nowhere", [True], None) == []


def test_a_cuff_button_is_an_event_once_a_press_not_while_it_is_held():
    cuffs = CuffPresses()
    assert cuffs.reading("left", "upper_button", False) == []
    assert kinds(cuffs.reading("left", "upper_button", True)) == ["button left_cuff dash"]
    assert cuffs.reading("left", "upper_button", True) == []  # held: Baxter repeats its state
    assert kinds(cuffs.reading("right", "lower_cuff", True)) == ["button right_cuff squeeze"]
    assert cuffs.reading("left", "upper_button", False) == []  # let go
    assert kinds(cuffs.reading("left", "upper_button", True)) == ["button left_cuff dash"]
    assert kinds(cuffs.reading("right", "lower_button", 1)) == ["button right_cuff circle"]
    assert cuffs.reading("torso", "upper_button", True) == []  # no such cuff
    assert cuffs.reading("left", "shoulder_button", True) == []  # an input that is no cuff's button


def test_a_cuff_press_reaches_the_handlers_that_name_it():
    pressed = CuffPresses().reading("right", "upper_button", True)[0]
    assert matches(n.Event("button", "dash"), pressed)  # any cuff's dash
    assert matches(n.Event("button", "right_cuff dash"), pressed)
    assert not matches(n.Event("button", "left_cuff dash"), pressed)
    assert not matches(n.Event("button", "circle"), pressed)
    assert not matches(n.Event("button", "ok"), pressed)  # a navigator's
