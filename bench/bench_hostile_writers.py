"""The writers under hostile conditions: killed halfway, a full disk, long renders.

    python bench/bench_hostile_writers.py

For every format that `render` writes frame by frame:

- kill -9 halfway: a render of two minutes of looking about is killed with
  SIGKILL once it is writing (a file of its own open in the folder); what is
  left in the folder is counted (goal: nothing);
- a full disk: the same render into a 200 KB file system of its own (tmpfs;
  needs root, else skipped): its exit status, its one line, what is left;
- memory: the peak resident memory of a 10 s and of a 120 s render, so that a
  writer that holds frames instead of streaming them shows as growth.
"""

from __future__ import annotations

import contextlib
import os
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
        return sorted(p.name for p in folder.iterdir())


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


if __name__ == "__main__":
    main()
