"""The language documentation tells the truth: its examples and its table parse."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pexpect
import pytest

from baxterface_cli import parse
from baxterface_cli.language.vocabulary import BARE_WORDS, LEGACY_USAGE
from conftest import free_port
from doc_blocks import DOCS, fenced_blocks, python_examples

pytestmark = pytest.mark.one_python  # what the docs say is the same under every Python

ROOT = Path(__file__).resolve().parent.parent
DOC = (ROOT / "docs" / "language.md").read_text(encoding="utf-8")
README = (ROOT / "README.md").read_text(encoding="utf-8")


# Untagged blocks are face scripts; console, python and text blocks are not.
SCRIPT_BLOCKS = [block.body for block in fenced_blocks(DOC) + fenced_blocks(README) if block.tag == ""]
LEGACY_ROWS = re.findall(r"^\| `([a-z0-9_.-]+)` \| `([^`]+)` \|$", DOC, re.M)


@pytest.mark.parametrize("block", SCRIPT_BLOCKS, ids=[f"block{i}" for i in range(len(SCRIPT_BLOCKS))])
def test_every_script_example_parses(block):
    parse(block)


def test_the_legacy_table_is_right_and_complete():
    assert len(LEGACY_ROWS) >= 27
    for legacy, script in LEGACY_ROWS:
        assert parse(legacy).body == parse(script).body, legacy
    documented = {legacy for legacy, _ in LEGACY_ROWS}
    for word in BARE_WORDS:
        if "_" in word:
            assert word in documented
    for command in LEGACY_USAGE:
        assert any(row.startswith(command + "_") for row in documented), command


# -- console examples: each command runs, and prints what the docs show ----

# Commands these examples leave to other tests: `make` is the set-up that CI
# itself runs; ROS commands run against a real master in tests/test_ros.py.
ELSEWHERE = (
    "make ",
    "baxterface node",
    "baxterface send",
    "baxterface stream",
    "baxterface state --ros",
    "rostopic ",
    "roslaunch ",
)


def console_examples(paths=DOCS):
    """(doc, command, expected output lines) for every `$ ` line of every console block."""
    out = []
    for path in paths:
        for block in fenced_blocks(path.read_text(encoding="utf-8")):
            if block.tag != "console":
                continue
            for line in block.body.splitlines():
                if line.startswith("$ "):
                    command = re.sub(r"\s{2,}#.*$", "", line[2:]).strip()
                    out.append([path.name, command, []])
                elif out:
                    out[-1][2].append(line.rstrip())
    return [tuple(example) for example in out]


def matches(expected, actual):
    """Do the lines match? A line of '...' stands for any number of lines, and a line
    ending in ' ...' for any line that starts like it (a time, say, that varies)."""
    if not expected:
        return not actual
    if expected[0].strip() == "...":
        return any(matches(expected[1:], actual[i:]) for i in range(len(actual) + 1))
    if not actual:
        return False
    head = expected[0]
    same = actual[0].startswith(head[:-3]) if head.endswith(" ...") else head == actual[0]
    return same and matches(expected[1:], actual[1:])


def runs_elsewhere(command):
    """Is this (after any VAR=value settings) a command another test runs?"""
    for part in command.split(" | "):  # `printf ... | baxterface send --stdin` is a ROS example too
        words = part.split()
        while words and re.fullmatch(r"[A-Z_]+=\S*", words[0]):
            words = words[1:]
        if " ".join(words).startswith(ELSEWHERE):
            return True
    return False


LOCAL = [e for e in console_examples() if not runs_elsewhere(e[1])]


@pytest.fixture
def doc_folder(tmp_path):
    """A folder like the reader's: the example scripts, beside and under scripts_examples/, and assets/."""
    (tmp_path / "scripts_examples").mkdir()
    (tmp_path / "assets").mkdir()  # the theme-drawing script writes beside itself, so here
    shutil.copy(ROOT / "assets" / "draw_default_theme.py", tmp_path / "assets")
    for pattern in ("*.face", "*.jsonl", "*.jpg", "*.ogg", "*.wav"):  # scripts, what they follow, say, hear
        for script in (ROOT / "scripts_examples").glob(pattern):
            shutil.copy(script, tmp_path / script.name)
            shutil.copy(script, tmp_path / "scripts_examples" / script.name)
    return tmp_path


@pytest.mark.parametrize("doc, command, expected", LOCAL, ids=[f"{e[0]}: {e[1]}" for e in LOCAL])
def test_console_examples_print_what_the_docs_show(doc, command, expected, doc_folder):
    for earlier_doc, earlier, _ in LOCAL:  # an example may use what one before it made
        if (earlier_doc, earlier) == (doc, command):
            break
        if earlier_doc == doc and "export" in earlier:
            subprocess.run(earlier, shell=True, cwd=str(doc_folder), env=doc_env(), capture_output=True)
    if command.startswith("baxterface theme check broken"):
        break_a_theme(doc_folder / "broken")
    if command.startswith(("baxterface studio", "baxterface screen")):
        return studio_example(command, expected, doc_folder)
    if command.startswith(("curl ", "baxterface state --url")) and re.search(r":808[01]/", command):
        return curl_example(command, expected, doc_folder)
    if command.startswith("baxterface play"):
        child = pexpect.spawn("bash", ["-c", command], cwd=str(doc_folder), env=doc_env(), timeout=60)
        child.expect(pexpect.EOF)
        child.close()
        assert child.exitstatus == 0 and b"played" in child.before
        return
    run = subprocess.run(
        command, shell=True, cwd=str(doc_folder), env=doc_env(), capture_output=True, text=True, timeout=120
    )
    assert run.returncode == (
        1 if "error" in "\n".join(expected) or "baxterface:" in "".join(expected) else 0
    )
    printed = (run.stdout + run.stderr).rstrip("\n")
    assert matches(expected, printed.splitlines() if printed else []), printed


