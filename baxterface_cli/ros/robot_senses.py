"""The robot's senses for a live session: its topics, and a microphone, as events.

What the face node and `stream` of a script that reacts both hear (ros/face_loop.py runs either):
the navigators' buttons and wheel, the cuffs' buttons, the head sonar's `person near`/`person
gone`, the camera's `face seen`/`face lost` (the camera subscribed to only while a handler or a
wait wants them, or a face is followed), and words from `listen` (ros/node_ears.py). Each reading
becomes events through robot/event_sensors.py and goes to the session's intake; callbacks only
hand over. The core `Robot` (ros/robot_link.py) is made here too, as it takes the camera watch
that raises the face events.
"""

from __future__ import annotations

import functools
import math
import time
from typing import Any, Callable, List, Optional

from ..engine.effects import Speech
from ..engine.session_intake import SessionIntake
from ..language import syntax_tree as n
from ..language.events import NAVIGATORS
from ..robot.camera_watch import CameraWatch
from ..robot.event_sensors import CUFF_INPUTS, CuffPresses, FaceSightings, NavigatorPresses, SonarPresence
from .effect_messages import CUFF_SIDES, CUFF_TOPIC, NAVIGATOR_TOPIC
from .images import image_pixels
from .link import Link
from .node_ears import Ears
from .node_settings import NodeSettings, camera_focal, camera_info_topic
from .robot_link import WARN_EVERY, connect_robot

SONAR_TOPIC = "/robot/sonar/head_sonar/state"
HAND_TYPE = "baxter_core_msgs/EndpointState"
NAVIGATOR_TYPE = "baxter_core_msgs/NavigatorState"
CUFF_TYPE = "baxter_core_msgs/DigitalIOState"


