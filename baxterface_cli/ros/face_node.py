"""`baxterface node`: the face node on ROS, replacing the old screen_listener.py.

It listens on `display_chatter` (old commands and scripts alike), draws with
the same engine as `play`, publishes changed frames on /robot/xdisplay as
bgr8 through one latched publisher, drives the head, nod and enable
topics through the core `Robot` (robot_link), speaks through the `_audio`
mode's speaker, and reports what the face is doing on `~state` (JSON,
latched). All work happens in one loop; subscriber callbacks only hand
messages over. The head camera (`_camera:=TOPIC`) is subscribed to only
while a face is followed, and its images are looked at on the camera
watch's own thread, never on the loop. The camera's focal length comes from
its `camera_info` (beside the image topic) when it publishes one, unless
`_camera_hfov` gives the field of view.
"""

from __future__ import annotations

import gc
import json
import math
import signal
import sys
import threading
import time
from typing import Any, List, Optional, Tuple

from ..core.face_state import FaceState
from ..core.tables import BROWS, MOUTHS, SKINS
from ..drawing.renderer import Renderer
from ..engine.backlog import Backlog
from ..engine.effects import Speech
from ..engine.intake import Intake
from ..engine.live_face import LiveFace, sleep_face
from ..robot.camera_watch import CameraWatch
from .messages import message_class
from .node_settings import NodeSettings, SettingError, camera_focal, camera_info_topic, theme_layers
from .robot_link import WARN_EVERY, connect_robot
from .speakers import open_speaker

