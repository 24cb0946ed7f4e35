"""The face node on a real ROS master (loopback): latency, frame rate, idle cost.

    .venv-ros/bin/python bench/bench_node.py

Starts its own roscore on a free port, then the node (`baxterface node`) as
its own process, and measures from a third one (this):

- latency: from a command on display_chatter (`skin_1` / `skin_3`, which
  change the face at once) to the first changed frame received here; the
  baseline, measured in this run, is a relay that answers each command with
  a frame it already holds: ROS's own cost of moving 1.8 MB;
- first motion: from `look_60_0` (a 0.5 s move) to the first frame showing
  the eyes moving, beside a jump (`look_60_0_0`), which shows at once;
- the continuous face's statements (`happy 0.4`, a blend, a timed `mood`, `wink left`,
  a timed `mouth curve`), each sent to a still default face, to its first changed
  frame; beside it, when the statement's own timeline first changes the picture (an
  untimed emotion moves the lids first, for 0.3 s, so its face changes only then);
- frame rate reaching a subscriber during a 30 fps look animation whose
  every frame differs (the node sends no frame that did not change);
- an idle face (idle blinks on): frames a second between blinks, and the
  node's CPU use.
"""

from __future__ import annotations

import os
import signal
import statistics
import subprocess
import sys
import threading
import time
from pathlib import Path

from ros_master import start_roscore

from baxterface_cli.core.face_constants import LIMITS
from baxterface_cli.core.presets import expression_of
from baxterface_cli.drawing.pose import pose
from baxterface_cli.drawing.theme import Theme
from baxterface_cli.engine.animation import Animation
from baxterface_cli.engine.compiler import compile_script
from baxterface_cli.language.parser import parse

ROOT = Path(__file__).resolve().parent.parent
RELAY = """
import sys, rospy, numpy
from std_msgs.msg import String
from sensor_msgs.msg import Image
rospy.init_node("relay")
frame = Image(height=600, width=1024, encoding="bgr8", step=3072, data=bytes(1024 * 600 * 3))
pub = rospy.Publisher("/robot/xdisplay", Image, latch=True, queue_size=1)
rospy.Subscriber("/display_chatter", String, lambda m: pub.publish(frame))
rospy.spin()
"""
# The continuous face's statements, each with what brings the face back to `default` before
# it (at once): the face is still when each is sent, so the first frame after it is its own.
STATEMENTS = [
    ("happy 0.4", "default in 0s"),
    ("happy 0.6 + confused 0.4", "default in 0s"),
    ("mood 0.6 -0.2 in 0.5s", "mood 0 0 in 0s"),  # `mood 0 0` ends the mood, with the default face
    ("wink left", "default in 0s"),
    ("mouth curve -0.5 in 0.3s", "default in 0s"),
]


class Frames:
    def __init__(self, rospy, Image) -> None:
        self.times = []
        self.event = threading.Event()
        self.sub = rospy.Subscriber("/robot/xdisplay", Image, self._got, queue_size=10, buff_size=2**24)

    def _got(self, msg) -> None:
        self.times.append(time.monotonic())
        self.event.set()


def latencies(rospy, String, frames, commands=("skin_3", "skin_1"), count=120, gap=0.15):
    """Milliseconds from each command to the first frame that reaches us after it."""
    pub = rospy.Publisher("/display_chatter", String, queue_size=10)
    time.sleep(1.0)
    out = []
    for i in range(count):
        frames.event.clear()
        sent = time.monotonic()
        pub.publish(String(commands[i % len(commands)]))
        if frames.event.wait(2.0):
            out.append((frames.times[-1] - sent) * 1000)
        time.sleep(gap)  # the move ends (a timed look lasts 0.5 s) before the next command
    pub.unregister()
    return out


def own_timing(command: str, reset: str):
    """The statement's length, and when its own timeline first changes the picture (ms).

    From the face the reset leaves; a change is one the renderer draws: the eyes or lids
    moved a pixel, or a drawn part's key changed.
    """
    layers = Theme.default().layers((1024, 600))

    def look(state):
        return pose(layers, state), layers.drawn.keys(expression_of(state))

    before = Animation(compile_script(parse(reset), seed=0))
    still = look(before.sample(before.duration))
    animation = Animation(compile_script(parse(command), seed=0))
    steps = int(animation.duration * 1000) + 1
    first = next((ms for ms in range(steps) if look(animation.sample(ms / 1000)) != still), None)
    return animation.duration, first