class RobotSenses:
    """The robot's topics (and ears) as events on `intake`'s session; `robot` is its core Robot."""

    def __init__(
        self,
        link: Link,
        intake: SessionIntake,
        settings: NodeSettings,
        speak: Callable[[Speech], None],
        warn: Callable[[str], None],
        info: Callable[[str], None],
    ) -> None:
        """`warn` and `info` log (the ears' lines too): a backlog's, never a ROS call on the loop."""
        self.link = link
        self.intake = intake
        self.session = intake.session
        self.faces = FaceSightings(settings.face_seen_after, settings.face_lost_after)
        self.sonar = SonarPresence(settings.person_near)
        self.presses = NavigatorPresses()
        self.cuffs = CuffPresses()
        self.camera_topic = settings.camera
        hfov, policy = settings.camera_hfov, settings.face_policy
        # The field of view given wins; without it, the camera says its focal length.
        self.camera_info_topic = camera_info_topic(settings.camera) if hfov is None else None
        self.camera_sub: Any = None
        self.camera_info_sub: Any = None

        def camera(hand_to):
            warn_bad = lambda text: link.log("warn", text, every=WARN_EVERY)  # noqa: E731

            def saw(target):  # on the camera's thread: the eyes' target, and `face seen`/`face lost`
                hand_to(target)
                self._raise(self.faces.reading(target is not None, time.monotonic()), "camera")

            return CameraWatch(saw, hfov_deg=hfov, decode=image_pixels, warn=warn_bad, policy=policy)

        self.robot = connect_robot(link, warn=warn, info=info, speak=speak, camera=camera)
        link.subscribe(SONAR_TOPIC, "sensor_msgs/PointCloud", self._sonar_cloud, queue=5)
        if link.has(NAVIGATOR_TYPE):  # Baxter's own messages: ROS 1, or a ROS 2 with baxter_core_msgs
            for navigator in NAVIGATORS:
                pressed = functools.partial(self._navigator, navigator=navigator)
                link.subscribe(NAVIGATOR_TOPIC.format(navigator), NAVIGATOR_TYPE, pressed, queue=10)
        if link.has(CUFF_TYPE):
            for side in CUFF_SIDES:
                for io_name in CUFF_INPUTS:
                    pressed = functools.partial(self._cuff, side=side, io_name=io_name)
                    link.subscribe(CUFF_TOPIC.format(side, io_name), CUFF_TYPE, pressed, queue=10)
        if link.has(HAND_TYPE):
            for side in self.robot.gaze.hands:
                hand = functools.partial(self._hand, side=side)
                link.subscribe(f"/robot/limb/{side}/endpoint_state", HAND_TYPE, hand, queue=1)
        self.ears = None
        if settings.listen:
            self.ears = Ears(
                self.session,
                lambda event, at: self._raise([event], "microphone"),
                settings.listen,
                settings.barge_in,
                log=lambda level, text: (info if level == "info" else warn)(f"listening: {text}"),
            )

    def start(self) -> Optional[str]:
        """Open the ears; why no words will be heard (a missing extra, device or recording), or None."""
        return self.ears.start() if self.ears is not None else None

    def close(self) -> None:
        if self.ears is not None:
            self.ears.close()

    # -- on the loop

    def check(self, now: float) -> None:
        """The events time alone brings about: a face lost, a person gone."""
        self._raise(self.faces.check(now) + self.sonar.check(now), "")

    def watch_camera(self) -> None:
        """Subscribe to the camera while a face is followed or wanted, and only then: images are heavy."""
        robot = self.robot
        faces = self._wants("face seen", "face lost")
        if faces and not robot.gaze.wants_camera and not robot.camera.watching:
            problem = robot.camera.start()
            if problem:
                self.link.log("warn", f"no face events: {problem}", every=WARN_EVERY)
        wanted = robot.gaze.wants_camera or (faces and robot.camera.watching)
        if wanted and self.camera_sub is None:
            self.camera_sub = self.link.subscribe(
                self.camera_topic, "sensor_msgs/Image", self._image, sensor=True
            )
            if self.camera_info_topic is not None:
                self.camera_info_sub = self.link.subscribe(
                    self.camera_info_topic, "sensor_msgs/CameraInfo", self._camera_info, sensor=True
                )
        elif not wanted and self.camera_sub is not None:
            self.camera_sub.close()
            self.camera_sub = None
            if self.camera_info_sub is not None:
                self.camera_info_sub.close()
                self.camera_info_sub = None

    # -- callbacks: hand over, nothing else

    def _raise(self, events: List[n.Event], source: str) -> None:
        for event in events:
            refusal = self.intake.post(event, source)
            if refusal:
                self.link.log("warn", refusal, every=WARN_EVERY)

    def _wants(self, *kinds: str) -> bool:
        """Does a handler, or a wait under way, take one of these events?"""
        s = self.session  # read without its lock: the worker swaps these whole
        waits = [getattr(r, "waiting", None) for r in (s.main, s.active)]
        events = [h.on.event for h in s.handlers] + [w[0].event for w in waits if w is not None]
        return any(e.kind in kinds for e in events)

    def _navigator(self, msg: Any, navigator: str) -> None:
        self._raise(self.presses.reading(navigator, list(msg.buttons), msg.wheel), f"{navigator} navigator")

    def _cuff(self, msg: Any, side: str, io_name: str) -> None:
        self._raise(self.cuffs.reading(side, io_name, msg.state == 1), f"{side} cuff")

    def _sonar_cloud(self, msg: Any) -> None:
        """Check a sonar cloud and hand its (ids, distances) over; skip it, warning, if malformed."""
        following, people = self.robot.gaze.wants_sonar, self._wants("person near", "person gone")
        if not following and not people:
            return
        channels = {c.name: list(c.values) for c in msg.channels}
        if "SensorId" not in channels or "Distance" not in channels:
            problem = f"no SensorId and Distance channels (it has {sorted(channels)})"
        else:
            problem = self.robot.heard_sonar(channels["SensorId"], channels["Distance"])
            if problem is None and people:
                readings = self.sonar.reading(channels["SensorId"], channels["Distance"], time.monotonic())
                self._raise(readings, "head sonar")
        if problem:
            self.link.log("warn", f"skipped a head sonar cloud: {problem}", every=WARN_EVERY)

    def _hand(self, msg: Any, side: str) -> None:  # a hand's pose, for arm following
        p = msg.pose.position
        if all(math.isfinite(v) for v in (p.x, p.y, p.z)):
            self.robot.gaze.hands[side] = (p.x, p.y, p.z)  # the latest only: read at the frame rate
        else:
            self.link.log("warn", f"skipped a {side} hand pose that is not finite", every=WARN_EVERY)

    def _image(self, msg: Any) -> None:
        if self.robot.gaze.wants_camera:
            self.robot.heard_image(msg, time.monotonic())  # decoded and looked at on the camera's thread
        elif self.robot.camera.watching:  # for `face seen` and `face lost` only
            self.robot.camera.give(msg, time.monotonic())

    def _camera_info(self, msg: Any) -> None:
        k = msg.K if hasattr(msg, "K") else msg.k  # ROS 1 spells it K, ROS 2 k
        focal = camera_focal(k, msg.binning_x)
        if focal is None:
            self.link.log(
                "warn",
                f"{self.camera_info_topic} gives no focal length (K[0] is {k[0] if len(k) else None}); "
                "following a face takes a field of view of 76 degrees (camera_hfov sets another)",
                every=WARN_EVERY,
            )
        else:
            self.robot.camera.lens(focal)
