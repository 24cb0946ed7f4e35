"""Robot effects: typed values that every consumer handles through one interface."""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import subprocess
import sys

import numpy as np
import pytest

import baxterface_cli
from baxterface_cli import parse
from baxterface_cli.core.geometry import dynamic_look, to_pixels
from baxterface_cli.engine import effects as fx
from baxterface_cli.engine.compiler import compile_script
from baxterface_cli.engine.effects import EffectHandler, EffectWords, StatusFold
from baxterface_cli.ros.effect_messages import COMMAND_TYPES, ros_commands
from baxterface_cli.speech.synthesis import Phoneme, Utterance, Word
from conftest import ROOT, baxterface

# Half a second of a made-up "Hi", built by hand: effects need no speech engine.
HI = Utterance(
    text="Hi",
    voice="en",
    rate=175,
    samples=np.zeros(11025, np.int16),
    sample_rate=22050,
    phonemes=(Phoneme(0.0, 0.2, "h"), Phoneme(0.2, 0.5, "aI")),
    words=(Word(0.0, "Hi"),),
)

ONE_OF_EACH = [
    fx.HeadPan(0.3, speed=0.6, duration=0.5),
    fx.HeadNod(),
    fx.SetEnabled(True),
    fx.SetFollowing("left arm", dynamic=True),
    fx.ShutDown(),
    fx.Speech(HI),
]


def handlers():
    """Every EffectHandler the package defines, found by importing all of it that imports without ROS."""
    for module in pkgutil.walk_packages(baxterface_cli.__path__, "baxterface_cli."):
        if module.name.endswith(("ros.node", "ros.send", "ros.buttons", "__main__")):
            continue  # these import rospy at the top; their handlers are the core's
        importlib.import_module(module.name)
    found, todo = [], [EffectHandler]
    while todo:
        for sub in todo.pop().__subclasses__():
            todo.append(sub)
            if sub.__module__.startswith("baxterface_cli."):
                found.append(sub)
    return found


def test_the_test_sees_every_kind_of_effect_and_consumer():
    assert {type(e) for e in ONE_OF_EACH} == set(fx.EFFECTS)
    names = {cls.__name__ for cls in handlers()}
    assert {"StatusFold", "EffectWords", "Robot", "_ToRos"} <= names


@pytest.mark.parametrize("handler", handlers(), ids=lambda c: c.__name__)
def test_every_consumer_handles_every_effect(handler):
    # An abstract method left over is an effect this consumer does not handle.
    assert not inspect.getattr_static(handler, "__abstractmethods__"), handler.__abstractmethods__


def test_each_effect_reaches_its_own_method():
    class Recorder(EffectHandler):
        def head_pan(self, effect, at):
            return "head_pan"

        def head_nod(self, effect, at):
            return "head_nod"

        def set_enabled(self, effect, at):
            return "set_enabled"

        def follow(self, effect, at):
            return "follow"

        def exit(self, effect, at):
            return "exit"

        def speech(self, effect, at):
            return "speech"

    assert [e.visit(Recorder(), 0.0) for e in ONE_OF_EACH] == [
        "head_pan",
        "head_nod",
        "set_enabled",
        "follow",
        "exit",
        "speech",
    ]


def test_a_consumer_missing_a_method_cannot_be_made():
    class Forgetful(EffectHandler):
        def head_pan(self, effect, at): ...

    with pytest.raises(TypeError):
        Forgetful()


def test_effects_in_words():
    words = [e.visit(EffectWords(), 0.0) for e in ONE_OF_EACH]
    assert words == [
        "head pan to +0.30 rad (+17.2 deg) over 0.5 s (speed 0.60 rad/s)",
        "nod",
        "enable",
        "follow left arm dynamic",
        "exit: the face node shuts down",
        'say "Hi" (0.50 s, voice en, 175 words a minute)',
    ]


def test_the_status_folds_effects_in_time_order():
    fold = StatusFold()
    for at, effect in enumerate(ONE_OF_EACH):
        effect.visit(fold, float(at))
    status = fold.status
    assert (status.enabled, status.following, status.follow_dynamic, status.exited) == (
        True,
        "left arm",
        True,
        True,
    )
    assert status.nodding(1.5) and not status.nodding(2.0)  # nodded at 1 s, for 1 s
    assert (status.speaking(5.4), status.speaking(5.5)) == ("Hi", None)  # said at 5 s, for 0.5 s


