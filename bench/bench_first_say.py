"""The first `say` a fresh face node hears: how soon its sound is asked for (issue 44).

    .venv-ros/bin/python bench/bench_first_say.py            # as the machine is
    .ci/busy .venv-ros/bin/python bench/bench_first_say.py   # two spinning loops a core beside it

Each run starts a `baxterface node` of its own (a real roscore on loopback, audio by sound_play,
the default), waits for its first ~state (the node is up) and sends a 12-word `say` on
display_chatter, at once or a second later; measured from the command's publishing to the
PLAY_FILE request on /robotsound (the sound is then one file read away for sound_play) and to the
first ~state that says it. The node as it is (the speech process started with the node) beside
the node as it was (started by the first `say`: start_in_background disabled in that process).
Goal: the first sound 150 ms after the command at most, quiet and with the load beside it.

Measured on the 2-core machine this is developed on (6 nodes each; median and worst, ms from the
command to the PLAY_FILE request), beside other work at a load of 8 to 10, then with .ci/busy's
loops too at a load of 14 to 15:

    load 8 to 10    before: 65 / 106 at once, 75 / 94 a second after up;  now: 19 / 23 and 27 / 64
    load 14 to 15   before: 409 / 939 and 530 / 723;  now: 140 / 457 and 122 / 771

The median now meets the goal under load; the worst does not: the rest is the compile on the
session's worker and the loop's share of two crowded cores, not the speech process's start.
"""

from __future__ import annotations

import json
import os
import signal
import statistics
import subprocess
import sys
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(Path(__file__).resolve().parent))
from ros_master import start_roscore  # noqa: E402

RUNS = 6
TEXT = "the robot looked up and smiled at everyone in the room number {}"
# The node as it was: its speech process started only when the first `say` is compiled.
BEFORE = (
    "import sys\n"
    "import baxterface_cli.ros.face_node as node\n"
    "node.start_in_background = lambda: None\n"
    "from baxterface_cli.cli import main\n"
    "main()\n"
)


class Heard:
    """When the PLAY_FILE requests and the ~states saying something arrived."""

    def __init__(self, rospy) -> None:
        from std_msgs.msg import String

        from baxterface_cli.ros.effect_messages import SOUND_PLAY_FILE
        from baxterface_cli.ros.messages import message_class

        self.sounds, self.saying, self.states = [], [], 0
        self.changed = threading.Condition()
        self.play_file = SOUND_PLAY_FILE
        rospy.Subscriber("/robotsound", message_class("sound_play/SoundRequest"), self._sound, queue_size=10)
        rospy.Subscriber("/baxter_face/state", String, self._state, queue_size=10)

    def _sound(self, msg) -> None:
        if msg.sound == self.play_file:
            with self.changed:
                self.sounds.append(time.monotonic())
                self.changed.notify_all()

    def _state(self, msg) -> None:
        with self.changed:
            self.states += 1
            if json.loads(msg.data)["saying"] is not None:
                self.saying.append(time.monotonic())
            self.changed.notify_all()

    def wait(self, test, timeout: float = 120.0) -> None:
        with self.changed:
            if not self.changed.wait_for(test, timeout):
                raise RuntimeError("the node did not answer")


def first_say(rospy, heard: Heard, env, before: bool, after_up: float, n: int):
    """(ms to the PLAY_FILE request, ms to the first state saying it) for one fresh node."""
    from std_msgs.msg import String

    start = [sys.executable, "-c", BEFORE] if before else [sys.executable, "-m", "baxterface_cli"]
    with heard.changed:
        heard.sounds.clear()
        heard.saying.clear()
        heard.states = 0
    command = [*start, "node", "_idle:=false", "_selftest:=false"]
    node = subprocess.Popen(
        command, cwd=str(ROOT), env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
    )
    chatter = rospy.Publisher("/display_chatter", String, queue_size=10)
    try:
        heard.wait(lambda: heard.states > 0)  # up: its ~state is latched at start
        while chatter.get_num_connections() == 0:
            time.sleep(0.005)
        time.sleep(after_up)
        sent = time.monotonic()
        chatter.publish(String(f'say "{TEXT.format(n)}"'))
        heard.wait(lambda: heard.sounds and heard.saying)
        return (heard.sounds[0] - sent) * 1000, (heard.saying[0] - sent) * 1000
    finally:
        chatter.unregister()
        node.send_signal(signal.SIGTERM)
        node.wait()
        subprocess.run(["rosparam", "delete", "/baxter_face"], env=env, capture_output=True)


def main() -> None:
    print(subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())
    core, env = start_roscore()
    os.environ.update(ROS_MASTER_URI=env["ROS_MASTER_URI"], ROS_IP="127.0.0.1")
    import rospy

    rospy.init_node("bench_first_say", anonymous=True, disable_signals=True)
    heard = Heard(rospy)
    results = {}
    try:
        n = 0
        for _ in range(RUNS):  # interleaved, so the machine's mood on the day is shared
            for before in (True, False):
                for after_up in (0.0, 1.0):
                    n += 1
                    got = first_say(rospy, heard, env, before, after_up, n)
                    results.setdefault((before, after_up), []).append(got)
    finally:
        rospy.signal_shutdown("bench done")
        core.send_signal(signal.SIGINT)
        core.wait()
    print(subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())
    print(f"the first say of a fresh node, {RUNS} nodes each (ms from the command; median, worst)")
    for (before, after_up), got in sorted(results.items(), key=lambda kv: (not kv[0][0], kv[0][1])):
        name = "started by the say (before)" if before else "started with the node (now)"
        when = "at once when up" if after_up == 0 else f"{after_up:.0f} s after up"
        sounds, states = [g[0] for g in got], [g[1] for g in got]
        print(
            f"  {name:29s} {when:16s} sound asked {statistics.median(sounds):7.1f} {max(sounds):7.1f}"
            f"   state saying {statistics.median(states):7.1f} {max(states):7.1f}"
        )


if __name__ == "__main__":
    main()
