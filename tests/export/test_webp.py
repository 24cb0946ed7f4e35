"""Animated WebP written as frames arrive: read back by Pillow (libwebp's demuxer) frame for frame
against the rendered frames, its container checked chunk by chunk, and a file size limit (a full
disk, without a mount) met at the frame that reaches it, in one line, leaving nothing.

(ffprobe and PyAV's FFmpeg decode no animated WebP, the file FFmpeg's own encoder writes neither.)
"""

from __future__ import annotations

import os
import struct
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from conftest import ROOT, baxterface

pytest.importorskip("PIL.WebPImagePlugin")

SCRIPT = "happy; look 40 -20 in 1s; skin 5; wait 0.2s; look -30 10 in 0.5s"  # 2 s, 60 frames at 30 fps


def chunks(path: Path) -> list:
    """The file's top-level chunks as (kind, data), after checking the RIFF header's size."""
    data = path.read_bytes()
    assert data[:4] == b"RIFF" and data[8:12] == b"WEBP"
    assert struct.unpack("<I", data[4:8])[0] == len(data) - 8
    found, at = [], 12
    while at < len(data):
        kind, (length,) = data[at : at + 4], struct.unpack("<I", data[at + 4 : at + 8])
        found.append((kind, data[at + 8 : at + 8 + length]))
        at += 8 + length + (length & 1)
    assert at == len(data)
    return found


def shown_frames(path: Path, fps: float) -> list:
    """Each frame time's picture as a viewer shows it: a WebP frame for as many frame times as it lasts."""
    out, elapsed = [], 0
    with Image.open(path) as im:
        assert im.is_animated and im.info.get("loop") == 0
        for i in range(im.n_frames):
            im.seek(i)
            im.load()  # WebP tells a frame's duration once it is decoded
            picture = np.asarray(im.convert("RGB"))
            start, elapsed = elapsed, elapsed + im.info["duration"]
            out += [picture] * (round(elapsed * fps / 1000) - round(start * fps / 1000))
    return out


def test_a_render_is_the_rendered_frames_exactly_and_equal_frames_merge(tmp_path):
    out, folder = tmp_path / "face.webp", tmp_path / "frames"
    for target in (str(out), f"{folder}/"):
        run = baxterface(
            "render",
            "-e",
            SCRIPT,
            "--out",
            target,
            "--size",
            "256x150",
            "-q",
        )
        assert run.code == 0, run.err
    drawn = [np.asarray(Image.open(p).convert("RGB")) for p in sorted(folder.glob("frame_*.png"))]
    shown = shown_frames(out, 30)
    assert len(drawn) == len(shown) == 60
    for i, (a, b) in enumerate(zip(drawn, shown)):
        assert np.array_equal(a, b), f"frame {i} differs"
    kinds = [kind for kind, _ in chunks(out)]
    assert kinds[:2] == [b"VP8X", b"ANIM"] and set(kinds[2:]) == {b"ANMF"}
    vp8x, anim = chunks(out)[0][1], chunks(out)[1][1]
    canvas = (int.from_bytes(vp8x[4:7], "little") + 1, int.from_bytes(vp8x[7:10], "little") + 1)
    assert vp8x[0] & 0x02 and canvas == (256, 150)  # animated
    assert struct.unpack("<H", anim[4:6])[0] == 0  # loops forever
    frames = [data for kind, data in chunks(out) if kind == b"ANMF"]
    assert len(frames) < 60  # the still moments are one frame each
    assert sum(int.from_bytes(f[12:15], "little") for f in frames) == 2000  # ms, the script's length
    assert not [p.name for p in tmp_path.iterdir() if p.name.startswith(".")]


