"""Themes: export, load, use at any size, and clear errors for broken ones."""

from __future__ import annotations

import json
import os
import shutil

import numpy as np
import pytest

from baxterface_cli import Face, ThemeError
from baxterface_cli.drawing.theme import Theme
from baxterface_cli.drawing.theme_manifest import parse_size
from conftest import baxterface

# One worker runs the module, so the exported theme is made once, not once a worker.
pytestmark = pytest.mark.xdist_group("theme_export")

SIZE = (256, 150)


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    folder = tmp_path_factory.mktemp("theme") / "mine"
    Theme.default().export(folder, SIZE)
    return folder


@pytest.fixture
def theme_dir(exported, tmp_path):
    folder = tmp_path / "theme"
    shutil.copytree(exported, folder)
    return folder


def test_an_exported_theme_draws_the_same_face(theme_dir):
    mine, default = Face(theme=theme_dir, size=SIZE), Face(size=SIZE)
    for face in (mine, default):
        face.set_emotion("happy", 1)
        face.look_at(30, -40)
    assert np.array_equal(mine.frame(), default.frame())


def test_a_theme_is_resampled_to_another_size(theme_dir):
    resampled = Face(theme=theme_dir, size=(512, 320)).frame_rgb().astype(int)
    drawn = Face(size=(512, 320)).frame_rgb().astype(int)
    assert resampled.shape == (320, 512, 3)
    assert np.abs(resampled - drawn).mean() < 6  # same face, only softer edges


def test_export_refuses_a_folder_with_files_unless_forced(exported):
    with pytest.raises(ThemeError, match="not empty"):
        Theme.default().export(exported, SIZE)


def break_manifest(folder, change):
    path = folder / "theme.json"
    manifest = json.loads(path.read_text())
    change(manifest)
    path.write_text(json.dumps(manifest))


@pytest.mark.parametrize(
    "damage, message",
    [
        (lambda d: (d / "mouth-teeth.png").unlink(), "mouth-teeth.png: missing"),
        (
            lambda d: (d / "brows-raised.png").write_bytes(b"\x89PNG\r\n\x1a\n garbage"),
            "brows-raised.png: cannot read image",
        ),
        (lambda d: (d / "eyes.png").write_text("not an image"), "eyes.png: cannot read image"),
        (
            lambda d: _resize(d / "skin-2.png", (100, 60)),
            "skin-2.png: is 100x60, but a skin layer must cover the theme's 256x150 screen",
        ),
        (lambda d: _resize(d / "eyes.png", (300, 150)), "eyes.png: a 300x150 image at 0,0 runs off"),
        (
            lambda d: (d / "theme.json").write_text('{"size": [256, 150],\n "layers": [}'),
            "theme.json:2:13: not valid JSON",
        ),
        (lambda d: (d / "theme.json").unlink(), "theme.json: missing"),
        (lambda d: break_manifest(d, lambda m: m["layers"].pop()), "no brows layer named 'worried'"),
        (lambda d: break_manifest(d, lambda m: m["layers"].pop(3)), "no skin layer named '0'"),
        (lambda d: break_manifest(d, lambda m: [m["layers"].pop() for _ in range(3)]), "and 2 more"),
        (lambda d: break_manifest(d, lambda m: m["layers"][0].pop("name")), None),
        (
            lambda d: break_manifest(d, lambda m: m["layers"][0].update(file="../../../etc/passwd")),
            "must be inside the theme folder",
        ),
        (lambda d: break_manifest(d, lambda m: m.update(size="big")), "'size' must be [width, height]"),
        (lambda d: break_manifest(d, lambda m: m["layers"][0].update(kind="hat")), "unknown 'hat'"),
    ],
)
def test_broken_themes_fail_with_the_file_named(theme_dir, damage, message):
    damage(theme_dir)
    if message is None:  # not broken after all: a layer's name defaults to its kind
        Face(theme=theme_dir, size=SIZE)
        return
    with pytest.raises(ThemeError) as caught:
        Face(theme=theme_dir, size=SIZE)
    assert message in str(caught.value)
    assert str(theme_dir) in str(caught.value)


def _resize(path, size):
    from PIL import Image

    Image.open(path).convert("RGBA").resize(size).save(path)


def test_theme_check_prints_one_line_and_fails(theme_dir):
    (theme_dir / "mouth-teeth.png").unlink()
    run = baxterface("theme", "check", str(theme_dir))
    assert run.code == 1
    assert run.err.strip().count("\n") == 0 and "mouth-teeth.png: missing" in run.err
    assert baxterface("theme", "check", str(theme_dir.parent / "nope")).code == 1


def test_theme_export_from_the_command_line(tmp_path):
    run = baxterface("theme", "export", str(tmp_path / "t"), "--size", "320x200")
    assert run.code == 0, run.err
    assert baxterface("theme", "check", str(tmp_path / "t")).code == 0
    assert json.loads((tmp_path / "t" / "theme.json").read_text())["size"] == [320, 200]
    bad = baxterface("theme", "export", str(tmp_path / "u"), "--size", "big")
    assert bad.code == 2 and "'--size': must look like 1024x600" in bad.err


@pytest.mark.parametrize("text, size", [("1024x600", (1024, 600)), ("1920X1200", (1920, 1200))])
def test_sizes_parse(text, size):
    assert parse_size(text) == size


@pytest.mark.parametrize("text", ["1024", "0x600", "axb", "99999x2"])
def test_bad_sizes_say_so(text):
    with pytest.raises(ValueError):
        parse_size(text)


def write_manifest_text(folder, old, new):
    path = folder / "theme.json"
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new, 1))


