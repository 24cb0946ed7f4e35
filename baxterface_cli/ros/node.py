"""`baxterface node`: the face node on ROS, replacing the old screen_listener.py.

It listens on `display_chatter` (old commands and scripts alike), draws with
the same engine as `play`, publishes changed frames on /robot/xdisplay as
bgr8 through one latched publisher, drives the head, nod and enable
topics, and reports what the face is doing on `~state` (JSON, latched).
All work happens in one loop; subscriber callbacks only hand messages over.
"""

from __future__ import annotations

import json
import math
import queue
import signal
import threading
import time
from typing import Any, List, Optional, Tuple

from ..diagnostics import ScriptError
from ..live import LiveFace, sleep_face
from ..renderer import Renderer, pose
from ..state import FaceState
from ..tables import BROWS, MOUTHS, SKINS
from ..theme import parse_size, resolve
from ..timeline import Action
from .messages import message_class

PAN_TOLERANCE = 0.1396263401  # baxter_interface's: 8 degrees
HEAD_TIMEOUT = 10.0  # seconds to keep asking the head, as baxter_interface does
ENABLE_TIMEOUT = 5.0
STATE_EVERY = 0.1  # seconds between ~state messages while the face moves
DISPLAY_TOPICS = {"baxter": "/robot/xdisplay", "sawyer": "/robot/head_display"}


def selftest_script() -> str:
    """Every layer once, then the sleep face: the original's start-up flash."""
    steps = [f"skin {i}; wait 0.12s" for i in SKINS]
    steps += [f"mouth {m}; wait 0.12s" for m in MOUTHS] + [f"brows {b}; wait 0.12s" for b in BROWS]
    steps += ["look left in 0.2s", "look right in 0.3s", "look center in 0.2s", "blink", "sleep"]
    return "; ".join(steps)