def test_rectangles_at_odd_places_and_unchanged_frames(tmp_path):
    from baxterface_cli.export.sink import Export
    from baxterface_cli.export.webp import WebpWriter

    rng = np.random.default_rng(1)
    frames = [rng.integers(0, 255, (41, 67, 3), np.uint8)]
    for i in range(1, 40):
        frame = frames[-1].copy()
        if i % 3:  # every third frame the same as the one before
            y, x = rng.integers(0, 40), rng.integers(0, 66)
            frame[y : y + 1 + i % 5, x : x + 1 + i % 7] = rng.integers(0, 255, 3, np.uint8)
        frames.append(frame)
    out = tmp_path / "odd.webp"
    with WebpWriter(out, Export((67, 41), 30.0, 40 / 30)) as writer:
        for i, frame in enumerate(frames):
            writer.add(frame, i / 30)
    shown = shown_frames(out, 30)
    assert len(shown) == 40
    for i, (frame, picture) in enumerate(zip(frames, shown)):
        assert np.array_equal(frame[..., ::-1], picture), f"frame {i} differs"
    durations = [int.from_bytes(d[12:15], "little") for k, d in chunks(out) if k == b"ANMF"]
    assert sum(durations) == 1333 and len(durations) < 40


def limited(limit: int, *args: str, cwd: Path) -> subprocess.CompletedProcess:
    """`baxterface ARGS` in a process that may write no file past `limit` bytes: a disk that fills."""
    import resource

    def lower() -> None:
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    return subprocess.run(
        [sys.executable, "-m", "baxterface_cli", *args],
        cwd=str(cwd),
        capture_output=True,
        text=True,
        timeout=120,
        preexec_fn=lower,
        env=dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])),
    )


@pytest.mark.skipif(not hasattr(os, "fork"), reason="a file size limit is set in the child")
def test_a_full_disk_fails_within_the_first_frames_in_one_line_and_leaves_nothing(tmp_path):
    # Forty minutes of looking about (72,000 frames): not rendered whole in the time allowed.
    script = "repeat 1200 { look 40 -20 in 1s; look -40 20 in 1s }"
    # The limit holds for every file the child writes: what the face keeps in its cache is made first.
    # (Else, under Python 3.8's numpy, np.savez meeting the limit prints an ignored exception at exit.)
    assert baxterface("render", "-e", script, "--out", str(tmp_path / "warm.png")).code == 0
    (tmp_path / "warm.png").unlink()
    start = time.monotonic()
    run = limited(300_000, "render", "-e", script, "--out", "long.webp", cwd=tmp_path)
    took = time.monotonic() - start
    assert run.returncode == 1
    assert run.stderr == "baxterface render: cannot write long.webp: File too large\n"
    assert list(tmp_path.iterdir()) == []
    assert took < 60


@pytest.mark.skipif(not hasattr(os, "fork"), reason="a file size limit is set in the child")
def test_the_writer_meets_the_limit_at_the_frame_that_reaches_it(tmp_path):
    """Each frame of noise is about 40 KB as lossless WebP: a limit of 200 KB is reached at the fifth
    or sixth, and the writer says so a few frames later (a frame is written when the next one is
    encoded, and four wait for the encoder): at the 11th here, never at the end (3,000)."""
    program = f"""
import sys
import numpy as np
from pathlib import Path
from baxterface_cli.export.sink import Export
from baxterface_cli.export.webp import WebpWriter
rng = np.random.default_rng(0)
writer = WebpWriter(Path({str(tmp_path / "noise.webp")!r}), Export((128, 96), 30.0, 100.0))
for i in range(3000):
    try:
        writer.add(rng.integers(0, 255, (96, 128, 3), np.uint8), i / 30)
    except OSError as e:
        writer.abort()
        print(i, e.strerror)
        sys.exit(0)
writer.close()
print("never")
"""
    import resource

    def lower() -> None:
        resource.setrlimit(resource.RLIMIT_FSIZE, (200_000, 200_000))

    run = subprocess.run(
        [sys.executable, "-c", program],
        capture_output=True,
        text=True,
        timeout=120,
        preexec_fn=lower,
        cwd=str(ROOT),
    )
    frame, reason = run.stdout.split(" ", 1)
    assert reason.strip() == "File too large" and int(frame) <= 16, run.stdout + run.stderr
    assert list(tmp_path.iterdir()) == []
