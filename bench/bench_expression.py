"""The continuous face: rendering a mood sweep against a look sweep, in one run.

    python bench/bench_expression.py [--runs N] [--profile]

Each script lasts 20 s and is rendered to MP4 at 1024x600, 30 fps, as `baxterface render
FILE --out x.mp4` does (the CLI's own animation and theme, a fresh renderer, the same
`render`), and the `render` call is timed. The baseline, in the same run, is a look sweep:
the eyes move every frame and nothing else does. Against it, a mood sweep round the mood
circle, whose expression (mouth, brows, lids and skin) differs in every frame. The two run
`--runs` times, interleaved, and each figure is the median; a sweep of `mouth curve` alone
and `happy` in steps of 0.1 are rendered once each, between them. Ratios are given of the
wall-clock time and of this process's CPU time (the video encoder's threads included),
which another busy process on the machine disturbs less. Goal: mood / look at most 1.5x.

What changes from frame to frame is counted first, as the renderer sees it: the eyes (a
new pose) and each drawn part (a new key: skin, mouth, brows).

With --profile, instead: each script, and a `skin tint` sweep, rendered once with
wall-clock timers round the renderer's and the writer's steps (each step's own time, nested
steps taken out), then the mood sweep once more under cProfile.
"""

from __future__ import annotations

import argparse
import cProfile
import pstats
import statistics
import tempfile
import time
from collections import defaultdict
from pathlib import Path
from typing import Dict, List, Tuple

from baxterface_cli.cli.app import DEFAULT_SEED, fitted_theme
from baxterface_cli.cli.events_option import session_animation
from baxterface_cli.core.presets import expression_of
from baxterface_cli.drawing.pose import pose
from baxterface_cli.drawing.renderer import Renderer
from baxterface_cli.engine.animation import Animation
from baxterface_cli.export.registry import format_for
from baxterface_cli.export.render_to_file import frame_times, render
from baxterface_cli.language.parser import parse

FPS = 30.0
LOOK = "look sweep (baseline)"
MOOD = "mood sweep"
HAPPY_STEPS = [k / 10 for k in range(1, 11)] + [k / 10 for k in range(9, -1, -1)]
SCRIPTS: Dict[str, str] = {
    LOOK: "repeat 10 { look 60 0 in 1s; look -60 0 in 1s }",
    # Pleasant, excited, unpleasant, calm and round again, linearly: every frame a new expression.
    MOOD: "repeat 5 { mood 1 0 in 1s; mood 0 1 in 1s; mood -1 0 in 1s; mood 0 -1 in 1s }",
    # The default face's mouth curve is 1: down first, so that every frame moves it.
    "mouth curve sweep": "repeat 10 { mouth curve -1 in 1s; mouth curve 1 in 1s }",
    # Each step 1 s: a 0.3 s morph (happy's lids stay open), then held.
    "happy 0.1 .. 1 .. 0 in steps": "\n".join(f"happy {k:g}; wait 0.7s" for k in HAPPY_STEPS),
}
EXTRAS = [name for name in SCRIPTS if name not in (LOOK, MOOD)]
# Profiled too: the skin's colour alone, which changes every pixel of the face.
PROFILED = {**SCRIPTS, "skin tint sweep": "repeat 10 { skin tint 0 in 1s; skin tint 4 in 1s }"}


def animation(name: str) -> Animation:
    return session_animation(parse(PROFILED[name], name), None, DEFAULT_SEED, False, None, None, "bench")[0]


def layers():
    return fitted_theme(None, None, "render")  # the default theme at 1024x600, as `render` gets it


def changes(name: str) -> Tuple[int, Dict[str, int]]:
    """Frame-to-frame steps, and in how many of them each thing the renderer draws changes."""
    anim, fitted = animation(name), layers()
    fmt = format_for("x.mp4")
    states = [anim.sample(t) for t in frame_times(fmt, anim, FPS, None)]
    counts: Dict[str, int] = defaultdict(int)
    previous = None
    for state in states:
        expression = expression_of(state)
        now = (pose(fitted, state), expression, fitted.drawn.keys(expression))
        if previous is not None:
            counts["eyes"] += (now[0].eye_dx, now[0].eye_dy) != (previous[0].eye_dx, previous[0].eye_dy)
            counts["expression"] += now[1] != previous[1]
            for part in ("skin", "mouth", "brows"):
                counts[part] += getattr(now[2], part) != getattr(previous[2], part)
        previous = now
    return len(states) - 1, counts


