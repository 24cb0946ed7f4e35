"""Render an animation to files: a folder of PNGs, an animated GIF, or one PNG."""

from __future__ import annotations

from pathlib import Path
from typing import Callable, List, Optional

import numpy as np

from .idle import Animation
from .output import GifWriter, PngFolder, build_palette, write_png
from .partial import remove_stale
from .renderer import Renderer

Progress = Callable[[int, int], None]  # (frames done, frames in all)


def output_kind(path: str) -> str:
    """ "folder", "gif" or "png", from how the user wrote the path."""
    if not path:
        # Path("") is the current folder: an empty variable would render there.
        raise ValueError("--out is empty; give DIR/ (./ for this folder), FILE.gif or FILE.png")
    if path.endswith(("/", "\\")) or Path(path).is_dir():
        return "folder"
    suffix = Path(path).suffix.lower()
    if suffix in (".gif", ".png"):
        return suffix[1:]
    raise ValueError(f"--out must end in .gif or .png, or name a folder (end it with '/'), not {path!r}")


def palette_times(animation: Animation) -> List[float]:
    """Moments that between them show every colour the animation uses."""
    times = {0.0, animation.duration}
    previous = animation.timeline.initial.skin
    for change in animation.timeline.parts:
        times.add(change.at + change.fade)
        if change.parts.skin != previous:  # blends of two skins have colours of their own
            times.update(change.at + change.fade * k for k in (0.25, 0.5, 0.75))
        previous = change.parts.skin
    return sorted(times)[:40]


def render(
    animation: Animation,
    renderer: Renderer,
    out: str,
    fps: float = 30.0,
    at: Optional[float] = None,
    progress: Optional[Progress] = None,
) -> int:
    """Write the animation to `out`; returns the number of frames written."""
    kind = output_kind(out)
    path = Path(out)
    # Partials are written beside the target: for a folder, beside the folder.
    path.parent.mkdir(parents=True, exist_ok=True)
    remove_stale(path.parent)
    if kind == "png":
        t = animation.duration if at is None else min(at, animation.duration)  # idle runs on past it
        write_png(path, renderer.render(animation.sample(t)))
        if progress:
            progress(1, 1)
        return 1
    times = animation.timeline.frame_times(fps)
    if kind == "gif":
        palette = build_palette(
            [
                np.ascontiguousarray(renderer.render(animation.sample(t))[..., ::-1])
                for t in palette_times(animation)
            ]
        )
        sink = GifWriter(path, renderer.size, fps, palette)
    else:
        sink = PngFolder(path)
    try:
        for i, t in enumerate(times):
            sink.add(renderer.render(animation.sample(t)))
            if progress:
                progress(i + 1, len(times))
        sink.close()
    except BaseException:
        sink.abort()
        raise
    return len(times)
