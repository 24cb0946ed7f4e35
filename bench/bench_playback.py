"""Playback keeps time: a 10 s script, played in real time, against a naive loop.

    python bench/bench_playback.py

Ours: `LivePlayer` (what `play` runs), which schedules frame i at start + i/fps, the script on a
live session stepped in real time. Baseline, in the same run: render a frame, show it, sleep
1/fps (the loop a first attempt writes), which falls behind by each frame's own cost. Both draw
into a terminal screen writing to /dev/null at 1024x600.
"""

from __future__ import annotations

import os
import time

from baxterface_cli import parse
from baxterface_cli.drawing.renderer import Renderer
from baxterface_cli.drawing.theme import Theme
from baxterface_cli.engine.animation import Animation
from baxterface_cli.engine.compiler import compile_script
from baxterface_cli.engine.live_session import LiveSession
from baxterface_cli.play.live_player import LivePlayer
from baxterface_cli.play.screens import TerminalScreen

SCRIPT = "repeat 5 { look 60 -40 in 1s ease-in-out; blink; look -60 40 in 0.5s }"
FPS = 30


def main() -> None:
    animation = Animation(compile_script(parse(SCRIPT), seed=0), idle=True)
    layers = Theme.default().layers((1024, 600))
    with open(os.devnull, "w") as sink:
        session = LiveSession(parse(SCRIPT), seed=0, keep_up=True)
        player = LivePlayer(session, Renderer(layers), TerminalScreen(sink, 120, 40), FPS)
        played = player.run()

        renderer, screen = Renderer(layers), TerminalScreen(sink, 120, 40)
        start = time.monotonic()
        for t in animation.timeline.frame_times(FPS):
            screen.show(renderer.render(animation.sample(t)), "")
            time.sleep(1 / FPS)
        naive = time.monotonic() - start

    frame = 1 / FPS
    print(f"script: {animation.duration:.2f} s at {FPS} fps (one frame = {frame * 1000:.1f} ms)")
    print(
        f"  baxterface play: {played:.3f} s, off by {(played - animation.duration) * 1000:+.1f} ms, "
        f"{player.frames_shown} frames"
    )
    print(f"  naive loop:      {naive:.3f} s, off by {(naive - animation.duration) * 1000:+.1f} ms")
    ratio = abs(naive - animation.duration) / max(abs(played - animation.duration), 1e-3)
    print(f"  ratio of errors: {ratio:.0f}x")


if __name__ == "__main__":
    main()