def timed(name: str, folder: Path) -> Tuple[float, float]:
    """Wall-clock seconds of the render, and this process's CPU seconds (the encoder's threads too)."""
    anim, renderer = animation(name), Renderer(layers())  # a fresh renderer, as each `render` has
    start, cpu = time.perf_counter(), time.process_time()
    render(anim, renderer, str(folder / "out.mp4"), fps=FPS)
    return time.perf_counter() - start, time.process_time() - cpu


def measure(runs: int) -> None:
    print(f"20 s scripts, rendered to MP4 at 1024x600, {FPS:.0f} fps, as `baxterface render` does")
    print("what changes from one frame to the next, as the renderer sees it:")
    for name in SCRIPTS:
        steps, counts = changes(name)
        print(
            f"  {name:<30} of {steps} steps: eyes {counts['eyes']:>3}, expression "
            f"{counts['expression']:>3}; drawn anew: skin {counts['skin']:>3}, mouth {counts['mouth']:>3}, "
            f"brows {counts['brows']:>3}"
        )
    times: Dict[str, List[Tuple[float, float]]] = defaultdict(list)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        # Warm up: PyAV's import and the theme's skins drawn once, costs a process pays once.
        render(
            session_animation(parse("mood 1 0 in 0.2s"), None, 0, False, None, None, "bench")[0],
            Renderer(layers()),
            str(folder / "w.mp4"),
        )
        for i in range(runs):
            for name in (LOOK, MOOD):
                times[name].append(timed(name, folder))
            if i < len(EXTRAS):
                times[EXTRAS[i]].append(timed(EXTRAS[i], folder))
        for name in EXTRAS[runs:]:
            times[name].append(timed(name, folder))
    base = statistics.median(wall for wall, _ in times[LOOK])
    base_cpu = statistics.median(cpu for _, cpu in times[LOOK])
    frames = round(20 * FPS)
    print(f"render time: wall-clock seconds of each run in order, then medians ({runs} runs of each sweep)")
    for name in SCRIPTS:
        walls, cpus = [w for w, _ in times[name]], [c for _, c in times[name]]
        runs_text = "  ".join(f"{t:6.2f}" for t in walls)
        wall, cpu = statistics.median(walls), statistics.median(cpus)
        print(
            f"  {name:<30} {runs_text:<24} median {wall:6.2f} s ({wall / frames * 1000:5.1f} ms a frame) "
            f"{wall / base:5.1f}x;  CPU {cpu:6.2f} s {cpu / base_cpu:5.1f}x"
        )
    mood = times[MOOD]
    print(
        f"mood / look: {statistics.median(w for w, _ in mood) / base:.2f}x wall-clock, "
        f"{statistics.median(c for _, c in mood) / base_cpu:.2f}x CPU time (goal: at most 1.5x)"
    )


class Sections:
    """Wall-clock time of each wrapped function, its wrapped callees' time taken out."""

    def __init__(self) -> None:
        self.own: Dict[str, float] = defaultdict(float)
        self.calls: Dict[str, int] = defaultdict(int)
        self._stack: List[float] = []
        self._wrapped: List[Tuple[object, str, object]] = []

    def wrap(self, owner, attr: str, name: str) -> None:
        fn = getattr(owner, attr)
        self._wrapped.append((owner, attr, owner.__dict__[attr]))

        def timed_call(*args, **kwargs):
            start = time.perf_counter()
            self._stack.append(0.0)
            try:
                return fn(*args, **kwargs)
            finally:
                total = time.perf_counter() - start
                self.own[name] += total - self._stack.pop()
                self.calls[name] += 1
                if self._stack:
                    self._stack[-1] += total

        setattr(owner, attr, timed_call)

    def unwrap(self) -> None:
        for owner, attr, original in reversed(self._wrapped):
            setattr(owner, attr, original)


