"""Flood the face node with good, bad and maximum-size commands, from a process of its own.

    python tests/support/flooder.py SECONDS

Run apart from whoever measures the frames, so that receiving 1.8 MB frames
and sending up to 300 KB commands do not compete in one process: the gaps
measured are then the node's. Prints how many commands a second it sent.
"""

import sys
import time

import rospy
from std_msgs.msg import String

from baxterface_cli.core.face_constants import LIMITS

MOVING = "repeat 100 { look 60 0 in 1s; look -60 0 in 1s }"  # every frame differs, for minutes
LINE = "look 40 -20 in 0.05s; look -40 20 in 0.05s\n"
HUGE = LINE * (LIMITS.max_pieces // 12)  # 12 pieces a line: the largest valid script, slow to parse
# Every good one keeps the eyes moving, so any gap between frames is the node's.
MIXED = [MOVING, "hapy", "a\n" * 100_000, HUGE, "look_a_b", "x" * 300_000]


def main() -> None:
    seconds = float(sys.argv[1])
    rospy.init_node("flooder", anonymous=True, disable_signals=True)
    chatter = rospy.Publisher("/display_chatter", String, queue_size=1000)
    queued = rospy.Publisher("/baxter_face/queue", String, queue_size=1000)
    while chatter.get_num_connections() < 1 or queued.get_num_connections() < 1:
        time.sleep(0.05)
    began, sent = time.monotonic(), 0
    while time.monotonic() - began < seconds:
        chatter.publish(String(MIXED[sent % len(MIXED)]))
        if sent % 10 == 0:
            queued.publish(String(HUGE))
        sent += 1
        time.sleep(0.002)
    print(f"{sent / (time.monotonic() - began):.0f}", flush=True)
    chatter.publish(String(MOVING))
    time.sleep(1.0)  # let the last messages go out before the connections close


if __name__ == "__main__":
    main()