STATE_EVERY = 0.1  # seconds between ~state messages while the face moves
# After a command, the next frame comes this soon rather than at the next
# tick: a move that starts now shows its first motion within ~10 ms.
FIRST_MOTION = 0.010
# The loop takes the GIL back several times a frame from threads that parse
# commands and receive messages; each time it may wait a whole switch
# interval (5 ms by default). 1 ms halved the worst frame gap under a flood.
SWITCH_INTERVAL = 0.001
# A full garbage collection walks every object that queued scripts hold and
# stops the loop while it does (about 100 ms with a full queue of big ones).
# Python's first two generations still collect young cycles; the full one is
# left for this many of theirs rather than 10.
FULL_COLLECTION_EVERY = 1000
MASTER_CHECK = 1.0  # seconds between checks that the master still knows this node
CAMERA_ENCODINGS = ("bgr8", "rgb8", "mono8")
IMAGE_BUFFER = 1 << 24  # bytes: room for a whole 1280x800 image, so only the newest is kept


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
        from std_msgs.msg import String

        self.rospy = rospy
        rospy.init_node("baxter_face", argv=argv, disable_signals=True)
        try:
            settings = NodeSettings.read(lambda name, default: rospy.get_param("~" + name, default))
            layers = theme_layers(settings)
        except SettingError as e:
            raise not_kept(e, rospy, argv) from None
        self.fps = settings.fps
        self.renderer = Renderer(layers)
        self.live = LiveFace(start=sleep_face(), idle=settings.idle, now=time.monotonic())
        self.String, self.Image = String, Image
        self.bridge = cv_bridge.CvBridge()

        self.image_pub = rospy.Publisher(settings.display_topic, Image, latch=True, queue_size=1)
        self.state_pub = rospy.Publisher("~state", String, latch=True, queue_size=1)
        levels = {"info": rospy.loginfo, "warn": rospy.logwarn, "error": rospy.logerr}
        self.log = Backlog(lambda level, text: levels[level](text))  # never logs from the loop
        self.speaker = open_speaker(settings.audio, rospy, self.log.warn)
        self.saying: Optional[Tuple[str, float]] = None  # (text, when it ends) while the face speaks
        self.camera_topic = settings.camera
        hfov, policy = settings.camera_hfov, settings.face_policy
        # The field of view given wins; without it, the camera says its focal length.
        self.camera_info_topic = camera_info_topic(settings.camera) if hfov is None else None
        self.camera_sub: Any = None
        self.camera_info_sub: Any = None

        def camera(hand_to):
            warn = lambda text: rospy.logwarn_throttle(WARN_EVERY, text)  # noqa: E731
            return CameraWatch(hand_to, hfov_deg=hfov, decode=self._decode_image, warn=warn, policy=policy)

        self.robot = connect_robot(
            rospy, warn=self.log.warn, info=self.log.info, speak=self._speak, camera=camera
        )

        self.wake = threading.Event()
        self.stop = threading.Event()
        self.intake = Intake(self.live, time.monotonic, ready=self.wake.set)
        self.last_key: Any = None
        self.last_frame_at = -math.inf
        self.last_state_text = ""
        self.last_state_at = -math.inf

        rospy.Subscriber("display_chatter", String, self._heard, callback_args=False, queue_size=100)
        rospy.Subscriber("~queue", String, self._heard, callback_args=True, queue_size=100)
        from sensor_msgs.msg import PointCloud

        rospy.Subscriber("/robot/sonar/head_sonar/state", PointCloud, self._sonar_cloud, queue_size=5)
        for side in self.robot.gaze.hands:
            rospy.Subscriber(
                f"/robot/limb/{side}/endpoint_state",
                message_class("EndpointState"),
                self._hand,
                side,
                queue_size=1,
            )
        if settings.selftest:
            self.live.command(selftest_script(), time.monotonic(), filename="selftest")

    # -- callbacks: hand over and wake the loop, nothing else

    def _heard(self, msg: Any, queued: bool) -> None:
        refusal = self.intake.submit(msg.data, queued)  # parsed off the frame loop
        if refusal:
            self.log.warn(refusal)

    def _sonar_cloud(self, msg: Any) -> None:
        """Check a sonar cloud and hand its (ids, distances) over; skip it, warning, if malformed."""
        if not self.robot.gaze.wants_sonar:
            return
        channels = {c.name: list(c.values) for c in msg.channels}
        if "SensorId" not in channels or "Distance" not in channels:
            problem = f"no SensorId and Distance channels (it has {sorted(channels)})"
        else:
            problem = self.robot.heard_sonar(channels["SensorId"], channels["Distance"])
        if problem:
            self.rospy.logwarn_throttle(WARN_EVERY, f"skipped a head sonar cloud: {problem}")

    def _hand(self, msg: Any, side: str) -> None:
        p = msg.pose.position
        if all(math.isfinite(v) for v in (p.x, p.y, p.z)):
            self.robot.gaze.hands[side] = (p.x, p.y, p.z)  # the latest only: read at the frame rate
        else:
            self.rospy.logwarn_throttle(WARN_EVERY, f"skipped a {side} hand pose that is not finite")

    def _image(self, msg: Any) -> None:
        self.robot.heard_image(msg, time.monotonic())  # decoded and looked at on the camera's thread

    def _decode_image(self, msg: Any) -> Any:
        if msg.encoding not in CAMERA_ENCODINGS:
            raise ValueError(f"its encoding is {msg.encoding!r}; the face follower takes bgr8, rgb8 or mono8")
        return self.bridge.imgmsg_to_cv2(msg, desired_encoding="bgr8")

    def _camera_info(self, msg: Any) -> None:
        focal = camera_focal(msg.K, msg.binning_x)
        if focal is None:
            self.rospy.logwarn_throttle(
                WARN_EVERY,
                f"{self.camera_info_topic} gives no focal length (K[0] is {msg.K[0] if msg.K else None}); "
                "following a face takes a field of view of 76 degrees (_camera_hfov:=DEGREES sets another)",
            )
        else:
            self.robot.camera.lens(focal)

    def _watch_camera(self) -> None:
        """Subscribe to the camera while a face is followed, and only then: images are heavy."""
        wanted = self.robot.gaze.wants_camera
        if wanted and self.camera_sub is None:
            self.camera_sub = self.rospy.Subscriber(
                self.camera_topic, self.Image, self._image, queue_size=1, buff_size=IMAGE_BUFFER
            )
            if self.camera_info_topic is not None:
                from sensor_msgs.msg import CameraInfo

                self.camera_info_sub = self.rospy.Subscriber(
                    self.camera_info_topic, CameraInfo, self._camera_info, queue_size=1
                )
        elif not wanted and self.camera_sub is not None:
            self.camera_sub.unregister()
            self.camera_sub = None
            if self.camera_info_sub is not None:
                self.camera_info_sub.unregister()
                self.camera_info_sub = None

    def _speak(self, effect: Speech) -> None:
        # Timed here, not by the script's status: a take-over restarts the script's clock.
        self.saying = (effect.utterance.text, time.monotonic() + effect.duration)
        self.speaker.speak(effect)

    # -- the loop

    def run(self) -> int:
        try:
            return self._run()
        finally:
            self.speaker.close()
            self.robot.camera.close()

    def _run(self) -> int:
        sys.setswitchinterval(SWITCH_INTERVAL)
        young, middle, _ = gc.get_threshold()
        gc.set_threshold(young, middle, FULL_COLLECTION_EVERY)
        for signum in (signal.SIGINT, signal.SIGTERM):
            signal.signal(signum, lambda *_: (self.stop.set(), self.wake.set()))
        self.rospy.loginfo(
            "baxterface face node: listening on %s", self.rospy.resolve_name("display_chatter")
        )
        threading.Thread(target=self._watch_master, name="baxterface-master", daemon=True).start()
        period = 1.0 / self.fps
        next_tick = time.monotonic()
        while not self.stop.is_set() and not self.rospy.is_shutdown():
            now = time.monotonic()
            took = self._take_commands(now)
            for cue in self.live.due(now):
                self.robot.take(cue.effect, now)
            self._watch_camera()
            state = self.robot.look(self.live.state(now), now)
            self.robot.tick(now)
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
            if took:
                next_tick = min(next_tick, now + FIRST_MOTION)
            self.wake.wait(max(0.0, next_tick - time.monotonic()))  # or until a command comes
            self.wake.clear()
        self.intake.close()
        self.log.flush(timeout=0.3)
        self.log.close()
        self.rospy.signal_shutdown("face node finished")
        return 0

    # -- the master

    def _watch_master(self) -> None:
        """Register again with a master that no longer knows this node (it was restarted)."""
        import rosgraph

        master = rosgraph.Master(self.rospy.get_name())
        while not self.stop.wait(MASTER_CHECK):
            try:
                master.lookupNode(self.rospy.get_name())
            except rosgraph.MasterError:  # up, but it has never heard of us: a new master
                self.log.info("the ROS master was restarted: registering again")
                register_again()
            except Exception:
                pass  # down: rospy's own calls will fail until it is back

    def _take_commands(self, now: float) -> bool:
        """Start or queue what the intake has ready; True if something started now."""
        took = self.intake.hand_over(now, warn=self.log.warn, error=self.log.error)
        if took is not None:
            self.last_state_at = -math.inf  # report the change at once
        if took:  # what was being said is cut off with the script that said it
            self.saying = None
            self.speaker.stop()
        return bool(took)

    def _publish_frame(self, state: FaceState, now: float, force: bool = False) -> None:
        key = self.renderer.frame_key(state)
        if key == self.last_key and not force:
            return
        frame = self.renderer.render(state)
        self.image_pub.publish(self.bridge.cv2_to_imgmsg(frame, encoding="bgr8"))
        self.last_key, self.last_frame_at = key, now

    def _publish_state(self, state: FaceState, now: float, force: bool = False) -> None:
        if now - self.last_state_at < STATE_EVERY and not force:
            return
        measured = self.robot.head
        if measured is not None:  # the robot's own pan, when it says it
            state = state.replace(head_pan=measured)
        report = {
            **state.as_record(),
            "enabled": self.robot.enabled,
            "following": self.robot.gaze.target,  # not the script's wish: what the robot can follow
            "follow_dynamic": self.robot.gaze.dynamic,
            "follow_seen": self.robot.gaze.seen,
            "playing": not self.live.finished(now),
            "queued": len(self.live.queue),
            "saying": self.saying[0] if self.saying and now < self.saying[1] else None,
        }
        text = json.dumps(report, sort_keys=True)
        if text != self.last_state_text or force:
            self.state_pub.publish(self.String(text))
            self.last_state_text = text
        self.last_state_at = now