@pytest.mark.parametrize(
    "damage, message",
    [
        (lambda d: break_manifest(d, lambda m: m["layers"][0].update(file="eyes\0.png")), "a NUL character"),
        (
            lambda d: break_manifest(d, lambda m: m["layers"][0].update(file="\ud800.png")),
            "not a possible file",
        ),
        (
            lambda d: write_manifest_text(d, '"lid_travel": 330.0', '"lid_travel": ' + "9" * 5000),
            "is too long",
        ),
        (lambda d: (d / "theme.json").write_text("[" * 100_000 + "]" * 100_000), "nested too deeply"),
        (lambda d: write_manifest_text(d, '"lid_travel": 330.0', '"lid_travel": NaN'), "NaN is not a number"),
        (
            lambda d: write_manifest_text(d, '"lid_travel": 330.0', '"lid_travel": 1e309'),
            "'lid_travel' must be",
        ),
        (lambda d: break_manifest(d, lambda m: m.update(lid_travel=True)), "'lid_travel' must be"),
        (lambda d: break_manifest(d, lambda m: m.update(size=[True, 150])), "'size' must be [width, height]"),
        (
            lambda d: break_manifest(d, lambda m: m.update(size=[-256, 150])),
            "'size' [-256, 150] is too small",
        ),
        (lambda d: break_manifest(d, lambda m: m.update(size=[8192, 8192])), "at most 8294400 pixels"),
        (lambda d: break_manifest(d, lambda m: m["layers"][5].update(anchor=[False, 0])), "the anchor of"),
        (lambda d: break_manifest(d, lambda m: m["layers"][5].update(anchor=[0.5, 0])), "the anchor of"),
        (lambda d: break_manifest(d, lambda m: m.update(name=["mine"])), "'name' must be a string"),
        (
            lambda d: break_manifest(d, lambda m: m["layers"][3].update(name=0)),
            "layer 4's 'name' must be a string",
        ),
        (lambda d: break_manifest(d, lambda m: m["layers"].append(m["layers"][0])), "layer 29 repeats the"),
        (
            lambda d: break_manifest(d, lambda m: m["layers"][0].update(file="/etc/hostname")),
            "inside the theme",
        ),
        (lambda d: (d / "eyes.png").write_bytes(b""), "eyes.png: cannot read image"),
        (
            lambda d: _blank(d / "eyes.png", (10_000, 10_000)),
            "eyes.png: 10000x10000 is too large: at most 8294400",
        ),
        (lambda d: ((d / "eyes.png").unlink(), (d / "eyes.png").mkdir()), "eyes.png: not a file"),
        (
            lambda d: _link(d / "eyes.png", d.parent / "outside.png"),
            "'eyes.png' must be inside the theme folder",
        ),
        (lambda d: _link(d / "eyes.png", d / "eyes.png"), "eyes.png"),  # a loop
    ],
)
def test_odd_manifests_and_files_fail_with_one_clear_line(theme_dir, damage, message):
    damage(theme_dir)
    run = baxterface("theme", "check", str(theme_dir))
    assert run.code == 1, run.err
    assert run.err.startswith(f"baxterface: {theme_dir}") and run.err.count("\n") == 1
    assert message in run.err


def _blank(path, size):
    from PIL import Image

    Image.new("1", size).save(path)


def _link(path, target):
    """Replace the layer `path` by a link to `target`, which gets its image."""
    if target != path:
        shutil.copy(path, target)
    path.unlink()
    path.symlink_to(target)


def test_a_layer_of_another_format_or_mode_is_fine(theme_dir):
    from PIL import Image

    Image.open(theme_dir / "skin-0.png").save(theme_dir / "skin-0.png", format="GIF")
    Image.open(theme_dir / "skin-1.png").convert("L").save(theme_dir / "skin-1.png")
    assert baxterface("theme", "check", str(theme_dir)).code == 0


def test_export_onto_a_file_or_where_it_cannot_write_fails_clearly(tmp_path):
    afile = tmp_path / "afile"
    afile.write_text("mine\n")
    for folder, message in [
        (afile, f"baxterface: {afile}: not a folder; choose a new folder"),
        (afile / "sub", f"baxterface: {afile / 'sub'}: cannot write: Not a directory"),
        ("/proc/x", "baxterface: /proc/x: cannot write: "),
    ]:
        run = baxterface("theme", "export", str(folder), "--size", "64x40")
        assert run.code == 1 and run.err.startswith(message) and run.err.count("\n") == 1, run.err
    assert afile.read_text() == "mine\n"
    empty = baxterface("theme", "export", "", cwd=tmp_path)
    assert empty.code == 2 and "is empty" in empty.err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile"]


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="root writes to read-only folders")
def test_export_into_a_read_only_folder_fails_clearly(tmp_path):
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        run = baxterface("theme", "export", str(locked / "t"), "--size", "64x40")
    finally:
        locked.chmod(0o700)
    assert run.code == 1 and run.err == f"baxterface: {locked / 't'}: cannot write: Permission denied\n"


@pytest.mark.parametrize(
    "text, message",
    [
        ("8192x8192", "size 8192x8192 is too large: at most 8294400 pixels (e.g. 3840x2160)"),
        ("8200x100", "size 8200x100 is too large: at most 8192 pixels a side"),
        ("15x600", "size 15x600 is too small: at least 16 pixels a side"),
        ("²x3", "size must look like 1024x600"),
        ("1" + "0" * 5000 + "x600", "is too large"),
    ],
)
def test_sizes_out_of_bounds_say_which_bound(text, message):
    with pytest.raises(ValueError) as caught:
        parse_size(text)
    assert message in str(caught.value) and len(str(caught.value)) < 100


def test_the_largest_size_is_allowed_everywhere():
    assert parse_size("3840x2160") == (3840, 2160)
    with pytest.raises(ValueError, match="too large"):
        Face(size=(8192, 8192))
