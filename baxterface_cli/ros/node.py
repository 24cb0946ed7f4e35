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
from ..following import ArmFollower, HumanFollower
from ..geometry import clamp_pan, clamp_to_ellipse
from ..live import LiveFace, sleep_face
from ..renderer import Renderer, pose
from ..state import FaceState
from ..tables import BROWS, MOUTHS, SKINS
from ..theme import parse_size, resolve
from ..timeline import EYE_SPAN_RAD, Action, to_pixels, to_radians
from .messages import message_class

PAN_TOLERANCE = 0.1396263401  # baxter_interface's: 8 degrees
HEAD_TIMEOUT = 10.0  # seconds to keep asking the head, as baxter_interface does
ENABLE_TIMEOUT = 5.0
STATE_EVERY = 0.1  # seconds between ~state messages while the face moves
FOLLOW_SMOOTHING = 0.25  # of the way to a followed target, each frame
FOLLOW_RELEASE = 0.5  # seconds the eyes take to hand back from following to the script
HEAD_FOLLOW_STEP = 0.1  # radians a followed target must move before the head is asked again
WARN_EVERY = 5.0  # seconds between repeats of one warning about bad sensor data
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
        if not 1.0 <= self.fps <= 120.0:
            raise ValueError(f"~fps must be from 1 to 120, not {self.fps:g}")
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
        # Following: sensor readings handed over by callbacks, and where the eyes are.
        self.human = HumanFollower()
        self.arm = ArmFollower()
        self.sonar: queue.Queue[Tuple[list, list]] = queue.Queue(maxsize=100)
        self.hands = {"left": None, "right": None}
        self.follow_eye: Optional[Tuple[float, float]] = None
        self.release: Optional[Tuple[float, Tuple[float, float]]] = None
        self.followed: Tuple[Optional[str], bool] = (None, False)

        rospy.Subscriber("display_chatter", String, self._heard, callback_args=False, queue_size=100)
        rospy.Subscriber("~queue", String, self._heard, callback_args=True, queue_size=100)
        rospy.Subscriber("/robot/head/head_state", message_class("HeadState"), self._head_state, queue_size=1)
        rospy.Subscriber("/robot/state", message_class("AssemblyState"), self._robot_state, queue_size=1)
        from sensor_msgs.msg import PointCloud

        rospy.Subscriber("/robot/sonar/head_sonar/state", PointCloud, self._sonar_cloud, queue_size=5)
        for side in self.hands:
            rospy.Subscriber(
                f"/robot/limb/{side}/endpoint_state",
                message_class("EndpointState"),
                self._hand,
                side,
                queue_size=1,
            )
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

    def _sonar_cloud(self, msg: Any) -> None:
        """Check a sonar cloud and hand its (ids, distances) over; skip it, warning, if malformed."""
        if self.followed[0] != "human":  # readings from before following began would be stale
            return
        channels = {c.name: list(c.values) for c in msg.channels}
        ids, distances = channels.get("SensorId"), channels.get("Distance")
        problem = None
        if ids is None or distances is None:
            problem = f"no SensorId and Distance channels (it has {sorted(channels)})"
        elif len(ids) != len(distances):
            problem = f"{len(ids)} sensor ids but {len(distances)} distances"
        elif not all(math.isfinite(v) for v in ids + distances):
            problem = "a value that is not a finite number"
        elif not all(float(v).is_integer() and 0 <= v <= 11 for v in ids):
            problem = "a sensor id outside 0-11"
        if problem:
            self.rospy.logwarn_throttle(WARN_EVERY, f"skipped a head sonar cloud: {problem}")
            return
        if not self.sonar.full():
            self.sonar.put((ids, distances))

    def _hand(self, msg: Any, side: str) -> None:
        p = msg.pose.position
        if all(math.isfinite(v) for v in (p.x, p.y, p.z)):
            self.hands[side] = (p.x, p.y, p.z)  # the latest only: read at the frame rate, not 100 Hz
        else:
            self.rospy.logwarn_throttle(WARN_EVERY, f"skipped a {side} hand pose that is not finite")

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
            state = self._follow(self.live.state(now), now)
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

    # -- following

    def _follow(self, state: FaceState, now: float) -> FaceState:
        """The face with its eyes on what is followed, moving there smoothly."""
        target, dynamic = self.live.following
        if (target, dynamic) != self.followed:
            if target is None and self.follow_eye is not None:
                self.release = (now, self.follow_eye)  # hand the eyes back to the script smoothly
            if target == "human":
                self.human = HumanFollower()
            self.follow_eye, self.followed = None, (target, dynamic)
        if target is None:
            if self.release is not None:
                since, (x, y) = self.release
                u = (now - since) / FOLLOW_RELEASE
                if u < 1.0:
                    return state.replace(eye_x=x + (state.eye_x - x) * u, eye_y=y + (state.eye_y - y) * u)
                self.release = None
            return state
        goal = self._follow_goal(target, dynamic, now)
        here = self.follow_eye or (state.eye_x, state.eye_y)
        if goal is not None:
            here = (
                here[0] + (goal[0] - here[0]) * FOLLOW_SMOOTHING,
                here[1] + (goal[1] - here[1]) * FOLLOW_SMOOTHING,
            )
        self.follow_eye = here
        return state.replace(eye_x=here[0], eye_y=here[1])

    def _follow_goal(self, target: str, dynamic: bool, now: float) -> Optional[Tuple[float, float]]:
        """Where the eyes should go for what is followed, turning the head if dynamic."""
        head = self.head_pan if self.head_pan is not None else 0.0
        if target == "human":
            eye_x = None
            while not self.sonar.empty():
                ids, distances = self.sonar.get_nowait()
                seen = self.human.update(ids, distances)
                eye_x = seen if seen is not None else eye_x
            if eye_x is None:
                return None if self.follow_eye is None else self.follow_eye
            want, eye_y = head + to_radians(eye_x), 0.0  # the sonar turns with the head
        else:
            hand = self.hands[target.split()[0]]
            if hand is None:
                return None
            eye_x, eye_y = self.arm.eye_target(*hand)
            want = to_radians(eye_x)  # the hand is in the base frame
        if not dynamic:
            return clamp_to_ellipse(to_pixels(want - head) if target == "human" else eye_x, eye_y)
        # The dynamic-look rule: beyond the eyes' own reach, the head turns.
        if abs(want - head) > EYE_SPAN_RAD and self.robot_enabled is not False:
            pan = clamp_pan(want)
            current = self.head_goal[0] if self.head_goal else head
            if abs(pan - current) > HEAD_FOLLOW_STEP:
                self.head_goal = (pan, 1.0, now + HEAD_TIMEOUT)
                self._send_pan()
            return clamp_to_ellipse(to_pixels(want - pan), eye_y)
        return clamp_to_ellipse(to_pixels(want - head), eye_y)

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
