"""The navigator buttons: one press, one command; toggles; the wheel; the mapping file."""

from __future__ import annotations

import json

import pytest

from baxterface_cli.robot.navigator_buttons import ButtonMap, Buttons, MappingError

UP, DOWN, OK, NONE = [False, True, False], [False, False, True], [True, False, False], [False, False, False]


def test_a_held_button_sends_once():
    b = Buttons(ButtonMap.load())
    assert b.update("left", UP) == ["wake_up"]
    assert b.update("left", UP) == [] and b.update("left", UP) == []
    assert b.update("left", NONE) == []
    assert b.update("left", UP) == ["wake_up"]


def test_the_spec_mapping():
    b = Buttons(ButtonMap.load())
    assert b.update("torso_left", OK) == ["enable"]
    b.update("torso_left", NONE)
    assert b.update("torso_left", OK) == ["disable"]  # it toggles
    assert b.update("left", DOWN) == ["sleep"]
    assert b.update("right", UP) == ["dynamic_left_arm_follow_on"]
    b.update("right", NONE)
    assert b.update("right", UP) == ["arm_follow_off"]
    assert b.update("right", DOWN) == ["dynamic_right_arm_follow_on"]


def test_the_wheel_scrolls_emotions_while_awake_and_wraps():
    b = Buttons(ButtonMap.load())
    assert b.update("left", NONE, wheel=250) == []  # the first reading only sets where it is
    assert b.update("left", NONE, wheel=251) == []  # asleep: nothing
    b.update("left", UP)  # wake up
    assert b.update("left", UP, wheel=252) == ["happy"]
    assert b.update("left", UP, wheel=2) == ["sad"]  # 252 -> 2 wraps forward, not back
    assert b.update("left", UP, wheel=1) == ["happy"]
    assert b.update("right", NONE, wheel=9) == []  # not the wheel that scrolls


def test_a_users_mapping_and_its_errors(tmp_path):
    mine = tmp_path / "mine.json"
    mine.write_text(json.dumps({"buttons": {"right.ok": "look left in 0.3s"}}), encoding="utf-8")
    assert Buttons(ButtonMap.load(mine)).update("right", OK) == ["look left in 0.3s"]
    for body, message in [
        ({"buttons": {"head.ok": "happy"}}, "unknown button 'head.ok'"),
        ({"buttons": {"left.ok": "hapy"}}, "did you mean 'happy'"),
        ({"buttons": {"left.ok": 3}}, "must be a command"),
    ]:
        mine.write_text(json.dumps(body), encoding="utf-8")
        with pytest.raises(MappingError, match=message):
            ButtonMap.load(mine)
    mine.write_text("{", encoding="utf-8")
    with pytest.raises(MappingError, match="not valid JSON"):
        ButtonMap.load(mine)


def test_a_cuff_button_is_a_key_of_its_own_once_a_press(tmp_path):
    mine = tmp_path / "cuffs.json"
    mapping = {"buttons": {"left_cuff.dash": ["happy", "sad"], "right_cuff.squeeze": "wake_up"}}
    mine.write_text(json.dumps(mapping), encoding="utf-8")
    b = Buttons(ButtonMap.load(mine))
    assert b.cuff("left", "upper_button", True) == ["happy"]  # upper_button: the dash
    assert b.cuff("left", "upper_button", True) == []  # held
    assert b.cuff("left", "upper_button", False) == []
    assert b.cuff("left", "upper_button", True) == ["sad"]  # a toggle, as a navigator's
    assert b.cuff("right", "lower_cuff", True) == ["wake_up"] and b.awake
    assert b.cuff("left", "lower_button", True) == []  # the circle: not mapped
    for key in ("left_cuff.ok", "torso_left.dash", "left_cuf.dash"):
        mine.write_text(json.dumps({"buttons": {key: "happy"}}), encoding="utf-8")
        with pytest.raises(MappingError, match=f"unknown button '{key}'; use NAVIGATOR.BUTTON or CUFF"):
            ButtonMap.load(mine)
