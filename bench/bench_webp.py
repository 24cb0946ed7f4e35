"""Animated WebP: the writer that writes as frames arrive, against FFmpeg's libwebp_anim, in the same run.

    python bench/bench_webp.py [ROUNDS]

- size and speed: `hello.face` and the 20.7 s `show.face` at 1024x600, 30 fps, rendered to WebP
  by `render` (this writer) and by FFmpeg's animation encoder through PyAV (the writer before),
  alternately, ROUNDS times (2): wall and CPU seconds (the machine's other load shows in the wall
  time more than in the CPU time), bytes, and the ratios new / before;
- a full disk: `render show.face --out show.webp` in a process that may write no file past 200 KB
  (RLIMIT_FSIZE, no mount needed), with each writer: exit status, its one line, seconds to fail.
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from baxterface_cli import parse_file
from baxterface_cli.drawing.renderer import Renderer
from baxterface_cli.drawing.theme import Theme
from baxterface_cli.engine.animation import Animation
from baxterface_cli.engine.compiler import compile_script
from baxterface_cli.engine.explanation import frame_times
from baxterface_cli.export.sink import Export
from baxterface_cli.export.video import open_video_writer
from baxterface_cli.export.webp import WebpWriter

ROOT = Path(__file__).resolve().parent.parent
SCRIPTS = [ROOT / "scripts_examples" / "hello.face", ROOT / "scripts_examples" / "show.face"]
# The writer before, for `render` in a child: FFmpeg's encoder in place of this one.
BEFORE = """
import sys
from baxterface_cli.export import registry
registry.FORMATS[".webp"] = registry.FORMATS[".webp"]._replace(open=registry._video("webp"))
from baxterface_cli.cli import main
sys.argv[0] = "baxterface"
main()
"""


def write(animation: Animation, renderer: Renderer, out: Path, writer: str) -> tuple:
    """(wall seconds, CPU seconds, bytes) of writing the animation with `writer`."""
    export = Export(renderer.size, 30.0, animation.duration)
    wall, cpu = time.perf_counter(), time.process_time()
    sink = WebpWriter(out, export) if writer == "new" else open_video_writer(out, export, "webp")
    with sink:
        for t in frame_times(animation.duration, 30.0):
            sink.add(renderer.render(animation.sample(t)), t)
    return time.perf_counter() - wall, time.process_time() - cpu, out.stat().st_size


def sizes_and_speeds(rounds: int) -> None:
    renderer = Renderer(Theme.default().layers((1024, 600)))
    print(f"1024x600, 30 fps, {rounds} rounds each, alternately: wall s, CPU s, bytes (new / before)")
    with tempfile.TemporaryDirectory() as tmp:
        for script in SCRIPTS:
            animation = Animation(compile_script(parse_file(script), seed=0))
            runs: dict = {"new": [], "before": []}
            for _ in range(rounds):
                for writer in runs:
                    runs[writer].append(write(animation, renderer, Path(tmp) / f"{writer}.webp", writer))
            best = {w: (min(r[0] for r in rs), min(r[1] for r in rs), rs[0][2]) for w, rs in runs.items()}
            (nw, nc, ns), (bw, bc, bs) = best["new"], best["before"]
            print(
                f"  {script.name:<11} {animation.duration:5.1f} s  new {nw:6.2f} s {nc:6.2f} cpu {ns:>9,} B"
                f"   before {bw:6.2f} s {bc:6.2f} cpu {bs:>9,} B   wall {nw / bw:.2f}x cpu {nc / bc:.2f}x "
                f"size {ns / bs:.3f}x"
            )


def full_disk() -> None:
    print("show.face as WebP with no file past 200 KB (RLIMIT_FSIZE): exit, line, seconds to fail")

    def lower() -> None:
        resource.setrlimit(resource.RLIMIT_FSIZE, (200_000, 200_000))

    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]))
    with tempfile.TemporaryDirectory() as tmp:
        for name, program in (("new", ["-m", "baxterface_cli"]), ("before", ["-c", BEFORE])):
            out = f"{tmp}/show.webp"
            start = time.monotonic()
            done = subprocess.run(
                [sys.executable, *program, "render", "scripts_examples/show.face", "--out", out, "-q"],
                cwd=str(ROOT),
                capture_output=True,
                text=True,
                preexec_fn=lower,
                env=env,
            )
            took = time.monotonic() - start
            lines = done.stderr.strip().splitlines()
            left = os.listdir(tmp)
            print(
                f"  {name:<7} exit {done.returncode}, {len(lines)} line: {lines[-1]!r}, "
                f"{took:.1f} s; {len(left)} left"
            )


def main() -> None:
    sizes_and_speeds(int(sys.argv[1]) if len(sys.argv) > 1 else 2)
    full_disk()


if __name__ == "__main__":
    main()
