"""Frames per second of the renderer against the original method, in one run.

    python bench/bench_render.py [--frames N]

The baseline is how the original node drew every frame: copy the background
and PIL-paste the five other full-screen RGBA layers onto it (eyes and lids
at their offsets), then hand the image over as a numpy array. Each figure is
the best of three timed runs, the baseline's and baxterface's taken in turn;
ratios are against the baseline measured here, at the same size, in this same
run.

"eyes move, through Face" is a look as a program makes it with the Python API:
`face.look_at(x, y)` then `face.frame()`, the frame let go before the next
(published, say), on the same eye positions as the baseline's.
"""

from __future__ import annotations

import argparse
import math
import time
from typing import Callable, Dict, List, Tuple

import numpy as np
from PIL import Image

from baxterface_cli import Face, FaceState, Parts
from baxterface_cli.core.face_constants import EMOTIONS
from baxterface_cli.drawing.pose import pose
from baxterface_cli.drawing.renderer import Renderer
from baxterface_cli.drawing.theme import Theme


class Original:
    """The original node's way: six full-screen PIL layers pasted per frame."""

    def __init__(self, theme: Theme, size: Tuple[int, int]) -> None:
        placed = theme.placed_at(size)

        def full(key):
            layer = Image.new("RGBA", size)
            layer.paste(placed[key].image, placed[key].anchor)
            return layer

        self.background = full(("background", "background"))
        self.eyes = full(("eyes", "eyes"))
        self.lids = full(("eyelids", "eyelids"))
        self.parts = {key: full(key) for key in placed if key[0] in ("skin", "mouth", "brows")}
        self.layers = theme.layers(size)

    def render(self, state: FaceState) -> np.ndarray:
        at = pose(self.layers, state)
        img = self.background.copy()
        img.paste(self.eyes, (at.eye_dx, at.eye_dy), self.eyes)
        # The original moved its one lids layer by one offset: every lid's, as no eye winks here.
        img.paste(self.lids, (0, at.lid_dy[0]), self.lids)
        for key in (("skin", str(state.skin)), ("mouth", state.mouth), ("brows", state.brows)):
            layer = self.parts[key]
            img.paste(layer, (0, 0), layer)
        return np.asarray(img)


def eyes_moving(n: int) -> List[FaceState]:
    return [FaceState(eye_x=60 * math.sin(i / 9), eye_y=45 * math.cos(i / 13)) for i in range(n)]


def lids_moving(n: int) -> List[FaceState]:
    # Blinks: close in 9 frames, open in 6, as at 30 fps (0.3 s and 0.2 s).
    cycle = [1 - k / 9 for k in range(9)] + [k / 6 for k in range(6)]
    return [FaceState(eyelids=cycle[i % len(cycle)]) for i in range(n)]


def emotions_changing(n: int) -> List[FaceState]:
    names = [e for e in EMOTIONS]
    out = []
    for i in range(n):
        name = names[i % len(names)]
        spec = EMOTIONS[name]
        mouth, brows = EMOTIONS[name].variants[0]
        out.append(FaceState(spec.skin, mouth, brows, eyelids=spec.eyelids))
    return out


def crossfading(a: Parts, b: Parts, n: int) -> List[FaceState]:
    return [FaceState(*b, eye_x=i % 20, fade_from=a, fade=(i % 7) / 7) for i in range(n)]


def through_face(face: Face) -> Callable[[FaceState], np.ndarray]:
    """A look through the Face API: the state's eye position set, then its frame."""

    def draw(state: FaceState) -> np.ndarray:
        face.look_at(state.eye_x, state.eye_y)
        return face.frame()

    return draw


def fps(
    renders: Dict[str, Callable[[FaceState], np.ndarray]], states: List[FaceState], runs: int = 3
) -> Dict[str, float]:
    """Frames per second of each way of drawing, the best of `runs` runs, taken in turn (one run
    of each, then again), so that a shared machine's load falls on all of them alike."""
    for render in renders.values():
        render(states[0])  # warm up: first-use costs are measured separately
    best = dict.fromkeys(renders, math.inf)
    for _ in range(runs):
        for name, render in renders.items():
            start = time.perf_counter()
            for state in states:
                render(state)
            best[name] = min(best[name], time.perf_counter() - start)
    return {name: len(states) / seconds for name, seconds in best.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frames", type=int, default=300)
    args = parser.parse_args()
    theme = Theme.default()
    rows: List[Tuple[str, str, float, float]] = []
    for size in [(1024, 600), (1920, 1200)]:
        original = Original(theme, size)
        label = f"{size[0]}x{size[1]}"
        scenarios: Dict[str, List[FaceState]] = {
            "eyes move": eyes_moving(args.frames),
            "lids move (blinks)": lids_moving(args.frames),
            "emotion changes every frame": emotions_changing(args.frames),
        }
        if size == (1024, 600):
            smile, grin, angry = (
                Parts(2, "smile", "normal"),
                Parts(2, "teeth", "raised"),
                Parts(4, "angry", "angry"),
            )
            scenarios["crossfade, same skin"] = crossfading(smile, grin, args.frames)
            scenarios["crossfade, skin changes"] = crossfading(smile, angry, args.frames // 3)
        for name, states in scenarios.items():
            renderer, copier = Renderer(theme.layers(size)), Renderer(theme.layers(size))
            ways = {
                "original": original.render,
                "": renderer.render,
                ", frame copied": lambda s, r=copier: r.render(s).copy(),
            }
            if name == "eyes move":
                ways[", through Face"] = through_face(Face(theme, size))
            measured = fps(ways, states)
            base = measured.pop("original")
            rows += [(label, name + way, base, figure) for way, figure in measured.items()]
    # First use of a part combination (a cold cache): the top stack is built.
    layers = theme.layers((1024, 600))
    start = time.perf_counter()
    combos = [Parts(s, m, b) for s in range(3) for m in ("smile", "sad") for b in ("normal", "angry")]
    renderer = Renderer(layers)
    for parts in combos:
        renderer.render(FaceState(*parts))
    cold = (time.perf_counter() - start) / len(combos) * 1000

    print(f"{'size':<10} {'frames':<38} {'original fps':>12} {'baxterface fps':>15} {'ratio':>7}")
    for label, name, base, ours in rows:
        print(f"{label:<10} {name:<38} {base:>12.0f} {ours:>15.0f} {ours / base:>6.1f}x")
    print(f"first frame of a new part combination at 1024x600: {cold:.1f} ms")


if __name__ == "__main__":
    main()
