"""The docs' Python examples that need rospy: each runs against a real master and does what it says."""

from __future__ import annotations

import signal
import subprocess
import sys

import pytest

from doc_blocks import python_examples

pytestmark = pytest.mark.ros

ROSPY = [e for e in python_examples() if "import rospy" in e.code]


def test_the_rospy_examples_are_found():
    assert any(e.doc == "api.md" for e in ROSPY)


@pytest.mark.parametrize("example", ROSPY, ids=[f"{e.doc}: python {e.number}" for e in ROSPY])
def test_rospy_examples_publish_what_the_docs_say(example, roscore, tmp_path):
    program = tmp_path / "example.py"
    program.write_text(example.code, encoding="utf-8")
    node = subprocess.Popen(
        [sys.executable, str(program)], cwd=str(tmp_path), env=roscore, stderr=subprocess.PIPE, text=True
    )
    try:
        # What the doc tells its reader to check with, waiting for the first frame.
        echo = subprocess.run(
            ["rostopic", "echo", "-n", "1", "--noarr", "/robot/xdisplay"],
            env=roscore,
            capture_output=True,
            text=True,
            timeout=120,
        )
        assert echo.returncode == 0, echo.stderr
        assert 'encoding: "bgr8"' in echo.stdout
        assert "width: 1024" in echo.stdout and "height: 600" in echo.stdout
        assert node.poll() is None  # still glancing
    finally:
        node.send_signal(signal.SIGINT)
        _, errors = node.communicate(timeout=30)
    assert "Traceback" not in errors, errors
