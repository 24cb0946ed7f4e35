"""Themes: export, load, use at any size, and clear errors for broken ones."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest

from baxterface_cli import Face, ThemeError
from baxterface_cli.theme import Theme, parse_size
from conftest import baxterface

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
    assert bad.code == 2 and "size must look like 1024x600" in bad.err


@pytest.mark.parametrize("text, size", [("1024x600", (1024, 600)), ("1920X1200", (1920, 1200))])
def test_sizes_parse(text, size):
    assert parse_size(text) == size


@pytest.mark.parametrize("text", ["1024", "0x600", "axb", "99999x2"])
def test_bad_sizes_say_so(text):
    with pytest.raises(ValueError):
        parse_size(text)
