"""`baxterface check` and the command line as a user meets it."""

from __future__ import annotations

import json
import os

import pytest

from conftest import ROOT, baxterface

pytestmark = pytest.mark.language


def test_a_good_script_is_silent_with_status_0(tmp_path):
    script = tmp_path / "ok.face"
    script.write_text("happy; look 40 -20 in 0.5s; wobble 0.3\n", encoding="utf-8")
    run = baxterface("check", str(script))
    assert (run.code, run.out, run.err) == (0, "", "")


def test_stdin_is_read_for_dash():
    assert baxterface("check", "-", stdin="sleep\nwake_up\n").code == 0
    run = baxterface("check", "-", stdin="hapy\n")
    assert run.code == 1
    assert run.err.startswith("<stdin>:1:1: error: unknown command 'hapy'")


def test_every_file_is_checked_and_any_error_fails(tmp_path):
    good, bad = tmp_path / "good.face", tmp_path / "bad.face"
    good.write_text("blink", encoding="utf-8")
    bad.write_text("blink\nskin 8", encoding="utf-8")
    run = baxterface("check", str(bad), str(good), str(tmp_path / "missing.face"))
    assert run.code == 1
    assert f"{bad}:2:6: error:" in run.err
    assert f"{tmp_path / 'missing.face'}: error: cannot read: No such file or directory" in run.err
    assert str(good) not in run.err


def test_a_directory_is_an_error_not_a_traceback(tmp_path):
    run = baxterface("check", str(tmp_path))
    assert run.code == 1
    assert "error: cannot read" in run.err and "Traceback" not in run.err


def test_binary_garbage_is_one_clear_error(tmp_path):
    junk = tmp_path / "junk.face"
    junk.write_bytes(bytes(range(256)) * 8)
    run = baxterface("check", str(junk))
    assert run.code == 1
    assert "Traceback" not in run.err
    assert run.err.startswith(f"{junk}:")
    # Control characters never reach the terminal raw.
    assert "\x1b" not in run.err and "\x00" not in run.err


def test_nul_bytes_in_utf8_are_reported_not_echoed(tmp_path):
    script = tmp_path / "nul.face"
    script.write_bytes(b"happy\x00\x1b[31m\n")
    run = baxterface("check", str(script))
    assert run.code == 1 and "unexpected character '\\x00'" in run.err
    assert "\x1b" not in run.err


def test_a_huge_file_is_refused_quickly(tmp_path):
    huge = tmp_path / "huge.face"
    huge.write_bytes(b"blink\n" * 2_000_000)  # 12 MB
    run = baxterface("check", str(huge))
    assert run.code == 1
    assert "script is too large" in run.err


def test_ast_is_stable_json():
    run = baxterface("check", "--ast", "-", stdin="happy\nlook_40_-20_0.5\n")
    assert run.code == 0, run.err
    tree = json.loads(run.out)
    assert tree["type"] == "Script"
    assert tree["body"][1] == {
        "type": "Look",
        "x": 40.0,
        "y": -20.0,
        "timing": {"type": "Timing", "duration": 0.5, "easing": "linear"},
        "dynamic": False,
        "line": 2,
        "column": 1,
    }
    # Stable: keys sorted, so the same script prints the same bytes.
    assert run.out == baxterface("check", "--ast", "-", stdin="happy\nlook_40_-20_0.5\n").out
    assert list(tree["body"][1]) == sorted(tree["body"][1])


def test_ast_takes_one_file():
    run = baxterface("check", "--ast", "a.face", "b.face")
    assert run.code == 2 and "exactly one FILE" in run.err


def test_legacy_and_script_spellings_print_the_same_ast_but_positions():
    legacy = json.loads(baxterface("check", "--ast", "-", stdin="look_40_-20_0.5").out)
    script = json.loads(baxterface("check", "--ast", "-", stdin="look 40 -20 in 0.5s").out)
    assert legacy == script


@pytest.mark.parametrize("args", [["--help"], ["check", "--help"], ["-h"]])
def test_help_is_complete(args):
    run = baxterface(*args)
    assert run.code == 0
    assert "Usage: baxterface" in run.out
    if args[0] == "check":
        for word in ("FILE", "--ast", "standard input", "exit status"):
            assert word in run.out
    else:
        assert "check" in run.out and "--install-completion" in run.out


def test_version():
    run = baxterface("--version")
    assert run.code == 0 and run.out.startswith("baxterface ")


def test_no_arguments_shows_help_not_a_traceback():
    run = baxterface()
    assert "Usage: baxterface" in run.out + run.err
    assert "Traceback" not in run.err


