"""Where `render --out` points: mount points, read-only and unwritable folders, pipes, devices, full
disks. A user's files are never lost, a target that cannot be written fails before a frame is drawn
and names the folder at fault, and every count of frames agrees."""

from __future__ import annotations

import contextlib
import errno
import json
import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from conftest import ROOT, baxterface
from waiting import eventually

LONG = "repeat 60 { look 40 -20 in 1s; look -40 20 in 1s }"  # two minutes: caught in the act


@contextlib.contextmanager
def tmpfs(where: Path, *options: str):
    """A file system of its own at `where` (tmpfs): a mount point, as a user's USB stick is."""
    where.mkdir(exist_ok=True)
    if not hasattr(os, "geteuid") or os.geteuid() != 0:
        pytest.skip("mounting a file system needs root")
    done = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", ",".join(("size=16m",) + options), "tmpfs", str(where)],
        capture_output=True,
    )
    if done.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {done.stderr.decode().strip()}")
    try:
        yield where
    finally:
        subprocess.run(["umount", str(where)], check=True)


def old_frames(folder: Path, count: int) -> dict:
    """A previous render's frames, each with contents of its own; {name: bytes}."""
    frames = {f"frame_{i:05d}.png": f"old frame {i}".encode() for i in range(count)}
    for name, data in frames.items():
        (folder / name).write_bytes(data)
    return frames


def contents(folder: Path) -> dict:
    return {p.name: p.read_bytes() for p in folder.iterdir() if p.is_file()}


def test_a_render_into_a_mount_point_replaces_its_frames_and_keeps_the_rest(tmp_path):
    with tmpfs(tmp_path / "stick") as stick:
        old_frames(stick, 5)
        (stick / "frame_00099.png").write_bytes(b"a longer render's last frame")
        (stick / "notes.txt").write_bytes(b"mine")
        run = baxterface(
            "render", "-e", "look 40 0 in 1s", "--size", "64x40", "--fps", "10", "--out", f"{stick}/"
        )
        assert run.code == 0, run.err
        names = sorted(p.name for p in stick.iterdir())
        assert names == [f"frame_{i:05d}.png" for i in range(10)] + ["notes.txt"]
        assert (stick / "notes.txt").read_bytes() == b"mine"
        for i in range(10):
            assert Image.open(stick / f"frame_{i:05d}.png").size == (64, 40)  # new, whole pictures
    assert [p.name for p in tmp_path.iterdir()] == ["stick"]  # nothing hidden left beside it


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGKILL])
def test_a_previous_renders_frames_are_all_there_until_the_new_ones_are_complete(tmp_path, signum):
    with tmpfs(tmp_path / "stick") as stick:
        before = old_frames(stick, 5)
        proc = subprocess.Popen(
            [sys.executable, "-m", "baxterface_cli", "render", "-e", LONG, "--out", f"{stick}/", "-q"],
            cwd=str(ROOT),
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
        )

        def drawing() -> bool:  # its hidden folder inside has frames in it
            assert proc.poll() is None
            return any(any(p.iterdir()) for p in stick.iterdir() if p.is_dir())

        eventually(drawing, timeout=60)
        proc.send_signal(signum)
        _, err = proc.communicate(timeout=60)
        assert proc.returncode != 0 and b"Traceback" not in err
        assert contents(stick) == before  # every old frame, as it was


def test_a_full_disk_under_a_folder_render_keeps_the_old_frames(tmp_path):
    with tmpfs(tmp_path / "stick") as stick:
        before = old_frames(stick, 5)
        filler = stick / "filler"
        with contextlib.suppress(OSError), open(filler, "wb") as f:
            f.write(b"\0" * (16 << 20))  # all but the last block or so
        run = baxterface("render", "-e", LONG, "--size", "256x150", "--out", f"{stick}/")
        assert run.code == 1
        assert run.err == f"baxterface render: cannot write {stick}/: No space left on device\n"
        filler.unlink()
        assert contents(stick) == before
        assert sorted(p.name for p in stick.iterdir()) == sorted(before)


@pytest.mark.parametrize("target", ["", "show.gif", "show.mp4", "still.png", "new/frames/"])
def test_a_read_only_mount_point_is_named_and_nothing_is_drawn(tmp_path, target):
    with tmpfs(tmp_path / "stick", "ro") as stick:
        run = baxterface("render", "-e", "blink", "--out", f"{stick}/{target}")
        assert run.code == 1
        assert run.err == (
            f"baxterface render: cannot write {stick}/{target}: {stick} is on a read-only file system\n"
        )
    assert [p.name for p in tmp_path.iterdir()] == ["stick"]


