"""GIF rendering: time and size for the 20 s show, against Pillow's plain way.

    python bench/bench_gif.py

Ours: `baxterface render show.face --out show.gif` (30 fps, 1024x600), timed
in full. Baseline, in the same run: each frame quantized to the same palette
by Pillow and saved with `save_all` (Pillow then stores each frame's changed
rectangle itself), on the first 150 frames, compared per frame.
"""

from __future__ import annotations

import io
import tempfile
import time
from pathlib import Path

import numpy as np
from PIL import Image

from baxterface_cli import parse_file
from baxterface_cli.drawing.renderer import Renderer
from baxterface_cli.drawing.theme import Theme
from baxterface_cli.engine.animation import Animation
from baxterface_cli.engine.compiler import compile_script
from baxterface_cli.export.png_gif import build_palette
from baxterface_cli.export.render_to_file import palette_times, render

SHOW = Path(__file__).resolve().parent.parent / "scripts_examples" / "show.face"
SAMPLE = 150


def main() -> None:
    animation = Animation(compile_script(parse_file(SHOW), seed=0))
    layers = Theme.default().layers((1024, 600))
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "show.gif"
        start = time.perf_counter()
        frames = render(animation, Renderer(layers), str(out), fps=30)
        ours = time.perf_counter() - start
        size = out.stat().st_size

        renderer = Renderer(layers)
        times = animation.timeline.frame_times(30)[:SAMPLE]
        start = time.perf_counter()
        palette = build_palette(
            [
                np.ascontiguousarray(renderer.render(animation.sample(t))[..., ::-1])
                for t in palette_times(animation)
            ]
        )
        swatch = Image.new("P", (1, 1))
        swatch.putpalette(palette.tobytes())
        images = [
            Image.fromarray(np.ascontiguousarray(renderer.render(animation.sample(t))[..., ::-1])).quantize(
                palette=swatch, dither=Image.NONE
            )
            for t in times
        ]
        buffer = io.BytesIO()
        images[0].save(buffer, "GIF", save_all=True, append_images=images[1:], duration=33, loop=0)
        plain = time.perf_counter() - start

    per_ours, per_plain = ours / frames, plain / SAMPLE
    print(f"show.face: {animation.duration:.1f} s, {frames} frames at 30 fps, 1024x600")
    print(f"  baxterface render: {ours:.2f} s ({per_ours * 1000:.1f} ms a frame), {size / 1e6:.2f} MB")
    print(
        f"  Pillow, plain:     {per_plain * 1000:.1f} ms a frame ({SAMPLE} frames), "
        f"{per_plain * frames:.1f} s for the show"
    )
    print(f"  ratio: {per_plain / per_ours:.1f}x faster per frame")


if __name__ == "__main__":
    main()
