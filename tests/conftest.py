"""Shared helpers: run the real `baxterface` command the way a user does."""

from __future__ import annotations

import atexit
import importlib
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Optional, Union

import pytest

ROOT = Path(__file__).resolve().parent.parent
# The tests' shared helpers (browser, studio_server, traces, ...) import as top-level modules.
sys.path.insert(0, str(Path(__file__).resolve().parent / "support"))

# A shell starts a background job with Ctrl-C ignored, and an ignored signal stays ignored in every
# program started from it: the tests that press Ctrl-C on `play`, `render` or `studio` would see
# nothing happen. Handled here, it is back to the default in every program the tests start.
signal.signal(signal.SIGINT, signal.default_int_handler)

# What the tests keep (the recordings' analyses, the fitted theme, the palettes) is in a cache of
# their own, never the user's, and one for the whole run: made by the first process to load this
# (pytest, or xdist's controller), whose workers inherit it, so each thing is made once a run rather
# than once a worker. Every program the tests start inherits it too.
if "BAXTERFACE_TEST_CACHE" not in os.environ:
    os.environ["BAXTERFACE_TEST_CACHE"] = tempfile.mkdtemp(prefix="baxterface-test-cache-")
    atexit.register(shutil.rmtree, os.environ["BAXTERFACE_TEST_CACHE"], True)
os.environ["XDG_CACHE_HOME"] = os.environ["BAXTERFACE_TEST_CACHE"]
# A program the tests start that dies of a signal (a middleware crash at exit, say) prints where
# every thread was, so a failure seen once in CI says where it happened.
os.environ.setdefault("PYTHONFAULTHANDLER", "1")


def pytest_collection_modifyitems(config, items):
    """Long runs go out first and short ones fill in beside them, so a suite ends with its
    workers busy rather than one long run alone: the modules that run in one worker
    (`xdist_group`: a costly fixture made once, or a server of their own), then the whole-tool
    tests at the top of tests/ (the docs' and the examples' programs, many played in real time;
    the wheel), then the rest."""
    top = ROOT / "tests"

    def order(item) -> int:
        if item.get_closest_marker("xdist_group") is not None:
            return 0
        return 1 if Path(str(item.fspath)).resolve().parent == top else 2

    items.sort(key=order)


class Run:
    def __init__(self, proc: subprocess.CompletedProcess) -> None:
        self.code = proc.returncode
        self.out = proc.stdout.decode("utf-8", "replace")
        self.err = proc.stderr.decode("utf-8", "replace")


def baxterface(
    *args: str, stdin: Union[bytes, str, None] = None, cwd: Optional[Path] = None, env: Optional[dict] = None
) -> Run:
    """Run `python -m baxterface_cli ARGS` in a subprocess and collect its output."""
    data = stdin.encode("utf-8") if isinstance(stdin, str) else stdin
    env = dict(env or os.environ, COLUMNS="100", NO_COLOR="1", TERM="dumb")
    env.pop("BAXTERFACE_DEBUG", None)
    proc = subprocess.run(
        [sys.executable, "-m", "baxterface_cli", *args],
        input=data if data is not None else b"",
        capture_output=True,
        cwd=str(cwd or ROOT),
        env=env,
        timeout=120,
    )
    return Run(proc)


@pytest.fixture
def cli():
    return baxterface


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def roscore(tmp_path_factory):
    """A roscore of the module's own on a free loopback port, and the environment that reaches it.

    The ROS parts of a module using it run in subprocesses, so it can share a
    session with test_ros.py, which makes the test process a node on its own master.
    """
    port = free_port()
    env = dict(
        os.environ,
        ROS_MASTER_URI=f"http://127.0.0.1:{port}",
        ROS_IP="127.0.0.1",
        ROS_HOME=str(tmp_path_factory.mktemp("ros_home")),
    )
    env.pop("ROS_HOSTNAME", None)
    core = subprocess.Popen(
        ["roscore", "-p", str(port)], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
    )
    deadline = time.monotonic() + 30
    while subprocess.run(["rosnode", "list"], env=env, capture_output=True, timeout=30).returncode != 0:
        assert core.poll() is None and time.monotonic() < deadline, "roscore did not start"
        time.sleep(0.2)
    yield env
    core.send_signal(signal.SIGINT)
    core.wait(timeout=30)


@pytest.fixture(scope="session")
def engine():
    """The real espeak-ng engine: skipped where it is missing, except in CI, which installs it."""
    from baxterface_cli.extras import MissingTool
    from baxterface_cli.speech.synthesis import engine as speech_engine

    try:
        return speech_engine()
    except MissingTool as e:
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI needs espeak-ng: {e}")
        pytest.skip(f"espeak-ng is not installed: {e}")


def needs(module: str):
    """Import an optional module (OpenCV, scikit-image): skipped where it is missing, except in CI,
    where make test installs it and a missing one must fail."""
    try:
        return importlib.import_module(module)
    except ImportError as e:
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI needs {module}: {e}")
        pytest.skip(f"{module} is not installed: {e}")


@pytest.fixture(scope="module")
def ros2(request):
    """ROS 2 on loopback, in a domain of the module's own: the environment for its processes.

    This process takes it too while the module runs, so a Link it opens
    (`open_link(2, ...)`) meets them. Skipped under Python before 3.10, where
    the ros2 extra installs no rclpy; anywhere else a missing rclpy fails in CI.
    """
    from ros2_world import domain_for, loopback_env

    if sys.version_info < (3, 10):
        pytest.skip("rclpy comes from PyPI for Python 3.10 and later (the ros2 extra)")
    needs("rclpy")
    env = loopback_env(domain_for(Path(str(request.fspath)).name))
    before = dict(os.environ)
    os.environ.update({k: env[k] for k in ("ROS_DOMAIN_ID", "ROS_AUTOMATIC_DISCOVERY_RANGE")})
    yield env
    os.environ.clear()
    os.environ.update(before)