def settle(frames, still=0.15, limit=3.0):
    """Wait until no frame has come for `still` seconds (at most `limit`): the face is still."""
    start = time.monotonic()
    time.sleep(still)
    while time.monotonic() - start < limit:
        last = frames.times[-1] if frames.times else 0.0
        wait = last + still - time.monotonic()
        if wait <= 0:
            return
        time.sleep(wait)


def statement_latencies(rospy, String, frames, count=30):
    """Milliseconds from each statement, sent to a still face, to the first frame after it.

    The statements take turns, so each is measured under the same conditions.
    """
    pub = rospy.Publisher("/display_chatter", String, queue_size=10)
    time.sleep(1.0)
    lengths = {command: own_timing(command, reset)[0] for command, reset in STATEMENTS}
    out = {command: [] for command, _ in STATEMENTS}
    for _ in range(count):
        for command, reset in STATEMENTS:
            pub.publish(String(reset))
            settle(frames)
            frames.event.clear()
            seen = len(frames.times)
            sent = time.monotonic()
            pub.publish(String(command))
            if frames.event.wait(2.0) and len(frames.times) > seen:
                out[command].append((frames.times[seen] - sent) * 1000)
            time.sleep(max(0.0, sent + lengths[command] - time.monotonic()))
            settle(frames)
    pub.unregister()
    return out


def rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return 0.0


def flood_figures(node, chatter, String, frames, env, seconds=10.0):
    """A flood of good, bad and maximum-size commands while the eyes move; then SIGTERM under load.

    The flood comes from a process of its own (tests/support/flooder.py), so this one
    only receives frames: the gaps are the node's.
    """
    chatter.publish(String("repeat 100 { look 60 0 in 1s; look -60 0 in 1s }"))
    time.sleep(1.0)
    before, start = rss_mb(node.pid), len(frames.times)
    flood = [sys.executable, str(ROOT / "tests" / "support" / "flooder.py"), str(seconds)]
    rate = float(subprocess.run(flood, env=env, check=True, capture_output=True, text=True).stdout)
    times = frames.times[start:]
    gap = max((b - a for a, b in zip(times, times[1:])), default=float("inf"))
    after = rss_mb(node.pid)
    huge = "look 40 -20 in 0.05s; look -40 20 in 0.05s\n" * (LIMITS.max_pieces // 12)
    for _ in range(20):
        chatter.publish(String(huge))
    stop = time.monotonic()
    node.send_signal(signal.SIGTERM)
    node.wait()
    return rate, gap * 1000, before, after, time.monotonic() - stop


def cpu_seconds(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def percentile(values, p):
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(round(p / 100 * (len(ordered) - 1))))]


