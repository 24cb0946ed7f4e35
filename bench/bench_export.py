"""Export: the 20-second show as MP4, WebM, WebP, APNG and a ROS bag, against its GIF.

    python bench/bench_export.py

Each format is rendered in full (1024x600, 30 fps) by `render`, as `baxterface
render show.face --out show.EXT` does, and timed. The baseline, in the same
run, is the GIF of the same show; sizes are also given against the raw
frames (1024 x 600 x 3 bytes each). Goals: the MP4 in at most half the show's
length and at most 40 % of the GIF's size; the bag at most 10 % of its raw frames.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

from baxterface_cli import parse_file
from baxterface_cli.extras import MissingTool
from baxterface_cli.idle import Animation
from baxterface_cli.renderer import Renderer
from baxterface_cli.rendering import render
from baxterface_cli.theme import Theme
from baxterface_cli.timeline import compile_script

SHOW = Path(__file__).resolve().parent.parent / "scripts_examples" / "show.face"
FORMATS = [".mp4", ".webm", ".webp", ".apng", ".bag"]


def timed(animation: Animation, renderer: Renderer, out: Path):
    start = time.perf_counter()
    frames = render(animation, renderer, str(out), fps=30)
    return time.perf_counter() - start, out.stat().st_size, frames


def main() -> None:
    animation = Animation(compile_script(parse_file(SHOW), seed=0))
    renderer = Renderer(Theme.default().layers((1024, 600)))
    with tempfile.TemporaryDirectory() as tmp:
        gif_seconds, gif_size, frames = timed(animation, renderer, Path(tmp) / "show.gif")
        raw = frames * 1024 * 600 * 3
        print(
            f"the {animation.duration:.1f} s show at 1024x600, 30 fps "
            f"({frames} frames, {raw / 1e6:.0f} MB raw)"
        )
        print(f"  {'.gif (baseline)':<16} {gif_seconds:6.2f} s  {gif_size / 1e6:7.2f} MB")
        for ext in FORMATS:
            try:
                seconds, size, _ = timed(animation, renderer, Path(tmp) / f"show{ext}")
            except MissingTool as e:
                print(f"  {ext:<16} skipped: {e}")
                continue
            print(
                f"  {ext:<16} {seconds:6.2f} s  {size / 1e6:7.2f} MB  "
                f"time {seconds / animation.duration:4.0%} of the show, size {size / gif_size:4.0%} of "
                f"the GIF, {size / raw:5.1%} of raw"
            )


if __name__ == "__main__":
    main()
