"""The writers under hostile conditions: killed halfway, a full disk, long renders.

    python bench/bench_hostile_writers.py

For every format that `render` writes frame by frame:

- kill -9 halfway: a render of two minutes of looking about is killed with
  SIGKILL once it is writing (a file of its own open in the folder); what is
  left in the folder is counted (goal: nothing);
- a full disk: the same render into a 200 KB file system of its own (tmpfs;
  needs root, else skipped): its exit status, its one line, what is left;
- memory: the peak resident memory of a 10 s and of a 120 s render, so that a
  writer that holds frames instead of streaming them shows as growth;
- mount points (root): a folder render onto a mount point holding five frames
  of a render before (frames of theirs lost, what is left beside it), onto a
  read-only one, and, without root's power over permissions, into a writable
  folder inside an unwritable one; each with its exit status, one line, and
  the time it took to fail;
- WebP on a full disk (root): the 20.7 s show into a full tmpfs, the time to
  its one line (FFmpeg's encoder wrote the file only at its end; see also bench_webp.py).
"""

from __future__ import annotations

import contextlib
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
FORMATS = ["long.gif", "frames/", "long.mp4", "long.webm", "long.webp", "long.apng", "long.bag"]
LOOKING = "repeat {n} {{ look 40 -20 in 1s; look -40 20 in 1s }}"


def render(text: str, out: str, **kwargs) -> subprocess.Popen:
    args = [sys.executable, "-m", "baxterface_cli", "render", "-e", text, "--out", out, "-q"]
    return subprocess.Popen(args, cwd=str(ROOT), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, **kwargs)


def writing_in(pid: int, folder: Path) -> bool:
    """Has process `pid` a file open in `folder` (named or not), or made a partial folder there?"""
    held = []
    for fd in Path(f"/proc/{pid}/fd").iterdir():
        with contextlib.suppress(OSError):
            held.append(os.readlink(str(fd)))
    return any(h.startswith(f"{folder}/") for h in held) or any(folder.iterdir())


def killed_halfway(target: str) -> list:
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        proc = render(LOOKING.format(n=60), f"{folder}/{target}")
        deadline = time.monotonic() + 60
        while not writing_in(proc.pid, folder) and time.monotonic() < deadline:
            time.sleep(0.02)
        time.sleep(0.5)  # well into the writing
        proc.kill()
        proc.wait()
        left = []  # a folder of frames keeps its partial inside itself: what is in it counts
        for path in folder.iterdir():
            inside = sorted(path.iterdir()) if path.is_dir() else []
            left += [f"{path.name}/{p.name}" for p in inside] or [path.name]
        return sorted(left)


def full_disk(target: str):
    with tempfile.TemporaryDirectory() as tmp:
        mount = Path(tmp)
        done = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=200k", "tmpfs", tmp], capture_output=True)
        if done.returncode != 0:
            return None
        try:
            proc = render(LOOKING.format(n=20), f"{mount}/{target}")
            _, err = proc.communicate(timeout=300)
            return proc.returncode, err.decode().strip().splitlines(), sorted(p.name for p in mount.iterdir())
        finally:
            subprocess.run(["umount", tmp], check=True)


def peak_mb(seconds: int, target: str) -> float:
    """The peak resident memory (MB) of one render, read from its own rusage."""
    code = (
        "import resource, sys; from baxterface_cli.cli import main\n"
        "try: main(sys.argv[1:])\n"
        "except SystemExit: pass\n"
        "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)"
    )
    with tempfile.TemporaryDirectory() as tmp:
        text = LOOKING.format(n=seconds // 2)
        args = [sys.executable, "-c", code, "render", "-e", text, "--out", f"{tmp}/{target}", "-q"]
        done = subprocess.run(args, cwd=str(ROOT), capture_output=True, text=True, check=True)
        return int(done.stdout.split()[-1]) / 1024


@contextlib.contextmanager
def mounted(where: Path, options: str = "size=64m"):
    where.mkdir(exist_ok=True)
    done = subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(where)], capture_output=True)
    if done.returncode != 0:
        yield None
        return
    try:
        yield where
    finally:
        subprocess.run(["umount", str(where)], check=True)