def register_again() -> None:
    """Tell the (new) master every topic and service this process has, as rospy does at start."""
    from rospy.impl.registration import (
        Registration,
        RegManager,
        get_registration_listeners,
        get_service_manager,
        get_topic_manager,
    )

    managers = [m for m in get_registration_listeners().listeners if isinstance(m, RegManager)]
    if not managers:
        return
    manager = managers[0]
    for name, kind in get_topic_manager().get_publications():
        manager.reg_added(name, kind, Registration.PUB)
    for name, kind in get_topic_manager().get_subscriptions():
        manager.reg_added(name, kind, Registration.SUB)
    for name, uri in get_service_manager().get_services():
        manager.reg_added(name, uri, Registration.SRV)


def not_kept(error: SettingError, rospy: Any, argv: List[str]) -> SettingError:
    """`error`, after taking a bad value given on this command line off the parameter server.

    rospy puts `_fps:=abc` on the server, where it would outlive this run and
    fail the next one; a value someone else set there is left, and the message
    says how to remove it.
    """
    where = rospy.resolve_name("~" + error.name)
    if any(word.startswith(f"_{error.name}:=") for word in argv):
        rospy.delete_param(where)
        return error
    return SettingError(error.name, f"{error.problem} (on the parameter server: 'rosparam delete {where}')")


def run_node(argv: List[str]) -> int:
    return FaceNode(argv).run()