def test_one_mapping_from_effects_to_ros_messages():
    pan, nod, enable, follow, leave, say = (ros_commands(e) for e in ONE_OF_EACH)
    (command,) = pan
    assert command.topic == "/robot/head/command_head_pan"
    assert command.fields == {"target": 0.3, "speed_ratio": 0.6, "enable_pan_request": 1}
    assert nod == [("/robot/head/command_head_nod", {"data": True})]
    assert enable == [("/robot/set_super_enable", {"data": True})]
    assert ros_commands(fx.SetEnabled(False))[0].fields == {"data": False}
    assert follow == [] and leave == []
    # sound_play says the text itself: a bag replayed later cannot name a sound file of ours.
    sound = {"sound": -3, "command": 1, "volume": 1.0, "arg": "Hi", "arg2": ""}
    assert say == [("/robotsound", sound)]
    assert {c.topic for e in ONE_OF_EACH for c in ros_commands(e)} == set(COMMAND_TYPES)


def test_every_statement_for_the_robot_explains_without_error():
    run = baxterface(
        "explain",
        "-",
        stdin='nod; enable; disable; follow human dynamic; follow off; wobble 3; say "Hi"; exit',
    )
    assert run.code == 0, run.err
    robot = [line.split("robot ", 1)[1] for line in run.out.splitlines() if " robot " in line]
    said = robot.pop(-2)  # how long "Hi" takes is espeak-ng's to say
    assert said.startswith('say "Hi" (') and said.endswith(" s, voice en, 175 words a minute)")
    assert robot == [
        "nod",
        "enable",
        "disable",
        "follow human dynamic",
        "follow off",
        "head pan to +1.50 rad (+85.9 deg) over 0.5 s (speed 1.00 rad/s)",
        "exit: the face node shuts down",
    ]


def test_explain_tells_one_story_in_time_order_and_angles_in_degrees_too():
    script = "wake up; happy; wobble 20deg in 1s; nod; look left in 0.5s; sad"
    run = baxterface("explain", "-e", script)
    assert run.code == 0, run.err
    rows = run.out.splitlines()[1:]
    times = [float(row.split()[0]) for row in rows]
    assert times == sorted(times), run.out
    kinds = [row.split("s ", 1)[1].split()[0] for row in rows]
    assert kinds == ["line", "face", "line", "face", "line", "robot", "line", "robot", "line", "line", "face"]
    assert "wobble 0.35 rad (20 deg) in 1s" in run.out
    assert "robot head pan to +0.35 rad (+20 deg) over 1 s (speed 0.35 rad/s)" in run.out
    grouped = baxterface("explain", "--grouped", "-e", script).out.splitlines()[1:]
    assert sorted(grouped) == sorted(rows)  # the same lines, each kind together
    in_groups = sorted(kinds, key=["line", "face", "robot"].index)
    assert [row.split("s ", 1)[1].split()[0] for row in grouped] == in_groups


def test_the_dynamic_look_rule_is_one_rule_for_scripts_and_following():
    # Beyond the pan limit the head stops at 1.5 rad and the eyes take the rest.
    pan, eye_x = dynamic_look(1.7, 0.0)
    assert (pan, eye_x) == (1.5, pytest.approx(to_pixels(0.2)))
    script = compile_script(parse("dynamic look 90.666 0 in 0s"))  # 90.666 px = 1.7 rad
    end = script.sample(script.duration)
    assert (end.head_pan, end.eye_x) == (1.5, pytest.approx(eye_x, abs=0.05))
    # Within the eyes' reach the head stays where it is.
    assert dynamic_look(0.2, 0.0) == (None, pytest.approx(to_pixels(0.2)))


def test_compiling_a_script_loads_no_drawing_code():
    code = (
        "import sys; from baxterface_cli import parse; "
        "from baxterface_cli.engine.compiler import compile_script; "
        "compile_script(parse(open('scripts_examples/show.face').read())); "
        "print(sorted(m for m in sys.modules if m in ('baxterface_cli.drawing.renderer', "
        "'baxterface_cli.drawing.face', 'baxterface_cli.drawing.theme', 'numpy', 'PIL')))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], cwd=str(ROOT), capture_output=True, text=True, check=True
    )
    assert out.stdout.strip() == "[]"