@pytest.mark.parametrize(
    "command",
    [["node", "--ros", "1"], ["send", "--ros", "1", "happy"], ["stream", "--ros", "1", "-e", "happy"]],
)
def test_without_ros_the_ros_commands_say_how_to_get_it(command):
    try:
        import rospy  # noqa: F401

        pytest.skip("this Python has ROS; tests/test_ros.py covers it")
    except ImportError:
        pass
    run = baxterface(*command)
    assert run.code == 1 and "Traceback" not in run.err
    if os.path.isdir("/usr/lib/python3/dist-packages/rospy"):  # on the machine, out of this venv's sight
        assert "'make ros' makes .venv-ros" in run.err and ".venv-ros/bin/baxterface" in run.err
    else:
        assert "ROS 1 is not installed" in run.err and "apt-get install" in run.err


COMMANDS = [
    ["render"], ["explain"], ["play"], ["check"], ["node"], ["buttons"], ["send"], ["stream"], ["state"],
    ["studio"], ["screen"], ["voices"], ["gestures"], ["theme", "export"], ["theme", "check"],
]  # fmt: skip


@pytest.mark.parametrize("command", COMMANDS, ids=" ".join)
def test_help_names_what_each_option_takes_not_its_python_type(command):
    run = baxterface(*command, "--help")
    assert run.code == 0 and run.out.startswith(f"Usage: baxterface {' '.join(command)} ")
    for word in ("<str>", "<int>", "<float", "<integer", "INTEGER", "FLOAT", "╭"):
        assert word not in run.out, word


def test_node_help_labels_its_examples_as_examples_and_gives_each_default():
    run = baxterface("node", "--help")
    assert "For example (these are not the defaults)" in " ".join(run.out.split())
    rows = {line.split()[0]: line.strip() for line in run.out.splitlines() if line.startswith("    ")}
    assert rows["size"].endswith("1024x600 (upgraded heads: 1920x1200)")
    assert rows["display_topic"].split(": ")[1].startswith("/robot/xdisplay")
    for name in (
        "fps",
        "theme",
        "idle",
        "selftest",
        "audio",
        "camera",
        "camera_hfov",
        "face_policy",
        "recordings",
    ):
        assert name in rows, name


@pytest.mark.parametrize(
    "command",
    [
        ["render", "-e", "happy", "-o", "x.png"],
        ["stream", "-e", "happy"],
        ["screen"],
        ["theme", "export", "t"],
    ],
)
def test_a_bad_size_is_one_line_naming_the_option(command, tmp_path):
    run = baxterface(*command, "--size", "10x10", cwd=tmp_path)
    assert run.code == 2
    assert run.err.splitlines()[-1] == (
        "Error: Invalid value for '--size': 10x10 is too small: at least 16 pixels a side"
    )


def test_buttons_help_points_to_the_page_that_describes_the_mapping():

    said = " ".join(baxterface("buttons", "--help").out.split())
    assert 'see "The navigator buttons" in docs/following.md' in said
    following = (ROOT / "docs" / "following.md").read_text(encoding="utf-8")
    assert "## The navigator buttons" in following and "buttons.json" in following


@pytest.mark.parametrize(
    "command, option, value",
    [
        (["render", "-e", "happy", "-o", "x.png"], "--at", "inf"),
        (["render", "-e", "happy", "-o", "x.gif"], "--fps", "nan"),
        (["render", "-e", "happy", "-o", "x.gif"], "--crossfade", "nan"),
        (["explain", "-e", "forever { blink; wait 1s }"], "--duration", "nan"),
        (["send", "happy"], "--timeout", "nan"),
    ],
)
def test_a_number_that_is_not_finite_is_one_line_naming_the_option(command, option, value, tmp_path):
    # click reads 'nan' and 'inf' as numbers, and NaN passes a range: --duration nan ran for ever.
    run = baxterface(*command, option, value, cwd=tmp_path)
    assert run.code == 2
    assert run.err.splitlines()[-1] == f"Error: Invalid value for '{option}': {value} is not a finite number."
    assert not list(tmp_path.iterdir())


def test_a_still_says_the_moment_it_shows_of_how_long_a_script(tmp_path):
    # `render --at 2` said the script's length (5.10 s), as if the still were its end.
    out = tmp_path / "at.png"
    run = baxterface("render", str(ROOT / "scripts_examples" / "hello.face"), "--at", "2", "--out", str(out))
    assert run.code == 0 and run.err == f"wrote {out} (1 frame, at 2.00 s of 5.10 s)\n"
    run = baxterface("render", str(ROOT / "scripts_examples" / "hello.face"), "--at", "60", "--out", str(out))
    assert run.err.splitlines()[-1] == f"wrote {out} (1 frame, at 5.10 s of 5.10 s)"  # its last frame