def test_an_unwritable_target_fails_before_the_first_frame_is_drawn(tmp_path):
    from baxterface_cli import parse
    from baxterface_cli.drawing.renderer import Renderer
    from baxterface_cli.drawing.theme import Theme
    from baxterface_cli.engine.animation import Animation
    from baxterface_cli.engine.compiler import compile_script
    from baxterface_cli.export.render_to_file import render
    from baxterface_cli.export.target import TargetError

    animation = Animation(compile_script(parse(LONG)))
    renderer = Renderer(Theme.default().layers((64, 40)))
    drawn = []
    with tmpfs(tmp_path / "stick", "ro") as stick:
        for target in ("show.gif", "frames/", "show.webp"):
            with pytest.raises(TargetError, match="read-only file system"):
                render(
                    animation, renderer, f"{stick}/{target}", progress=lambda done, total: drawn.append(done)
                )
    assert drawn == []


def without_root_powers(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    """`baxterface ARGS` as root without the power to pass over permissions: as any user is."""
    setpriv = shutil.which("setpriv")
    if setpriv is None or not hasattr(os, "geteuid") or os.geteuid() != 0:
        pytest.skip("needs root and setpriv to drop the power to override permissions")
    drop = ["--bounding-set=-dac_override,-dac_read_search"]
    command = [setpriv, *drop, sys.executable, "-m", "baxterface_cli", *args]
    env = dict(os.environ, COLUMNS="100", NO_COLOR="1", TERM="dumb")
    return subprocess.run(command, cwd=str(cwd), env=env, capture_output=True, text=True, timeout=120)


def test_a_writable_folder_in_an_unwritable_one_is_written_and_an_unwritable_folder_is_named(tmp_path):
    locked = tmp_path / "locked"
    (locked / "frames").mkdir(parents=True)
    old_frames(locked / "frames", 3)
    locked.chmod(0o555)
    try:
        run = without_root_powers(
            "render", "-e", "look 40 0 in 0.5s", "--fps", "10", "--out", "locked/frames/", cwd=tmp_path
        )
        assert run.returncode == 0, run.stderr
        assert sorted(p.name for p in (locked / "frames").iterdir()) == [
            f"frame_{i:05d}.png" for i in range(5)
        ]
        for target in ("locked/show.gif", "locked/new/", "locked/new/deeper/show.mp4"):
            run = without_root_powers("render", "-e", LONG, "--out", target, cwd=tmp_path)
            assert run.returncode == 1
            assert run.stderr == (
                f"baxterface render: cannot write {target}: locked is not writable (Permission denied)\n"
            )
        assert sorted(p.name for p in locked.iterdir()) == ["frames"]
    finally:
        locked.chmod(0o755)


def test_a_named_pipe_at_the_target_is_refused_and_kept(tmp_path):
    pipe = tmp_path / "show.mp4"
    os.mkfifo(pipe)
    run = baxterface("render", "-e", "blink", "--out", str(pipe))
    assert run.code == 1
    assert (
        run.err
        == f"baxterface render: cannot write {pipe}: {pipe} is a named pipe; render replaces only files\n"
    )
    assert pipe.is_fifo() and [p.name for p in tmp_path.iterdir()] == ["show.mp4"]


@pytest.mark.parametrize(
    "out, message",
    [
        ("/dev/null/x.mp4", "/dev/null is a character device, not a folder"),
        ("/dev/null/frames/", "/dev/null is a character device, not a folder"),
    ],
)
def test_a_device_is_never_written_nor_taken_for_a_folder(out, message):
    run = baxterface("render", "-e", "blink", "--out", out)
    assert run.code == 1 and run.err == f"baxterface render: cannot write {out}: {message}\n"
    assert Path("/dev/null").is_char_device()


def test_nothing_is_written_into_the_device_folder_even_by_root():
    name = f"/dev/baxterface-test-{os.getpid()}.mp4"
    try:
        run = baxterface("render", "-e", "blink", "--out", name)
        assert run.code == 1 and run.err.startswith(
            f"baxterface render: cannot write {name}: /dev is a system folder"
        )
        assert not os.path.lexists(name)
    finally:
        with contextlib.suppress(OSError):
            os.unlink(name)


def test_a_file_on_the_way_to_a_folder_is_named(tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    run = baxterface("render", "-e", "blink", "--out", "notes.txt/frames/", cwd=tmp_path)
    assert run.code == 1
    assert run.err == "baxterface render: cannot write notes.txt/frames/: notes.txt is a file, not a folder\n"
    assert (tmp_path / "notes.txt").read_text() == "mine"


def test_webp_finds_a_full_disk_at_its_first_frame(tmp_path):
    """The WebP encoder writes its file only at the end: the room for it is asked at the start."""
    pytest.importorskip("av")
    from baxterface_cli.export.sink import Export
    from baxterface_cli.export.video import open_video_writer

    with tmpfs(tmp_path / "stick", "size=256k") as stick:
        with contextlib.suppress(OSError), open(stick / "filler", "wb") as f:
            f.write(b"\0" * (1 << 20))
        writer = open_video_writer(stick / "show.webp", Export((256, 150), 30.0, 60.0), "webp")
        frame = np.random.default_rng(0).integers(0, 255, (150, 256, 3), np.uint8)
        with pytest.raises(OSError) as raised:
            writer.add(frame, 0.0)
        writer.abort()
        assert raised.value.errno == errno.ENOSPC
        assert [p.name for p in stick.iterdir()] == ["filler"]


def test_webp_on_a_full_disk_is_one_line_and_leaves_nothing(tmp_path):
    with tmpfs(tmp_path / "stick", "size=256k") as stick:
        with contextlib.suppress(OSError), open(stick / "filler", "wb") as f:
            f.write(b"\0" * (1 << 20))
        run = baxterface(
            "render", "-e", LONG, "--out", f"{stick}/show.webp"
        )  # in the time bound, not at the end
        assert run.code == 1
        assert run.err == f"baxterface render: cannot write {stick}/show.webp: No space left on device\n"
        assert [p.name for p in stick.iterdir()] == ["filler"]


def test_ctrl_c_on_a_terminal_says_it_stopped_and_writes_nothing(tmp_path):
    import pexpect

    out = tmp_path / "long.mp4"
    child = pexpect.spawn(
        sys.executable,
        ["-m", "baxterface_cli", "render", "-e", LONG, "--out", str(out)],
        cwd=str(ROOT),
        dimensions=(24, 100),
        encoding="utf-8",
        timeout=60,
    )
    child.expect(r" [1-9]\d*%")  # the bar's count, once frames are drawn
    child.sendintr()
    child.expect(pexpect.EOF)
    child.close()
    assert child.exitstatus == 130
    assert f"; {out} not written" in child.before and "baxterface render: stopped after " in child.before
    assert "Traceback" not in child.before
    assert list(tmp_path.iterdir()) == []


def test_ctrl_c_without_a_terminal_is_one_line_too(tmp_path):
    out = tmp_path / "long.gif"
    proc = subprocess.Popen(
        [sys.executable, "-m", "baxterface_cli", "render", "-e", LONG, "--out", str(out)],
        cwd=str(ROOT),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )

    def writing() -> bool:  # the GIF's file, open in the folder, has frames in it
        assert proc.poll() is None
        for fd in Path(f"/proc/{proc.pid}/fd").iterdir():
            with contextlib.suppress(OSError):
                if os.readlink(str(fd)).startswith(f"{tmp_path}/") and fd.stat().st_size > 10_000:
                    return True
        return False

    eventually(writing, timeout=60)
    proc.send_signal(signal.SIGINT)
    stdout, err = proc.communicate(timeout=60)
    lines = err.decode().splitlines()
    assert proc.returncode == 130 and stdout == b""
    assert len(lines) == 1 and lines[0].startswith("baxterface render: stopped after ")
    assert lines[0].endswith(f" frames; {out} not written")
    assert list(tmp_path.iterdir()) == []


def test_every_count_of_frames_agrees_and_the_last_is_the_end(tmp_path):
    text = "look 40 0 in 1s"
    explained = baxterface("explain", "-e", text, "--json")
    records = [json.loads(line) for line in explained.out.splitlines()]
    assert len(records) == 30 and records[-1]["t"] == 1.0
    runs = {
        out: baxterface("render", "-e", text, "--size", "128x76", "--out", f"{tmp_path}/{out}")
        for out in ("frames/", "show.gif", "show.mp4", "end.png")
    }
    for out in ("frames/", "show.gif", "show.mp4"):
        assert runs[out].err == f"wrote {tmp_path}/{out} (30 frames, 1.00 s)\n"
    assert len(list((tmp_path / "frames").iterdir())) == 30
    with Image.open(tmp_path / "show.gif") as gif:
        shown = 0
        for i in range(gif.n_frames):
            gif.seek(i)
            shown += gif.info["duration"]
    assert shown == 1000  # 30 frames of 1/30 s
    probed = subprocess.run(
        [
            "ffprobe",
            "-v",
            "error",
            "-count_frames",
            "-show_streams",
            "-of",
            "json",
            str(tmp_path / "show.mp4"),
        ],
        capture_output=True,
        check=True,
        text=True,
    ).stdout
    assert int(json.loads(probed)["streams"][0]["nb_read_frames"]) == 30
    # The last picture of the folder is the end of the script, as the still of its end is.
    assert (tmp_path / "frames" / "frame_00029.png").read_bytes() == (tmp_path / "end.png").read_bytes()