def timed(args: list, prefix: tuple = ()) -> tuple:
    """(exit status, last line said, seconds) of `baxterface render ARGS`."""
    start = time.monotonic()
    command = [*prefix, sys.executable, "-m", "baxterface_cli", "render", *args, "-q"]
    done = subprocess.run(command, cwd=str(ROOT), capture_output=True, text=True, timeout=600)
    lines = done.stderr.strip().splitlines()
    return done.returncode, (lines[-1] if lines else ""), time.monotonic() - start


def mount_points() -> None:
    print("a 20 s folder render onto a mount point: exit, line, seconds; old frames lost, left beside it")
    with tempfile.TemporaryDirectory() as tmp:
        with mounted(Path(tmp) / "stick") as stick:
            if stick is None:
                print("  skipped: mounting a tmpfs needs root")
                return
            old = {f"frame_{i:05d}.png": f"old {i}".encode() for i in range(5)}
            for name, data in old.items():
                (stick / name).write_bytes(data)
            code, said, took = timed(["-e", LOOKING.format(n=10), "--out", f"{stick}/"])
            # Lost: an old frame gone, neither kept as it was nor replaced by a new one.
            lost = [n for n in old if not (stick / n).exists()]
            beside = [p.name for p in Path(tmp).iterdir() if p.name != "stick"]
            print(f"  writable   exit {code}, {said!r}, {took:.1f} s")
            print(f"             {len(lost)} of 5 old frames lost, {len(beside)} left beside the mount point")
        with mounted(Path(tmp) / "ro", "size=64m,ro") as ro:
            code, said, took = timed(["-e", LOOKING.format(n=10), "--out", f"{ro}/"])
            print(f"  read-only  exit {code}, {said!r}, {took:.1f} s")
        if shutil.which("setpriv") is None:
            print("  in 0555: skipped, needs setpriv (util-linux) to drop root's power over permissions")
            return
        locked = Path(tmp) / "locked"
        (locked / "frames").mkdir(parents=True)
        locked.chmod(0o555)
        drop = ("setpriv", "--bounding-set=-dac_override,-dac_read_search")
        try:
            code, said, took = timed(["-e", LOOKING.format(n=10), "--out", f"{locked}/frames/"], drop)
            written = len(list((locked / "frames").iterdir()))
            print(f"  in 0555    exit {code}, {written} frames, {took:.1f} s")
            code, said, took = timed(["-e", LOOKING.format(n=10), "--out", f"{locked}/new/"], drop)
            print(f"  new in 0555 exit {code}, {said!r}, {took:.1f} s")
        finally:
            locked.chmod(0o755)


def webp_full_disk() -> None:
    print("the 20.7 s show as WebP onto a full disk: exit, line, seconds to fail")
    with tempfile.TemporaryDirectory() as tmp, mounted(Path(tmp) / "full", "size=256k") as full:
        if full is None:
            print("  skipped: mounting a tmpfs needs root")
            return
        with contextlib.suppress(OSError), open(full / "filler", "wb") as f:
            f.write(b"\0" * (1 << 20))
        code, said, took = timed(["scripts_examples/show.face", "--out", f"{full}/show.webp"])
        print(f"  show.webp  exit {code}, {said!r}, {took:.1f} s")


def main() -> None:
    print("kill -9 halfway through a 120 s render: files left in the folder")
    for target in FORMATS:
        left = killed_halfway(target)
        print(f"  {target:<10} {len(left)} left" + (f" ({', '.join(left)})" if left else ""))
    print("a full disk (a 200 KB tmpfs) under a 40 s render: exit status, message, files left")
    for target in FORMATS + ["long.wav"]:
        result = full_disk(target)
        if result is None:
            print("  skipped: mounting a tmpfs needs root")
            break
        code, lines, left = result
        said = lines[-1] if lines else ""
        print(f"  {target:<10} exit {code}, {len(lines)} line: {said!r}; {len(left)} left")
    print("peak memory of a render (MB): 10 s, 120 s")
    for target in ["long.gif", "long.mp4", "long.apng", "long.bag"]:
        short, long = peak_mb(10, target), peak_mb(120, target)
        print(f"  {target:<10} {short:6.0f} {long:6.0f}  ({long / short:.2f}x)")
    mount_points()
    webp_full_disk()


if __name__ == "__main__":
    main()
