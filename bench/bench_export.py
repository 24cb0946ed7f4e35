"""Export: the 20-second show as MP4, WebM, WebP, APNG and a ROS bag, against its GIF.

    python bench/bench_export.py

Each format is rendered in full (1024x600, 30 fps) by `render`, as `baxterface
render show.face --out show.EXT` does, and timed. The baseline, in the same
run, is the GIF of the same show; sizes are also given against the raw
frames (1024 x 600 x 3 bytes each). Goals: the MP4 in at most half the show's
length and at most 40 % of the GIF's size; the bag at most 10 % of its raw frames.

Where ROS is installed (`roscore`, `rosbag` and Debian's python3 with rospy), the
bag is then played three times by `rosbag play` against a roscore of its own, and a listener
in its own process reports how far each frame arrives from its time in the
script (goal: within one frame, 33 ms).
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import tempfile
import time
from pathlib import Path

from ros_master import start_roscore

from baxterface_cli import parse_file
from baxterface_cli.drawing.renderer import Renderer
from baxterface_cli.drawing.theme import Theme
from baxterface_cli.engine.animation import Animation
from baxterface_cli.engine.compiler import compile_script
from baxterface_cli.export.render_to_file import render
from baxterface_cli.extras import MissingTool

ROOT = Path(__file__).resolve().parent.parent
SHOW = ROOT / "scripts_examples" / "show.face"
FORMATS = [".mp4", ".webm", ".webp", ".apng", ".bag"]
ROS_PYTHON = "/usr/bin/python3"  # Debian's, which has rospy
LISTENER = """
import json, sys, time
import rospy
from sensor_msgs.msg import Image
got = []
rospy.init_node("bench_listener", anonymous=True, disable_signals=True)
# A buffer that holds a whole frame: rospy's default one delays big messages.
rospy.Subscriber("/robot/xdisplay", Image, lambda m: got.append((m.header.stamp.to_sec(), time.monotonic())),
                 queue_size=1000, buff_size=1 << 25)
print("ready", flush=True)
sys.stdin.read()  # until the bag has played
time.sleep(0.5)
print(json.dumps(got), flush=True)
"""


def timed(animation: Animation, renderer: Renderer, out: Path):
    start = time.perf_counter()
    frames = render(animation, renderer, str(out), fps=30)
    return time.perf_counter() - start, out.stat().st_size, frames


def can_play_bags() -> bool:
    if not (shutil.which("roscore") and shutil.which("rosbag") and os.path.exists(ROS_PYTHON)):
        return False
    return subprocess.run([ROS_PYTHON, "-c", "import rospy"], capture_output=True).returncode == 0


def play_bag(bag: Path, home: str) -> None:
    """`rosbag play` the bag to a listener; print how far frames arrive from their times."""
    core, env = start_roscore(home)
    try:
        listener = subprocess.Popen(
            [ROS_PYTHON, "-c", LISTENER], env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True
        )
        assert listener.stdout.readline().strip() == "ready"
        # --delay: time for the listener to connect before the first frame.
        subprocess.run(
            ["rosbag", "play", "--quiet", "--delay", "0.5", str(bag)],
            env=env,
            check=True,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        got = json.loads(listener.communicate("", timeout=120)[0].splitlines()[-1])
    finally:
        core.send_signal(signal.SIGINT)
        core.wait()
    # Against the quickest frame, so ROS's constant cost of moving a frame is left out.
    offsets = [arrived - stamp for stamp, arrived in got]
    late = sorted((offset - min(offsets)) * 1000 for offset in offsets)
    print(
        f"rosbag play of the bag: {len(got)} frames heard, later than their time in the script by "
        f"median {late[len(late) // 2]:.1f} ms, p95 {late[int(len(late) * 0.95)]:.1f} ms, "
        f"max {late[-1]:.1f} ms (goal: 33 ms)"
    )


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
        bag = Path(tmp) / "show.bag"
        if not bag.exists():
            return
        if not can_play_bags():
            print("rosbag play: skipped (needs roscore, rosbag and Debian's python3 with rospy)")
            return
        for _ in range(3):  # a busy moment on 2 cores shows as one slow play of three
            play_bag(bag, str(Path(tmp) / "ros_home"))


if __name__ == "__main__":
    main()