def main() -> None:
    core, env = start_roscore()
    os.environ.update(ROS_MASTER_URI=env["ROS_MASTER_URI"], ROS_IP="127.0.0.1")
    import rospy
    from sensor_msgs.msg import Image
    from std_msgs.msg import String

    rospy.init_node("bench_face", anonymous=True, disable_signals=True)
    frames = Frames(rospy, Image)
    try:
        relay = subprocess.Popen([sys.executable, "-c", RELAY], env=env)
        time.sleep(2.0)
        floor = latencies(rospy, String, frames)
        relay.send_signal(signal.SIGINT)
        relay.wait()

        node = subprocess.Popen(
            [sys.executable, "-m", "baxterface_cli", "node", "_idle:=false"], cwd=str(ROOT), env=env
        )
        time.sleep(4.0)
        ours = latencies(rospy, String, frames)
        # A jump shows at once; a timed move (0.5 s) must show its first motion as soon.
        jumps = latencies(rospy, String, frames, ("look_60_0_0", "look_-60_0_0"), count=60, gap=0.3)
        moves = latencies(rospy, String, frames, ("look_60_0", "look_-60_0"), count=60, gap=0.8)
        statements = statement_latencies(rospy, String, frames)

        chatter = rospy.Publisher("/display_chatter", String, queue_size=10)
        time.sleep(0.5)
        chatter.publish(String("look -60 40 in 0s"))
        time.sleep(0.5)
        start = len(frames.times)
        # Eyes a few pixels further every frame, so every frame differs.
        chatter.publish(String("repeat 3 { look 60 -40 in 1s; look -60 40 in 1s }"))
        time.sleep(6.0)
        window = [t for t in frames.times[start:]]
        look_fps = (len(window) - 1) / (window[-1] - window[0]) if len(window) > 1 else 0.0
        flood = flood_figures(node, chatter, String, frames, env)

        idle = subprocess.Popen(
            [sys.executable, "-m", "baxterface_cli", "node", "_idle:=true"], cwd=str(ROOT), env=env
        )
        time.sleep(4.0)
        chatter.publish(String("default"))
        time.sleep(2.0)
        begin, cpu0, count0 = time.monotonic(), cpu_seconds(idle.pid), len(frames.times)
        time.sleep(30.0)
        spent = time.monotonic() - begin
        cpu = (cpu_seconds(idle.pid) - cpu0) / spent * 100
        stamps = frames.times[count0:]
        # Seconds with no blink under way: frames in them are what idle costs the link.
        busy = {int(t - begin) for t in stamps}
        blink_seconds = {s for s in busy if sum(1 for t in stamps if int(t - begin) == s) > 1}
        quiet = [s for s in range(int(spent)) if s not in blink_seconds]
        quiet_rate = sum(1 for t in stamps if int(t - begin) in quiet) / max(1, len(quiet))
        idle.send_signal(signal.SIGTERM)
        idle.wait()
    finally:
        rospy.signal_shutdown("bench done")
        core.send_signal(signal.SIGINT)
        core.wait()

    print("display_chatter -> first changed frame at a subscriber (ms), 120 commands")
    for name, values in (("relay (ROS's floor)", floor), ("baxterface node", ours)):
        print(
            f"  {name:<20} median {statistics.median(values):6.1f}  p99 {percentile(values, 99):6.1f}  "
            f"({len(values)} answered)"
        )
    print(f"  node / floor: median {statistics.median(ours) / statistics.median(floor):.1f}x")
    print("look_60_0 on display_chatter -> first frame showing the eyes moving (ms), 60 commands each")
    for name, values in (("jump (look_60_0_0)", jumps), ("0.5 s move (look_60_0)", moves)):
        print(
            f"  {name:<24} median {statistics.median(values):6.1f}  max {max(values):6.1f}  "
            f"({len(values)} answered)"
        )
    print("the continuous face: a statement sent to a still default face -> its first changed frame (ms)")
    print(f"  {'statement':<26} {'p50':>6} {'p95':>6} {'max':>6}  its own first change  p50 after that")
    for command, reset in STATEMENTS:
        values, own = statements[command], own_timing(command, reset)[1]
        if not values or own is None:
            print(f"  {command:<26} {len(values)} answered; its own first change: {own} ms")
            continue
        print(
            f"  {command:<26} {statistics.median(values):6.1f} {percentile(values, 95):6.1f} "
            f"{max(values):6.1f}  {own:6d} ms {'':>12} {statistics.median(values) - own:6.1f}  "
            f"({len(values)} answered)"
        )
    print(f"  (ROS's floor above: median {statistics.median(floor):.1f} ms)")
    print(f"30 fps look animation reaching a subscriber: {look_fps:.1f} frames/s")
    rate, gap, before, after, exit_s = flood
    print(f"flood of good, bad and maximum-size commands for 10 s: {rate:.0f} commands/s absorbed")
    print(
        f"  largest gap between frames {gap:.0f} ms; node memory {before:.0f} MB before, {after:.0f} MB after"
    )
    print(f"  SIGTERM with 20 maximum-size commands pending: exited in {exit_s:.2f} s")
    print(
        f"idle face over {spent:.0f} s: {len(stamps)} frames, {quiet_rate:.2f} frames/s between blinks, "
        f"node CPU {cpu:.1f} % of a core"
    )


if __name__ == "__main__":
    main()
