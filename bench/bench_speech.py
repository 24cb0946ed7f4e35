"""Speech: how fast `say` is synthesised, and how soon the node speaks after a command.

    .venv-ros/bin/python bench/bench_speech.py

- synthesis: 20 different 12-word sentences through the engine `say` uses
  (espeak-ng through its library), as seconds of speech per second of work;
  the baseline, in the same run, is the `espeak-ng` program writing the same
  sentences to WAV files (goal: at least 20x real time).
- the node (a real roscore on loopback, `baxterface node` in its own process,
  audio by sound_play, the default): from a 12-word `say` on display_chatter
  to the PLAY_FILE request on /robotsound (its sound is then one file read
  away) and to the first frame with a speech mouth; the baseline is a command
  that changes the face at once (`mouth smile-open`). Goal: 100 ms, p95.
"""

from __future__ import annotations

import os
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_node import percentile  # noqa: E402
from ros_master import start_roscore  # noqa: E402

WORDS = ("the", "robot", "looked", "up", "and", "smiled", "at", "everyone", "in", "the", "room", "number")


def sentences(count: int, offset: int = 0):
    """Twelve words each, all different, so no cache helps."""
    return [" ".join(WORDS[:11] + (str(offset + i),)) for i in range(count)]


def synthesis() -> None:
    from baxterface_cli.speech.synthesis import engine

    texts = sentences(20)
    speaker = engine()
    speaker.say("warm up")
    start = time.perf_counter()
    spoken = sum(speaker.say(text).duration for text in texts)
    ours = time.perf_counter() - start
    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        for i, text in enumerate(texts):
            subprocess.run(["espeak-ng", "-w", f"{tmp}/{i}.wav", text], check=True)
        program = time.perf_counter() - start
    print(f"synthesis of 20 twelve-word sentences ({spoken:.1f} s of speech)")
    print(f"  espeak-ng program (baseline)  {program:6.2f} s  {spoken / program:6.0f}x real time")
    print(f"  baxterface engine             {ours:6.2f} s  {spoken / ours:6.0f}x real time")
    print(f"  {ours / len(texts) * 1000:.0f} ms a sentence; engine / program: {program / ours:.1f}x faster")


class Heard:
    """Times of frames on /robot/xdisplay and PLAY_FILE requests on /robotsound."""

    def __init__(self, rospy) -> None:
        from sensor_msgs.msg import Image

        from baxterface_cli.ros.effect_messages import SOUND_PLAY_FILE
        from baxterface_cli.ros.messages import message_class

        self.frames, self.sounds = [], []
        self.changed = threading.Event()
        self.play_file = SOUND_PLAY_FILE
        rospy.Subscriber("/robot/xdisplay", Image, self._frame, queue_size=10, buff_size=2**24)
        rospy.Subscriber("/robotsound", message_class("sound_play/SoundRequest"), self._sound, queue_size=10)

    def _frame(self, msg) -> None:
        self.frames.append(time.monotonic())

    def _sound(self, msg) -> None:
        if msg.sound == self.play_file:
            self.sounds.append(time.monotonic())


def first_after(times, t):
    later = [x for x in list(times) if x > t]
    return (later[0] - t) * 1000 if later else None


def node_latency() -> None:
    core, env = start_roscore()
    os.environ.update(ROS_MASTER_URI=env["ROS_MASTER_URI"], ROS_IP="127.0.0.1")
    import rospy
    from std_msgs.msg import String

    rospy.init_node("bench_speech", anonymous=True, disable_signals=True)
    heard = Heard(rospy)
    node = subprocess.Popen(
        [sys.executable, "-m", "baxterface_cli", "node", "_idle:=false", "_selftest:=false"],
        cwd=str(ROOT),
        env=env,
        stderr=subprocess.DEVNULL,
    )
    chatter = rospy.Publisher("/display_chatter", String, queue_size=10)
    try:
        time.sleep(4.0)
        chatter.publish(String("default"))
        time.sleep(1.0)
        jumps, says, sounds = [], [], []
        for _ in range(20):
            for command in ("mouth smile-open", "mouth smile"):
                sent = time.monotonic()
                chatter.publish(String(command))
                time.sleep(0.4)
                jumps.append(first_after(heard.frames, sent))
        for text in sentences(20, offset=100):
            sent = time.monotonic()
            chatter.publish(String(f'say "{text}"'))
            time.sleep(4.5)  # the sentence ends before the next
            says.append(first_after(heard.frames, sent))
            sounds.append(first_after(heard.sounds, sent))
    finally:
        node.send_signal(signal.SIGTERM)
        node.wait()
        rospy.signal_shutdown("bench done")
        core.send_signal(signal.SIGINT)
        core.wait()
    print("display_chatter -> at a subscriber (ms): a change of mouth, shown at once, and a 12-word say")
    for name, values in (
        ("mouth change: first frame (baseline)", jumps),
        ("say: sound_play PLAY_FILE request", sounds),
        ("say: first speech-mouth frame", says),
    ):
        got = [v for v in values if v is not None]
        print(
            f"  {name:<38} median {statistics.median(got):6.1f}  p95 {percentile(got, 95):6.1f}  "
            f"({len(got)} of {len(values)} answered)"
        )


def main() -> None:
    synthesis()
    node_latency()


if __name__ == "__main__":
    main()
