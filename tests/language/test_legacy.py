"""Every command of the old face node parses, to the AST of its script spelling.

The pairs below are written from the spec's command list
(../shared/spec/seed-behaviour.md), not from the code's tables, so a word
dropped from the code fails here.
"""

from __future__ import annotations

import pytest

from baxterface_cli import parse
from baxterface_cli.language import syntax_tree as n

pytestmark = pytest.mark.language

# (legacy command as typed on the old topic, script spelling, the meaning)
LEGACY = [
    ("default", "default", n.Emotion("default")),
    ("happy", "happy", n.Emotion("happy")),
    ("sad", "sad", n.Emotion("sad")),
    ("angry", "angry", n.Emotion("angry")),
    ("confused", "confused", n.Emotion("confused")),
    ("panic", "panic", n.Emotion("panic")),
    ("bored", "bored", n.Emotion("bored")),
    ("crafty", "crafty", n.Emotion("crafty")),
    ("sleep", "sleep", n.Emotion("sleep")),
    ("wake_up", "wake up", n.Emotion("wake up")),
    ("look_40_-20", "look 40 -20", n.Look(40, -20)),
    ("look_40_-20_0.5", "look 40 -20 in 0.5s", n.Look(40, -20, n.Timing(0.5))),
    ("look_-40_20", "look -40 20", n.Look(-40, 20)),
    ("look_10_0_1.5", "look 10 0 in 1500ms", n.Look(10, 0, n.Timing(1.5))),
    ("look_0_0_0", "look center in 0s", n.Look(0, 0, n.Timing(0.0))),
    ("look_.5_-.5_.25", "look 0.5 -0.5 in 250ms", n.Look(0.5, -0.5, n.Timing(0.25))),
    ("dynamic_look_65_0", "dynamic look left", n.Look(65, 0, dynamic=True)),
    ("dynamic_look_-65_0", "dynamic look right", n.Look(-65, 0, dynamic=True)),
    ("dynamic_look_-10_5_2", "dynamic look -10 5 in 2s", n.Look(-10, 5, n.Timing(2.0), dynamic=True)),
    ("wobble_0.3", "wobble 0.3", n.Wobble(0.3)),
    ("wobble_-0.5", "wobble -0.5rad", n.Wobble(-0.5)),
    ("wobble_2.0", "wobble 2", n.Wobble(2.0)),
    ("wobble_0", "wobble 0deg", n.Wobble(0.0)),
    ("enable", "enable", n.Enable()),
    ("disable", "disable", n.Disable()),
    ("human_follow_on", "follow human", n.Follow("human")),
    ("human_follow_off", "follow off", n.Follow(None)),
    ("dynamic_human_follow_on", "follow human dynamic", n.Follow("human", True)),
    ("left_arm_follow_on", "follow left arm", n.Follow("left arm")),
    ("right_arm_follow_on", "follow right arm", n.Follow("right arm")),
    ("dynamic_left_arm_follow_on", "follow left arm dynamic", n.Follow("left arm", True)),
    ("dynamic_right_arm_follow_on", "follow right arm dynamic", n.Follow("right arm", True)),
    ("arm_follow_off", "follow off", n.Follow(None)),
    ("exit", "exit", n.Exit()),
] + [(f"skin_{i}", f"skin {i}", n.Skin(i)) for i in range(6)]


@pytest.mark.parametrize("legacy, script, meaning", LEGACY, ids=[row[0] for row in LEGACY])
def test_legacy_command_means_its_script_spelling(legacy, script, meaning):
    assert parse(legacy).body == (meaning,)
    assert parse(script).body == (meaning,)


@pytest.mark.parametrize("typed", ["HAPPY", "Look_10_0", "WAKE_UP", "Human_Follow_On", "DYNAMIC_LOOK_1_2_3"])
def test_legacy_commands_ignore_case_like_the_old_node(typed):
    assert parse(typed).body == parse(typed.lower()).body


def test_a_legacy_stream_is_a_script():
    # One command per line, as a user pasting `rostopic pub` payloads would.
    script = parse("wake_up\nlook_40_-20_0.5\nwobble_0.3\nhuman_follow_on\nsleep\n")
    assert [type(s).__name__ for s in script.body] == ["Emotion", "Look", "Wobble", "Follow", "Emotion"]


def test_legacy_positions_point_at_the_numbers():
    from baxterface_cli import ScriptError

    with pytest.raises(ScriptError) as caught:
        parse("look_40_-20_1x")
    assert "look_40_-20_1x" in str(caught.value)  # lexed as a name: not a valid legacy command
    with pytest.raises(ScriptError) as caught:
        parse("skin_9")
    (d,) = caught.value.diagnostics
    assert (d.line, d.column) == (1, 6)