def studio_example(command, expected, folder):
    """A studio (or a screen) serves until Ctrl-C: it prints what the docs show (on a free port),
    then stops."""
    port = str(free_port())
    served = command.split()[1]
    child = pexpect.spawn(
        "bash",
        ["-c", command.replace("--no-browser", f"--no-browser --port {port}")],
        cwd=str(folder),
        env=doc_env(),
        timeout=60,
        encoding="utf-8",
    )
    for line in expected:
        child.expect_exact(re.sub(r":808[01]/", f":{port}/", line))
    child.sendintr()
    child.expect(pexpect.EOF)
    child.close()
    assert child.exitstatus == 130 and f"baxterface {served}: stopped" in child.before


def curl_example(command, expected, folder):
    """The API examples, against a studio on show.face at a free port in place of 8080, or a
    screen on hello.face in place of 8081."""
    from studio_server import running_screen, running_studio

    if ":8081/" in command:
        server = running_screen(folder, str(folder / "hello.face"))
    else:
        server = running_studio(folder / "show.face")
    with server as studio:
        port = studio.base.rsplit(":", 1)[1]
        run = subprocess.run(
            re.sub(r":808[01]/", f":{port}/", command),
            shell=True,
            cwd=str(folder),
            env=doc_env(),
            capture_output=True,
            text=True,
            timeout=120,
        )
    assert run.returncode == 0, run.stderr
    assert matches(expected, run.stdout.rstrip("\n").splitlines()), run.stdout


def doc_env():
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "BAXTERFACE_DEBUG")}
    env.update(COLUMNS="100", NO_COLOR="1", TERM="xterm-256color")
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env['PATH']}"
    return env


def break_a_theme(folder):
    """The docs' `broken/`: an exported theme whose skin-3.png was cropped to 1000 pixels wide."""
    from PIL import Image

    if not folder.exists():
        subprocess.run(["baxterface", "theme", "export", str(folder)], env=doc_env(), check=True)
    skin = folder / "skin-3.png"
    Image.open(skin).crop((0, 0, 1000, 600)).save(skin)


def test_the_console_examples_are_found():
    commands = [c for _, c, _ in console_examples()]
    assert "baxterface explain hello.face" in commands and len(LOCAL) >= 8


# -- Python examples: each runs, and prints what the docs show ----------------

# Blocks that need rospy run against a real master in tests/test_docs_ros.py, those that open a
# Link (ROS 1 or 2) or import rclpy in tests/test_docs_ros2.py.
# Those that import rclpy itself talk to a face node of test_docs_ros2.py's.
PYTHON = [
    e
    for e in python_examples()
    if "import rospy" not in e.code and "open_link(" not in e.code and "import rclpy" not in e.code
]


@pytest.mark.parametrize("example", PYTHON, ids=[f"{e.doc}: python {e.number}" for e in PYTHON])
def test_python_examples_run_and_print_what_the_docs_show(example, doc_folder):
    for command in example.setup:  # what an earlier step of the doc made, as `theme export`
        subprocess.run(command, shell=True, cwd=str(doc_folder), env=doc_env(), capture_output=True)
    program = doc_folder / "example.py"
    program.write_text(example.code, encoding="utf-8")
    run = subprocess.run(
        [sys.executable, str(program)], cwd=str(doc_folder), env=doc_env(), capture_output=True, text=True
    )
    assert run.returncode == 0, run.stderr
    if example.expected is not None:
        printed = run.stdout.rstrip("\n")
        assert matches(example.expected, printed.splitlines() if printed else []), printed


def test_the_python_examples_are_found():
    docs = {e.doc for e in python_examples()}
    assert {"README.md", "api.md", "language.md", "speech.md", "themes.md"} <= docs
    assert sum(1 for e in python_examples() if e.expected) >= 3


def test_the_languages_table_of_controls_is_the_controls_table():
    from baxterface_cli.core.expression import CONTROLS
    from baxterface_cli.core.presets import DEFAULT_FACE

    text = (ROOT / "docs" / "language.md").read_text(encoding="utf-8")
    rows = [line for line in text.splitlines() if line.startswith("| `") and "Expression" not in line]
    shown = {}
    for row in rows:
        cells = [c.strip() for c in re.split(r"(?<!\\)\|", row.strip("|"))]
        if len(cells) == 5 and "to" in cells[1]:
            shown[cells[0]] = cells[1:]
    assert len(shown) == len(CONTROLS)
    for (part, control), spec in CONTROLS.items():
        optional = "[left\\|right]" if len(spec.sides) > 1 else ""
        side = optional if "" in spec.sides else "left\\|right"
        name = "`" + " ".join(w for w in (part, side, control) if w) + "`"
        low_high, default, meaning, fields = shown[name]
        assert low_high == f"{spec.low:g} to {spec.high:g}", name
        first = spec.sides.get("", spec.sides.get("left"))[0]
        assert float(default) == pytest.approx(getattr(DEFAULT_FACE, first), abs=0.005), name
        assert meaning == spec.meaning, name
        every = sorted({f for group in spec.sides.values() for f in group})
        assert sorted(f.strip("` ") for f in fields.split(",")) == every, name
