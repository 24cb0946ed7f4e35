"""The two set-up commands install what they say: `make play` what playing needs, `make test` the rest."""

from __future__ import annotations

import re
import subprocess

from conftest import ROOT


def planned_installs(target, tmp_path):
    """The pip installs `make TARGET` would run into a venv that does not exist yet."""
    plan = subprocess.run(
        ["make", "-n", target, f"VENV={tmp_path / 'venv'}", f"VENV38={tmp_path / 'venv38'}"],
        cwd=str(ROOT),
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert plan.returncode == 0, plan.stderr
    return re.findall(r"pip install .*-e '\.\[([a-z0-9,]*)\]'", plan.stdout), plan.stdout


def test_make_play_installs_speech_and_its_sound_but_not_the_tests_tools(tmp_path):
    extras, plan = planned_installs("play", tmp_path)
    assert extras == ["speech"]
    assert "espeak-ng" in plan and "libportaudio2" in plan  # so a script that says something is heard
    assert "baxterface play scripts_examples/show.face" in plan


def test_make_test_installs_every_extra(tmp_path):
    extras, _ = planned_installs("test", tmp_path)
    wanted = {"test", "video", "bag", "speech", "lipsync", "camera", "studio", "voices", "hear"}
    assert any(wanted <= set(line.split(",")) for line in extras), extras


def test_the_ros_environment_hears_with_moonshine_beside_debians_numpy(tmp_path):
    plan = subprocess.run(
        ["make", "-n", "venv-ros", f"VENV_ROS={tmp_path / 'ros'}"],
        cwd=str(ROOT),
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert plan.returncode == 0, plan.stderr
    install = next(line for line in plan.stdout.splitlines() if "pip install" in line)
    assert "hear" in re.findall(r"-e '\.\[([a-z0-9,]*)\]'", install)[0].split(",")
    assert f"-c {tmp_path / 'ros'}/constraints.txt" in install  # Debian's NumPy kept
