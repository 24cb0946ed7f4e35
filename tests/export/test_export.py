"""`render` to MP4, WebM, WebP and APNG, read back by independent readers (ffprobe, PyAV, Pillow)."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from conftest import baxterface

SCRIPT = "happy; look 40 -20 in 1s; skin 5; wait 0.2s; look -30 10 in 0.5s"
LENGTH = 2.0  # seconds, as explain says
CHECKED_AT = 1.7  # a moment inside the second look


def probe(path: Path) -> dict:
    """What ffprobe (FFmpeg's own reader, not the writer's library) says about a video."""
    out = subprocess.run(
        [
            "ffprobe",
            "-v",
            "error",
            "-count_frames",
            "-show_streams",
            "-show_format",
            "-of",
            "json",
            str(path),
        ],
        capture_output=True,
        check=True,
        text=True,
    ).stdout
    return json.loads(out)


def decoded_frames(path: Path) -> list:
    """Every frame as RGB, decoded by PyAV."""
    import av

    with av.open(str(path)) as container:
        return [f.to_ndarray(format="rgb24") for f in container.decode(video=0)]


def still(tmp_path: Path, at: float) -> np.ndarray:
    out = tmp_path / f"at{at}.png"
    assert baxterface("render", "-e", SCRIPT, "--out", str(out), "--at", str(at)).code == 0
    return np.asarray(Image.open(out).convert("RGB")).astype(int)


def test_explain_gives_the_length_the_videos_must_have():
    run = baxterface("explain", "-e", SCRIPT)
    assert run.out.splitlines()[0] == f"<-e>: {LENGTH:.2f} s"


@pytest.mark.parametrize("ext, codec", [(".mp4", "h264"), (".webm", "vp9")])
def test_a_video_lasts_the_script_in_frames_a_browser_plays_and_shows_what_a_still_shows(
    tmp_path, ext, codec
):
    out = tmp_path / f"face{ext}"
    run = baxterface("render", "-e", SCRIPT, "--out", str(out), "--fps", "25")
    assert run.code == 0, run.err
    info = probe(out)
    (stream,) = info["streams"]
    assert stream["codec_name"] == codec and stream["pix_fmt"] == "yuv420p"
    assert (stream["width"], stream["height"]) == (1024, 600)
    assert int(stream["nb_read_frames"]) == LENGTH * 25
    assert abs(float(info["format"]["duration"]) - LENGTH) <= 1 / 25
    frames = decoded_frames(out)
    expected = still(tmp_path, CHECKED_AT)
    shown = frames[round(CHECKED_AT * 25)].astype(int)
    # Lossy, so alike on average and in the eyes' place, not to the bit.
    assert np.abs(shown - expected).mean() < 3
    assert np.abs(shown - still(tmp_path, 0.0)).mean() > 3 * np.abs(shown - expected).mean()
    assert list(tmp_path.iterdir()) and not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


def test_a_video_carries_the_scripts_sound_when_it_has_some(tmp_path):
    from baxterface_cli.export.sink import Export
    from baxterface_cli.export.video import open_video_writer

    rate = 22050
    tone = (8000 * np.sin(2 * np.pi * 440 * np.arange(rate) / rate)).astype(np.int16)  # 1 s
    out = tmp_path / "sound.mp4"
    writer = open_video_writer(out, Export((64, 48), 25.0, 1.0, audio=(tone, rate)), "h264")
    for i in range(25):
        writer.add(np.full((48, 64, 3), i * 10, np.uint8), i / 25)
    writer.close()
    kinds = {s["codec_type"]: s for s in probe(out)["streams"]}
    assert kinds["audio"]["codec_name"] == "aac" and int(kinds["audio"]["sample_rate"]) == rate
    assert abs(float(kinds["audio"]["duration"]) - 1.0) < 0.1


@pytest.mark.parametrize("ext", [".webp", ".apng"])
def test_an_animation_is_lossless_loops_and_keeps_the_scripts_time(tmp_path, ext):
    out = tmp_path / f"face{ext}"
    assert baxterface("render", "-e", SCRIPT, "--out", str(out), "--fps", "20").code == 0
    expected = still(tmp_path, CHECKED_AT)
    with Image.open(out) as im:
        assert im.is_animated and im.size == (1024, 600) and im.info.get("loop") == 0
        total, shown = 0, None
        for i in range(im.n_frames):
            im.seek(i)
            im.load()  # WebP tells a frame's duration once it is decoded
            if shown is None and total >= CHECKED_AT * 1000 - 1:
                shown = np.asarray(im.convert("RGB")).astype(int)
            total += im.info["duration"]
    assert abs(total - LENGTH * 1000) <= 50  # one frame at 20 fps
    # Lossless: every pixel as the still has it (no palette, no banding).
    assert shown is not None and np.abs(shown - expected).max() == 0


def hide_pyav(tmp_path: Path) -> dict:
    """An environment where `import av` fails, as without the [video] extra."""
    fake = tmp_path / "no_av"
    (fake / "av").mkdir(parents=True)
    (fake / "av" / "__init__.py").write_text("raise ImportError('hidden for the test')\n")
    return dict(os.environ, PYTHONPATH=os.pathsep.join([str(fake), os.environ.get("PYTHONPATH", "")]))


@pytest.mark.one_python  # ffmpeg's encoder, the same under every Python
@pytest.mark.skipif(shutil.which("ffmpeg") is None, reason="needs the ffmpeg program")
def test_without_pyav_an_ffmpeg_on_path_writes_the_same_video(tmp_path):
    out = tmp_path / "fallback.mp4"
    run = baxterface("render", "-e", SCRIPT, "--out", str(out), env=hide_pyav(tmp_path))
    assert run.code == 0, run.err
    (stream,) = probe(out)["streams"]
    assert stream["codec_name"] == "h264" and int(stream["nb_read_frames"]) == LENGTH * 30
    shown = decoded_frames(out)[round(CHECKED_AT * 30)].astype(int)
    assert np.abs(shown - still(tmp_path, CHECKED_AT)).mean() < 3


def test_without_pyav_or_ffmpeg_one_line_says_how_to_get_one_and_nothing_is_written(tmp_path):
    env = hide_pyav(tmp_path)
    env["PATH"] = str(tmp_path / "empty")  # no ffmpeg anywhere
    out = tmp_path / "out"
    out.mkdir()
    run = baxterface("render", "-e", SCRIPT, "--out", str(out / "x.mp4"), env=env)
    assert run.code == 1
    assert run.err == (
        "baxterface render: writing .mp4 video needs PyAV (pip install 'baxterface[video]') "
        "or an ffmpeg program on PATH (apt install ffmpeg)\n"
    )
    assert list(out.iterdir()) == []


@pytest.mark.parametrize(
    "out, code, message",
    [
        ("x.avi", 2, "--out must end in .png, .gif, .mp4, .webm, .webp, .apng, .bag or .wav"),
        ("x.mov", 2, "or name a folder (end it with '/')"),
    ],
)
def test_formats_it_cannot_write_are_refused_clearly(tmp_path, out, code, message):
    run = baxterface("render", "-e", "happy", "--out", out, cwd=tmp_path)
    assert run.code == code and message in run.err and "Traceback" not in run.err
    assert list(tmp_path.iterdir()) == []


def test_an_odd_size_cannot_be_a_video_and_says_so(tmp_path):
    run = baxterface("render", "-e", "happy", "--out", "x.mp4", "--size", "101x60", cwd=tmp_path)
    assert run.code == 2
    assert run.err == "baxterface render: video needs an even width and height, not 101x60 (see --size)\n"
    assert list(tmp_path.iterdir()) == []