class FaceNode:
    """The node's state and its one loop."""

    def __init__(self, argv: List[str]) -> None:
        import cv_bridge
        import rospy
        from sensor_msgs.msg import Image
        from std_msgs.msg import Bool, String

        self.rospy = rospy
        rospy.init_node("baxter_face", argv=argv, disable_signals=True)
        self.fps = float(rospy.get_param("~fps", 30.0))
        size = parse_size(str(rospy.get_param("~size", "1024x600")))
        theme = rospy.get_param("~theme", "") or None
        self.renderer = Renderer(resolve(theme).layers(size))
        self.live = LiveFace(
            start=sleep_face(), idle=bool(rospy.get_param("~idle", True)), now=time.monotonic()
        )
        self.String, self.Bool, self.Image = String, Bool, Image
        self.bridge = cv_bridge.CvBridge()
        self.HeadPanCommand = message_class("HeadPanCommand")

        display = rospy.get_param("~display_topic", DISPLAY_TOPICS["baxter"])
        self.image_pub = rospy.Publisher(display, Image, latch=True, queue_size=1)
        self.state_pub = rospy.Publisher("~state", String, latch=True, queue_size=1)
        self.pan_pub = rospy.Publisher("/robot/head/command_head_pan", self.HeadPanCommand, queue_size=10)
        self.nod_pub = rospy.Publisher("/robot/head/command_head_nod", Bool, queue_size=1)
        self.enable_pub = rospy.Publisher("/robot/set_super_enable", Bool, queue_size=10)

        self.inbox: queue.Queue[Tuple[str, bool]] = queue.Queue()
        self.wake = threading.Event()
        self.stop = threading.Event()
        self.head_pan: Optional[float] = None  # measured, from head_state
        self.robot_enabled: Optional[bool] = None  # from /robot/state; None until heard
        self.head_goal: Optional[Tuple[float, float, float]] = None  # target, speed, deadline
        self.enable_goal: Optional[Tuple[bool, float, float]] = None  # value, next send, deadline
        self.last_key: Any = None
        self.last_frame_at = -math.inf
        self.last_state_text = ""
        self.last_state_at = -math.inf

        rospy.Subscriber("display_chatter", String, self._heard, callback_args=False, queue_size=100)
        rospy.Subscriber("~queue", String, self._heard, callback_args=True, queue_size=100)
        rospy.Subscriber("/robot/head/head_state", message_class("HeadState"), self._head_state, queue_size=1)
        rospy.Subscriber("/robot/state", message_class("AssemblyState"), self._robot_state, queue_size=1)
        if rospy.get_param("~selftest", False):
            self.live.command(selftest_script(), time.monotonic(), filename="selftest")

    # -- callbacks: hand over and wake the loop, nothing else

    def _heard(self, msg: Any, queued: bool) -> None:
        self.inbox.put((msg.data, queued))
        self.wake.set()

    def _head_state(self, msg: Any) -> None:
        self.head_pan = float(msg.pan)

    def _robot_state(self, msg: Any) -> None:
        self.robot_enabled = bool(msg.enabled)

    # -- the loop

    def run(self) -> int:
        for signum in (signal.SIGINT, signal.SIGTERM):
            signal.signal(signum, lambda *_: (self.stop.set(), self.wake.set()))
        self.rospy.loginfo(
            "baxterface face node: listening on %s", self.rospy.resolve_name("display_chatter")
        )
        period = 1.0 / self.fps
        next_tick = time.monotonic()
        while not self.stop.is_set() and not self.rospy.is_shutdown():
            now = time.monotonic()
            self._take_commands(now)
            for action in self.live.due(now):
                self._act(action, now)
            state = self.live.state(now)
            self._keep_asking(now)
            if self.live.exited:
                self._publish_frame(state, now, force=True)
                self._publish_state(state, now, force=True)
                time.sleep(0.5)  # let the last frame reach its subscribers
                break
            # The cap: frames at most `fps` a second (a little slack for a
            # tick that comes early; ticks themselves keep the average).
            if now >= self.last_frame_at + 0.75 * period:
                self._publish_frame(state, now)
            self._publish_state(state, now)
            # Ticks keep their own rhythm, publishing or not; a late loop
            # skips the ticks it missed rather than hurrying to catch up.
            next_tick += period
            if next_tick < now:
                next_tick = now + period
            self.wake.wait(max(0.0, next_tick - time.monotonic()))  # or until a command comes
            self.wake.clear()
        self.rospy.signal_shutdown("face node finished")
        return 0

    def _take_commands(self, now: float) -> None:
        while True:
            try:
                text, queued = self.inbox.get_nowait()
            except queue.Empty:
                return
            try:
                self.live.command(text, now, queue=queued)
                self.last_state_at = -math.inf  # report the new command at once
            except ScriptError as e:
                self.rospy.logerr("bad command on display_chatter:\n%s", e.render())
            except Exception as e:  # never let one message stop the face
                self.rospy.logerr("could not run a command: %r", e)

    def _publish_frame(self, state: FaceState, now: float, force: bool = False) -> None:
        at = pose(self.renderer.layers, state)
        key = (at, state.parts, state.fade_from, int(state.fade * 255 + 0.5) if state.fade_from else 255)
        if key == self.last_key and not force:
            return
        frame = self.renderer.render(state)
        self.image_pub.publish(self.bridge.cv2_to_imgmsg(frame, encoding="bgr8"))
        self.last_key, self.last_frame_at = key, now

    def _publish_state(self, state: FaceState, now: float, force: bool = False) -> None:
        if now - self.last_state_at < STATE_EVERY and not force:
            return
        following, dynamic = self.live.following
        report = {
            "emotion": self.live.emotion,
            "skin": state.skin,
            "mouth": state.mouth,
            "brows": state.brows,
            "eye_x": round(state.eye_x, 2),
            "eye_y": round(state.eye_y, 2),
            "eyelids": round(state.eyelids, 3),
            "head_pan": round(self.head_pan if self.head_pan is not None else state.head_pan, 4),
            "enabled": self.robot_enabled,
            "following": following,
            "follow_dynamic": dynamic,
            "playing": not self.live.finished(now),
            "queued": len(self.live.queue),
        }
        text = json.dumps(report, sort_keys=True)
        if text != self.last_state_text or force:
            self.state_pub.publish(self.String(text))
            self.last_state_text = text
        self.last_state_at = now

    # -- the robot

    def _act(self, action: Action, now: float) -> None:
        if action.kind == "head":
            if self.robot_enabled is False:
                self.rospy.logwarn("the robot is disabled: not turning the head to %.2f rad", action.value)
                return
            start = self.head_pan if self.head_pan is not None else 0.0
            speed = (
                1.0
                if action.duration <= 0
                else min(1.0, max(0.05, abs(action.value - start) / action.duration))
            )
            self.head_goal = (action.value, speed, now + action.duration + HEAD_TIMEOUT)
            self._send_pan()
        elif action.kind == "nod":
            if self.robot_enabled is False:
                self.rospy.logwarn("the robot is disabled: not nodding")
                return
            self.nod_pub.publish(self.Bool(True))
        elif action.kind in ("enable", "disable"):
            value = action.kind == "enable"
            self.enable_goal = (value, now, now + ENABLE_TIMEOUT)
            self._keep_asking(now)
        elif action.kind == "follow":
            target, dynamic = action.value
            self.rospy.loginfo("following: %s%s", target or "nothing", " (dynamic)" if dynamic else "")

    def _send_pan(self) -> None:
        target, speed, _ = self.head_goal  # type: ignore[misc]
        self.pan_pub.publish(self.HeadPanCommand(target=target, speed_ratio=speed, enable_pan_request=1))

    def _keep_asking(self, now: float) -> None:
        """Repeat head and enable commands until the robot agrees, or give up and say so."""
        if self.head_goal is not None:
            target, _, deadline = self.head_goal
            if self.head_pan is not None and abs(self.head_pan - target) <= PAN_TOLERANCE:
                self.head_goal = None
            elif now > deadline:
                self.rospy.logwarn("the head did not reach %.2f rad in time", target)
                self.head_goal = None
            elif self.robot_enabled is not False:
                self._send_pan()
        if self.enable_goal is not None:
            value, next_send, deadline = self.enable_goal
            if self.robot_enabled is value:
                self.enable_goal = None
            elif now > deadline:
                word = "enabled" if value else "disabled"
                self.rospy.logwarn("the robot did not report itself %s within %.0f s", word, ENABLE_TIMEOUT)
                self.enable_goal = None
            elif now >= next_send:
                self.enable_pub.publish(self.Bool(value))
                self.enable_goal = (value, now + 0.1, deadline)


def run_node(argv: List[str]) -> int:
    return FaceNode(argv).run()