def profile() -> None:
    from baxterface_cli.drawing import renderer
    from baxterface_cli.engine import animation as animation_module
    from baxterface_cli.export import video

    fitted = layers()
    with tempfile.TemporaryDirectory() as tmp:
        out = str(Path(tmp) / "mood.mp4")
        warm_up = session_animation(parse("mood 1 0 in 0.2s"), None, 0, False, None, None, "bench")[0]
        render(warm_up, Renderer(fitted), out)

        steps = [
            (video.PyAvVideo, "add", "encoding: PyAvVideo.add"),
            (animation_module.Animation, "sample", "Animation.sample"),
            # The part books draw what they have not kept: DrawnParts._skin, _mouth, _brows.
            (fitted.skins, "_draw", "DrawnParts._skin"),
            (fitted.mouths, "_draw", "DrawnParts._mouth"),
            (fitted.brows, "_draw", "DrawnParts._brows"),
            (renderer, "skin_stack", "renderer.skin_stack"),
            (renderer, "socket_boxes", "renderer.socket_boxes"),
            (renderer._Canvas, "__init__", "renderer._Canvas.__init__"),
            (renderer.Renderer, "render", "Renderer.render, the rest"),
        ]
        measured: Dict[str, Tuple[float, Sections]] = {}
        for name in PROFILED:
            sections = Sections()
            for owner, attr, step in steps:
                sections.wrap(owner, attr, step)
            start = time.perf_counter()
            render(animation(name), Renderer(fitted), out, fps=FPS)
            measured[name] = (time.perf_counter() - start, sections)
            sections.unwrap()
        print("wall-clock seconds of each step, its timed callees taken out (no profiler)")
        short = {LOOK: "look", MOOD: "mood", EXTRAS[0]: "mouth curve", EXTRAS[1]: "happy steps"}
        short["skin tint sweep"] = "skin tint"
        print(f"  {'step':<28}" + "".join(f"{short[n]:>12}" for n in PROFILED) + "  mood's share, calls")
        mood_total, mood_sections = measured[MOOD]

        def own(name: str, step: str) -> float:
            total, sections = measured[name]
            if step == "everything else":
                return total - sum(sections.own.values())
            return sections.own.get(step, 0.0)

        for step in [step for _, _, step in steps] + ["everything else"]:
            cells = "".join(f"{own(name, step):12.2f}" for name in PROFILED)
            calls = mood_sections.calls.get(step, "")
            print(f"  {step:<28}{cells}  {own(MOOD, step) / mood_total:6.1%} {calls:>5}")
        print(f"  {'in all':<28}" + "".join(f"{measured[n][0]:12.2f}" for n in PROFILED))

        profiler = cProfile.Profile()
        profiler.enable()
        render(animation(MOOD), Renderer(fitted), out, fps=FPS)
        profiler.disable()
    stats = pstats.Stats(profiler)
    entries = stats.stats  # type: ignore[attr-defined]
    whole = max(ct for (_, _, _, ct, _) in entries.values())
    print(f"the same under cProfile: {whole:.2f} s (the profiler slows Python-heavy code most)")

    def label(key) -> str:
        path, line, func = key
        short = path.split("baxterface_cli/")[-1] if "baxterface_cli/" in path else Path(path).name
        return f"{short}:{line}({func})" if line else func

    for title, index in (("own time (tottime)", 2), ("with callees (cumtime)", 3)):
        print(f"  top 20 by {title}: calls, seconds, share of the render")
        top = sorted(entries.items(), key=lambda kv: -kv[1][index])[:20]
        for key, (_, calls, tt, ct, _) in top:
            seconds = tt if index == 2 else ct
            print(f"    {label(key)[:70]:<70} {calls:>7} {seconds:7.2f} s {seconds / whole:6.1%}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--profile", action="store_true", help="profile the mood sweep instead")
    args = parser.parse_args()
    if args.profile:
        profile()
    else:
        measure(args.runs)


if __name__ == "__main__":
    main()
