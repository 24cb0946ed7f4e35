"""The wheel carries the grammar: installed into a fresh venv, it works anywhere."""

from __future__ import annotations

import subprocess
import sys
import venv
import zipfile

import pytest

from conftest import ROOT

pytestmark = pytest.mark.slow


def run(*cmd, cwd=None):
    return subprocess.run([str(c) for c in cmd], cwd=cwd, capture_output=True, text=True, timeout=600)


def test_wheel_installs_into_a_fresh_venv_and_runs_from_elsewhere(tmp_path):
    dist = tmp_path / "dist"
    built = run(sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-w", dist, ROOT)
    assert built.returncode == 0, built.stderr
    (wheel,) = dist.glob("baxterface-*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    assert "baxterface_cli/grammar/face.lark" in names
    assert "baxterface_cli/assets/default/theme.json" in names
    assert "baxterface_cli/assets/default/skin-5.png" in names
    assert "baxterface_cli/robot/buttons.json" in names
    assert "baxterface_cli/data/voices.txt" in names  # what `check` knows voices by
    for page in ("index.html", "app.js", "editor.js", "studio.css"):  # the studio, with no Node
        assert f"baxterface_cli/studio/static/{page}" in names
    for shared in ("sound.js", "tap.js"):  # what every face page loads
        assert f"baxterface_cli/web/static/{shared}" in names
    for page in ("screen.html", "screen.js", "screen.css"):  # the screen's page
        assert f"baxterface_cli/screen/static/{page}" in names
    assert "baxterface_cli/studio/panel.json" in names
    # The editor's build recipe stays in the sdist.
    assert not [n for n in names if "/studio/editor_recipe/" in n]

    env_dir = tmp_path / "venv"
    venv.create(env_dir, with_pip=False)  # this pip installs into it: no pip of its own to set up
    bindir = env_dir / ("Scripts" if sys.platform == "win32" else "bin")
    # Not compiled at install (what a user's pip does by default, not what is tested here).
    installed = run(
        sys.executable, "-m", "pip", "--python", bindir / "python", "install", "-q", "--no-compile", wheel
    )
    assert installed.returncode == 0, installed.stderr

    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "s.face").write_text("happy; look 40 -20 in 0.5s; wobble 0.3\nhapy\n", encoding="utf-8")
    checked = run(bindir / "baxterface", "check", "s.face", cwd=elsewhere)
    assert checked.returncode == 1
    assert "s.face:2:1: error: unknown command 'hapy'; did you mean 'happy'?" in checked.stderr
    # The grammar came from inside the installed package, not from this checkout.
    where = run(
        bindir / "python",
        "-c",
        "from baxterface_cli.resources import resource; print(resource('grammar/face.lark'))",
        cwd=elsewhere,
    )
    assert "site-packages" in where.stdout and str(ROOT) not in where.stdout
    # The installed theme draws a face.
    drawn = run(
        bindir / "python",
        "-c",
        "from baxterface_cli import Face; f = Face(); f.set_emotion('happy', 0); "
        "print(f.frame().shape, f.theme.name)",
        cwd=elsewhere,
    )
    assert drawn.stdout.strip() == "(600, 1024, 3) default", drawn.stderr
