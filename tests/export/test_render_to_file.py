"""`baxterface render`: GIFs, PNG folders and single PNGs, as files a user gets (videos: test_export)."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from baxterface_cli import parse
from baxterface_cli.drawing.renderer import Renderer
from baxterface_cli.drawing.theme import Theme
from baxterface_cli.engine.compiler import compile_script
from conftest import ROOT, baxterface

SCRIPT = "look 40 -20 in 0.5s ease-in-out; blink; look -30 10 in 0.4s; wobble 0.3"


def under_each_python(first, *others):
    """A test's targets: `first` under every Python, the others under one (one_python). Every
    writer keeps its partial file by the same code; the first, PyAV's, differs most between
    the versions that Python 3.8 and 3.11 install."""
    return [first, *(pytest.param(other, marks=pytest.mark.one_python) for other in others)]


def gif_frames(path):
    """(RGB array, duration in ms) of each frame, as a viewer shows them."""
    with Image.open(path) as im:
        out = []
        for i in range(im.n_frames):
            im.seek(i)
            out.append((np.asarray(im.convert("RGB")).astype(int), im.info["duration"]))
        return out, im.info.get("loop"), im.size


def test_gif_loops_with_the_scripts_timing_and_the_right_pictures(tmp_path):
    out = tmp_path / "show.gif"
    run = baxterface("render", "-e", SCRIPT, "--out", str(out))
    assert run.code == 0, run.err
    frames, loop, size = gif_frames(out)
    assert loop == 0 and size == (1024, 600)
    timeline = compile_script(parse(SCRIPT), seed=0)
    count = round(timeline.duration * 30)  # frames of 1/30 s that last the script
    total_ms = sum(ms for _, ms in frames)
    assert total_ms == round(count * 100 / 30) * 10  # the script's length, in GIF centiseconds
    assert abs(total_ms / 1000 - timeline.duration) <= 0.5 / 30 + 0.005
    times = [k / 30 for k in range(count - 1)] + [timeline.duration]  # the last: the end itself
    renderer = Renderer(Theme.default().layers((1024, 600)))
    elapsed = 0
    for rgb, ms in frames:
        k = round(elapsed / 1000 * 30)
        want = renderer.render(timeline.sample(times[k]))[..., ::-1].astype(int)
        assert np.abs(rgb - want).mean() < 3.0, k
        elapsed += ms
    end = renderer.render(timeline.sample(timeline.duration))[..., ::-1].astype(int)
    assert np.abs(frames[-1][0] - end).mean() < 3.0  # it stops where the script leaves the face


def test_same_script_and_seed_give_byte_identical_gifs(tmp_path):
    text = "happy; angry; crafty; bored; " + SCRIPT
    a, b, c = (tmp_path / f"{n}.gif" for n in "abc")
    for path, seed in ((a, "7"), (b, "7"), (c, "8")):
        args = ["-e", text, "--seed", seed, "--size", "256x150"]  # any size shows it, and small is quick
        assert baxterface("render", *args, "--out", str(path)).code == 0
    assert a.read_bytes() == b.read_bytes()
    assert a.read_bytes() != c.read_bytes()  # the seed is what made them equal


def test_a_folder_gets_numbered_frames_at_the_asked_size(tmp_path):
    folder = tmp_path / "frames"
    run = baxterface(
        "render", "-e", "look 40 0 in 1s", "--out", f"{folder}/", "--fps", "10", "--size", "320x200"
    )
    assert run.code == 0, run.err
    names = sorted(p.name for p in folder.iterdir())
    assert names == [f"frame_{i:05d}.png" for i in range(10)]  # 1 s at 10 fps, as a video has
    assert Image.open(folder / "frame_00009.png").size == (320, 200)
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


def test_a_png_is_the_last_frame_or_the_one_at_at(tmp_path):
    text = "look 40 0 in 1s"
    assert baxterface("render", "-e", text, "--out", str(tmp_path / "end.png")).code == 0
    assert baxterface("render", "-e", text, "--at", "0.5", "--out", str(tmp_path / "mid.png")).code == 0
    renderer = Renderer(Theme.default().layers((1024, 600)))
    timeline = compile_script(parse(text))
    for name, t in (("end.png", 1.0), ("mid.png", 0.5)):
        got = np.asarray(Image.open(tmp_path / name).convert("RGB"))
        assert np.array_equal(got, renderer.render(timeline.sample(t))[..., ::-1])


def test_the_script_can_come_from_a_file_or_standard_input(tmp_path):
    script = tmp_path / "s.face"
    script.write_text("happy\n", encoding="utf-8")
    assert baxterface("render", str(script), "--out", str(tmp_path / "a.png")).code == 0
    assert baxterface("render", "--out", str(tmp_path / "b.png"), stdin="happy\n").code == 0
    assert baxterface("render", "-", "--out", str(tmp_path / "c.png"), stdin="happy\n").code == 0
    assert (
        (tmp_path / "a.png").read_bytes()
        == (tmp_path / "b.png").read_bytes()
        == (tmp_path / "c.png").read_bytes()
    )


@pytest.mark.parametrize(
    "args, code, message",
    [
        (["-e", "hapy", "--out", "x.gif"], 1, "<-e>:1:1: error: unknown command 'hapy'"),
        (["-e", "happy", "--out", "x.avi"], 2, "must end in .png, .gif, .mp4"),
        (["-e", "happy", "--out", "x.gif", "--size", "huge"], 2, "'--size': must look like 1024x600"),
        (["-e", "happy", "--out", "x.gif", "--theme", "/nonexistent"], 1, "not a theme folder"),
        (["s.face", "-e", "happy", "--out", "x.gif"], 2, "not both"),
    ],
)
def test_bad_requests_fail_clearly(tmp_path, args, code, message):
    run = baxterface("render", *args, cwd=tmp_path)
    assert run.code == code
    assert message in run.err and "Traceback" not in run.err
    assert list(tmp_path.iterdir()) == []


def test_without_a_terminal_one_line_says_what_was_written_and_quiet_says_nothing(tmp_path):
    out = tmp_path / "b.gif"
    run = baxterface("render", "-e", "look 40 0 in 1s", "--out", str(out))
    assert (run.code, run.out, run.err) == (0, "", f"wrote {out} (30 frames, 1.00 s)\n")
    quiet = baxterface("render", "-e", "blink", "--out", str(tmp_path / "q.gif"), "-q")
    assert (quiet.code, quiet.out, quiet.err) == (0, "", "")


def writing_in(pid, folder):
    """Is process `pid` writing in `folder`: a file open there (named or not), or a partial folder?"""
    fds = Path(f"/proc/{pid}/fd")
    held = []
    for fd in fds.iterdir() if fds.is_dir() else []:
        with contextlib.suppress(OSError):
            held.append(os.readlink(str(fd)))
    # A folder of frames has its partial folder inside itself.
    places = [folder] + [p for p in folder.iterdir() if p.is_dir() and not p.name.startswith(".")]
    named = any(p.name.startswith(".") for place in places for p in place.iterdir())
    return named or any(h.startswith(f"{folder}/") for h in held)


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT, signal.SIGKILL])
@pytest.mark.parametrize(
    "target", under_each_python("long.mp4", "long.gif", "frames/", "long.apng", "long.bag", "long.webp")
)
def test_a_render_killed_halfway_leaves_no_partial_file(tmp_path, signum, target):
    # Long enough to be caught in the act: 2 minutes of looking about.
    text = "repeat 60 { look 40 -20 in 1s; look -40 20 in 1s }"
    proc = subprocess.Popen(
        [sys.executable, "-m", "baxterface_cli", "render", "-e", text, "--out", f"{tmp_path}/{target}", "-q"],
        cwd=str(ROOT),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    deadline = time.monotonic() + 60
    while not writing_in(proc.pid, tmp_path):  # the render has begun writing
        assert proc.poll() is None and time.monotonic() < deadline
        time.sleep(0.05)
    time.sleep(0.3)
    proc.send_signal(signum)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode != 0
    assert b"Traceback" not in err
    if signum == signal.SIGKILL and target.endswith("/"):
        # A folder of frames cannot be written unnamed: a killed render leaves the folder with its
        # hidden partial folder inside, and the next render into the same place clears it away.
        folder = tmp_path / target
        assert [p.name for p in tmp_path.iterdir()] == [folder.name]
        assert [p.name.endswith(".baxterface-partial") for p in folder.iterdir()] == [True]
        again = baxterface("render", "-e", "look 40 0 in 0.2s", "--fps", "10", "--out", f"{folder}/")
        assert again.code == 0, again.err
        assert sorted(p.name for p in folder.iterdir()) == ["frame_00000.png", "frame_00001.png"]
        return
    assert list(tmp_path.iterdir()) == [], os.listdir(tmp_path)


def test_a_terminal_gets_a_progress_bar(tmp_path):
    import pexpect

    out = tmp_path / "p.gif"
    child = pexpect.spawn(
        sys.executable,
        ["-m", "baxterface_cli", "render", "-e", "look 40 0 in 3s", "--out", str(out)],
        cwd=str(ROOT),
        dimensions=(24, 100),
        encoding="utf-8",
        timeout=60,
    )
    child.expect(pexpect.EOF)
    child.close()
    assert child.exitstatus == 0
    assert "rendering" in child.before  # the bar, drawn while it worked
    assert f"wrote {out} (90 frames, 3.00 s)" in child.before
    assert out.exists()


def dead_pid():
    """The id of a process that has come and gone."""
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    return proc.pid


def partial_name(target, pid, token="abcd1234"):
    return f".{target}.{pid}.{token}.baxterface-partial"


@pytest.mark.parametrize("target", ["face.png", "face.gif", "frames/"])
def test_links_planted_beside_the_target_are_never_followed(tmp_path, target):
    shared, victim, victim_dir = tmp_path / "shared", tmp_path / "victim.txt", tmp_path / "victim"
    shared.mkdir()
    victim.write_text("precious\n")
    victim_dir.mkdir()
    (victim_dir / "keep.txt").write_text("precious\n")
    name = target.rstrip("/")
    # The names renders used to write, and a stale-looking one of the new kind.
    for planted in (f".{name}.partial", f".{name}.partial-abc123"):
        (shared / planted).symlink_to(victim)
    (shared / partial_name(name, dead_pid())).symlink_to(victim_dir, target_is_directory=True)
    run = baxterface("render", "-e", "blink", "--size", "64x40", "--fps", "10", "--out", f"{shared}/{target}")
    assert run.code == 0, run.err
    assert victim.read_text() == "precious\n"
    assert sorted(p.name for p in victim_dir.iterdir()) == ["keep.txt"]
    assert (victim_dir / "keep.txt").read_text() == "precious\n"
    out = shared / name
    first = out / "frame_00000.png" if target.endswith("/") else out
    assert not first.is_symlink()
    Image.open(first).verify()


@pytest.mark.one_python  # the file system's renames, the same under every Python
def test_two_renders_to_one_target_at_once_leave_one_of_them_whole(tmp_path):
    # Each render's result is known from a render alone; together, the
    # target must be exactly one of the two, never a mixture. The seeds
    # differ, and nothing else: the two keep pace, and overlap.
    text = "repeat 5 { happy; look 40 -20 in 0.5s; sad; look -40 20 in 0.5s }"
    seeds = ["1", "2"]
    args = ["-e", text, "--size", "128x75", "--fps", "30", "-q"]
    alone = []
    for seed in seeds:
        out = tmp_path / f"alone{seed}.gif"
        assert baxterface("render", *args, "--seed", seed, "--out", str(out)).code == 0
        alone.append(out.read_bytes())
    assert alone[0] != alone[1]
    for trial in range(2):
        out = tmp_path / f"trial{trial}" / "show.gif"
        out.parent.mkdir()
        procs = [
            subprocess.Popen(
                [sys.executable, "-m", "baxterface_cli", "render", *args, "--seed", seed, "--out", str(out)],
                cwd=str(ROOT),
                stdout=subprocess.DEVNULL,
                stderr=subprocess.PIPE,
            )
            for seed in seeds
        ]
        for proc in procs:
            _, err = proc.communicate(timeout=120)
            assert proc.returncode == 0, err.decode()
        assert out.read_bytes() in alone, trial
        assert [p.name for p in out.parent.iterdir()] == [out.name]
        with Image.open(out) as im:
            im.seek(im.n_frames - 1)  # every frame decodes


def test_partials_of_killed_renders_are_removed_and_live_ones_kept(tmp_path):
    dead, live = dead_pid(), os.getpid()
    stale_file = tmp_path / partial_name("show.gif", dead)
    stale_file.write_bytes(b"GIF89a half")
    stale_folder = tmp_path / partial_name("frames", dead, "x_y9")
    stale_folder.mkdir()
    (stale_folder / "frame_00000.png").write_bytes(b"half")
    others = [
        tmp_path / partial_name("show.gif", live),  # still being written
        tmp_path / partial_name("frames", live, "x_y8"),
        tmp_path / ".show.gif.partial",  # not our naming: not ours to remove
        tmp_path / f".notes.{dead}.txt",
    ]
    for path in others:
        path.write_bytes(b"")
    run = baxterface("render", "-e", "blink", "--size", "64x40", "--out", str(tmp_path / "show.gif"))
    assert run.code == 0, run.err
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["show.gif"] + [p.name for p in others])


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0, reason="needs root to give files away")
def test_another_users_stale_partials_are_left_alone(tmp_path):
    theirs = tmp_path / partial_name("show.gif", dead_pid())
    theirs.write_bytes(b"")
    os.chown(theirs, 65534, 65534)
    assert (
        baxterface("render", "-e", "blink", "--size", "64x40", "--out", str(tmp_path / "show.gif")).code == 0
    )
    assert theirs.exists()


def test_an_empty_out_is_refused_and_touches_nothing(tmp_path):
    (tmp_path / "frame_00000.png").write_bytes(b"mine")
    run = baxterface("render", "-e", "happy", "--out", "", cwd=tmp_path)
    assert run.code == 2 and "--out is empty; give DIR/ (./ for this folder)" in run.err
    assert [p.name for p in tmp_path.iterdir()] == ["frame_00000.png"]


def test_a_folder_render_replaces_only_frames_it_could_have_written(tmp_path):
    (tmp_path / "frame_00042.png").write_bytes(b"old render")
    keep = ["frame_final.png", "frame_1.png", "notes.txt"]
    for name in keep:
        (tmp_path / name).write_bytes(b"mine")
    run = baxterface(
        "render", "-e", "look 40 0 in 0.2s", "--size", "64x40", "--fps", "10", "--out", "./", cwd=tmp_path
    )
    assert run.code == 0, run.err
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(keep + ["frame_00000.png", "frame_00001.png"])


@pytest.mark.parametrize("target", ["new/er/show.gif", "new/er/still.png", "new/er/frames/"])
def test_missing_folders_on_the_way_are_made(tmp_path, target):
    run = baxterface("render", "-e", "blink", "--size", "64x40", "--out", target, cwd=tmp_path)
    assert run.code == 0, run.err
    assert (tmp_path / target).exists()


def test_at_past_the_end_warns_and_shows_the_last_frame(tmp_path):
    text = "look 40 0 in 1s"
    run = baxterface("render", "-e", text, "--at", "30", "--out", str(tmp_path / "late.png"), "-q")
    assert run.code == 0
    assert run.err == "baxterface render: --at 30 is past the script's end (1.00 s); showing the last frame\n"
    assert baxterface("render", "-e", text, "--out", str(tmp_path / "end.png")).code == 0
    assert (tmp_path / "late.png").read_bytes() == (tmp_path / "end.png").read_bytes()
    at_end = baxterface("render", "-e", text, "--at", "1", "--out", str(tmp_path / "end.png"), "-q")
    assert (at_end.code, at_end.err) == (0, "")


@pytest.mark.parametrize("target", ["show.gif", "frames/"])
def test_at_is_refused_for_outputs_of_every_frame(tmp_path, target):
    run = baxterface("render", "-e", "blink", "--at", "0.5", "--out", target, cwd=tmp_path)
    assert run.code == 2 and "picks the frame of a .png" in run.err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "size, message",
    [
        ("8192x8192", "'--size': 8192x8192 is too large: at most 8294400 pixels (e.g. 3840x2160)"),
        ("3841x2160", "'--size': 3841x2160 is too large: at most 8294400 pixels"),
        ("8200x100", "'--size': 8200x100 is too large: at most 8192 pixels a side"),
        ("1" + "0" * 5000 + "x600", "'--size': 100000000000000000000000000000... is too large"),
        ("8x600", "'--size': 8x600 is too small: at least 16 pixels a side"),
    ],
)
def test_sizes_that_would_exhaust_memory_are_refused(tmp_path, size, message):
    run = baxterface("render", "-e", "happy", "--size", size, "--out", "x.png", cwd=tmp_path)
    assert run.code == 2 and message in " ".join(run.err.replace("│", " ").split())  # unwrapped
    assert list(tmp_path.iterdir()) == []


@pytest.fixture
def small_disk(tmp_path):
    """A file system of 64 KB of its own (tmpfs), for a render to fill."""
    mount = tmp_path / "small"
    mount.mkdir()
    if os.geteuid() != 0:
        pytest.skip("mounting a small file system needs root")
    done = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(mount)], capture_output=True
    )
    if done.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {done.stderr.decode().strip()}")
    yield mount
    subprocess.run(["umount", str(mount)], check=True)


@pytest.mark.parametrize(
    "target", under_each_python("x.mp4", "x.gif", "frames/", "x.apng", "x.bag", "x.webp", "x.wav")
)
def test_a_full_disk_is_one_line_and_leaves_nothing(small_disk, target):
    text = 'repeat 10 { look 40 -20 in 1s; look -40 20 in 1s }\nsay "' + "la " * 20 + '"'
    # Small frames fill it all the same (the smallest file, the MP4, is twice its size).
    run = baxterface("render", "-e", text, "--size", "256x150", "--out", f"{small_disk}/{target}")
    assert run.code == 1
    assert (
        run.err.strip() == f"baxterface render: cannot write {small_disk}/{target}: No space left on device"
    )
    assert list(small_disk.iterdir()) == []
