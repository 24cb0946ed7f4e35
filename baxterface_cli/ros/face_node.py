"""`baxterface node`: the face node on ROS 1 or ROS 2, replacing the old screen_listener.py.

It listens on `display_chatter` (old commands and scripts alike), draws with
the same engine as `play`, publishes changed frames on /robot/xdisplay as
bgr8 through one latched publisher, drives the head, nod and enable
topics through the core `Robot` (robot_link), speaks through the `audio`
mode's speaker, and reports what the face is doing on `~state` (JSON,
latched). All work happens in one loop; subscriber callbacks only hand
messages over. The head camera (`camera` parameter) is subscribed to only
while a face is followed, and its images are looked at on the camera
watch's own thread, never on the loop. The camera's focal length comes from
its `camera_info` (beside the image topic) when it publishes one, unless the
`camera_hfov` parameter gives the field of view. ROS itself is behind a
`Link` (link.py): the same node runs on either version.

Scripts run on one live session (engine/live_session.py): a handler sent on `display_chatter`
installs itself, other commands take over, `signal NAME` raises the signal. The session's steps
are compiled on the intake's worker (engine/session_intake.py), never on the loop. The node
raises the events its topics give (robot/event_sensors.py): the navigators' buttons and wheel,
the head sonar's `person near`/`person gone`, and the camera's `face seen`/`face lost`, for
which the camera is watched while a handler or a wait wants them.
"""

from __future__ import annotations

import functools
import gc
import json
import math
import signal
import sys
import threading
import time
from typing import Any, List, Optional, Tuple

from ..core.face_constants import BROWS, MOUTHS, SKINS
from ..core.face_state import FaceState
from ..drawing.renderer import Renderer
from ..engine.change_polling import FirstMotion
from ..engine.effects import Speech
from ..engine.live_face import sleep_face
from ..engine.live_session import LiveSession
from ..engine.log_backlog import Backlog
from ..engine.session_intake import SessionIntake
from ..language import syntax_tree as n
from ..robot.camera_watch import CameraWatch
from ..robot.event_sensors import FaceSightings, NavigatorPresses, SonarPresence
from ..robot.mtcnn_detector import detector_note
from ..speech.recordings import Recordings
from .compressed import CompressedFrames
from .connect import open_link
from .images import image_fields, image_pixels
from .link import CHATTER, NODE_NAME, QUEUE, STATE, Link
from .node_settings import NodeSettings, SettingError, camera_focal, camera_info_topic, theme_layers
from .robot_link import WARN_EVERY, connect_robot
from .speakers import UnknownAudio, default_audio, open_speaker
from .transport import PARAMETER, TransportError, from_ros_args

STATE_EVERY = 0.1  # seconds between ~state messages while the face moves
# The loop takes the GIL back several times a frame from threads that parse
# commands and receive messages; each time it may wait a whole switch
# interval (5 ms by default). 1 ms halved the worst frame gap under a flood.
SWITCH_INTERVAL = 0.001
# A full garbage collection walks every object that queued scripts hold and
# stops the loop while it does (about 100 ms with a full queue of big ones).
# Python's first two generations still collect young cycles; the full one is
# left for this many of theirs rather than 10.
FULL_COLLECTION_EVERY = 1000
SONAR_TOPIC = "/robot/sonar/head_sonar/state"
HAND_TYPE = "baxter_core_msgs/EndpointState"
NAVIGATOR_TYPE = "baxter_core_msgs/NavigatorState"
NAVIGATOR_TOPIC = "/robot/navigators/{}_navigator/state"
NAVIGATORS = ("left", "right", "torso_left", "torso_right")


def selftest_script() -> str:
    """Every layer once, then the sleep face: the original's start-up flash."""
    steps = [f"skin {i}; wait 0.12s" for i in SKINS]
    steps += [f"mouth {m}; wait 0.12s" for m in MOUTHS] + [f"brows {b}; wait 0.12s" for b in BROWS]
    steps += ["look left in 0.2s", "look right in 0.3s", "look center in 0.2s", "blink", "sleep"]
    return "; ".join(steps)


def recordings_hint(version: int) -> str:
    """How a node of ROS `version` is told where recordings may be read."""
    return "_recordings:=FOLDER" if version == 1 else "--ros-args -p recordings:=FOLDER"


class FaceNode:
    """The node's state and its one loop."""

    def __init__(self, link: Link) -> None:
        self.link = link
        try:
            get = link.param
            settings = NodeSettings.read(get, NodeSettings(audio=default_audio(link.version)))
            layers = theme_layers(settings)
            self.log = Backlog(link.log)  # never logs from the loop
            self.speaker = open_speaker(settings.audio, link, self.log.warn)
        except UnknownAudio as e:
            raise SettingError("audio", str(e).split(" ", 1)[1]) from None
        except SettingError as e:
            kept = link.forget_bad(e.name)
            raise e if kept is None else SettingError(e.name, f"{e.problem} ({kept})") from None
        self.fps = settings.fps
        self.renderer = Renderer(layers)
        self.renderer.prepare_in_background()
        # Commands come from anyone on the ROS network: `say file` reads only under ~recordings.
        recordings = Recordings(
            settings.recordings,
            confined=True,
            warn=self.log.warn,
            refusal=f"this face node reads no recordings; start it with {recordings_hint(link.version)}",
        )
        self.session = LiveSession(
            start=sleep_face(), idle=settings.idle, now=time.monotonic(), recordings=recordings, seed=None
        )
        self.live = self.session.face  # read by the loop without the session's lock
        self.faces = FaceSightings(settings.face_seen_after, settings.face_lost_after)
        self.sonar = SonarPresence(settings.person_near)
        self.presses = NavigatorPresses()
        self.image_pub = link.publisher(settings.display_topic, "sensor_msgs/Image", latched=True, queue=1)
        self.jpeg = CompressedFrames(link, self.image_pub.topic)  # JPEGs only while someone subscribes
        self.state_pub = link.publisher(STATE, "std_msgs/String", latched=True, queue=1)
        self.saying: Optional[Tuple[str, float]] = None  # (text, when it ends) while the face speaks
        self.camera_topic = settings.camera
        hfov, policy = settings.camera_hfov, settings.face_policy
        # The field of view given wins; without it, the camera says its focal length.
        self.camera_info_topic = camera_info_topic(settings.camera) if hfov is None else None
        self.camera_sub: Any = None
        self.camera_info_sub: Any = None

        def camera(hand_to):
            warn = lambda text: link.log("warn", text, every=WARN_EVERY)  # noqa: E731

            def saw(target):  # on the camera's thread: the eyes' target, and `face seen`/`face lost`
                hand_to(target)
                self._raise(self.faces.reading(target is not None, time.monotonic()), "camera")

            return CameraWatch(saw, hfov_deg=hfov, decode=image_pixels, warn=warn, policy=policy)

        self.robot = connect_robot(
            link, warn=self.log.warn, info=self.log.info, speak=self._speak, camera=camera
        )

        self.wake = threading.Event()
        self.stopping = False  # set by SIGINT and SIGTERM
        self.intake = SessionIntake(self.session, time.monotonic, ready=self.wake.set, log=self._logged)
        self.shown_timeline: Any = self.live.timeline  # a new one: a step began (speech cut, state sent)
        self.last_key: Any = None
        self.last_frame_at = -math.inf
        self.first_motion = FirstMotion()  # after a command, looked at often until it shows
        self.last_state_text = ""
        self.last_state_at = -math.inf

        link.subscribe(CHATTER, "std_msgs/String", lambda msg: self._heard(msg, False), queue=100)
        link.subscribe(QUEUE, "std_msgs/String", lambda msg: self._heard(msg, True), queue=100)
        link.subscribe(SONAR_TOPIC, "sensor_msgs/PointCloud", self._sonar_cloud, queue=5)
        if link.has(NAVIGATOR_TYPE):  # Baxter's own message, as the hands'
            for navigator in NAVIGATORS:
                pressed = functools.partial(self._navigator, navigator=navigator)
                link.subscribe(NAVIGATOR_TOPIC.format(navigator), NAVIGATOR_TYPE, pressed, queue=10)
        if link.has(HAND_TYPE):  # Baxter's own message: ROS 1, or a ROS 2 with baxter_core_msgs
            for side in self.robot.gaze.hands:
                hand = functools.partial(self._hand, side=side)
                link.subscribe(f"/robot/limb/{side}/endpoint_state", HAND_TYPE, hand, queue=1)
        if settings.selftest:
            self.session.submit(selftest_script(), time.monotonic(), filename="selftest")

    # -- callbacks: hand over and wake the loop, nothing else

    def _heard(self, msg: Any, queued: bool) -> None:  # display_chatter and ~queue
        refusal = self.intake.submit(msg.data, queued)  # parsed off the frame loop
        if refusal:
            self.log.warn(refusal)

    def _raise(self, events: List[n.Event], source: str) -> None:
        for event in events:
            refusal = self.intake.post(event, source)
            if refusal:
                self.link.log("warn", refusal, every=WARN_EVERY)

    def _logged(self, level: str, text: str) -> None:  # the session's worker: the backlog logs it
        getattr(self.log, level if level in ("info", "error") else "warn")(text)

    def _navigator(self, msg: Any, navigator: str) -> None:
        self._raise(self.presses.reading(navigator, list(msg.buttons), msg.wheel), f"{navigator} navigator")

    def _wants(self, *kinds: str) -> bool:
        """Does a handler, or a wait under way, take one of these events?"""
        s = self.session  # read without its lock: the worker swaps these whole
        waits = [getattr(r, "waiting", None) for r in (s.main, s.active)]
        events = [h.on.event for h in s.handlers] + [w[0].event for w in waits if w is not None]
        return any(e.kind in kinds for e in events)

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

    def _watch_camera(self) -> None:
        """Subscribe to the camera while a face is followed, and only then: images are heavy."""
        faces = self._wants("face seen", "face lost")
        if faces and not self.robot.gaze.wants_camera and not self.robot.camera.watching:
            problem = self.robot.camera.start()
            if problem:
                self.link.log("warn", f"no face events: {problem}", every=WARN_EVERY)
        wanted = self.robot.gaze.wants_camera or (faces and self.robot.camera.watching)
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

    def _speak(self, effect: Speech) -> None:
        # Timed here, not by the script's status: a take-over restarts the script's clock.
        self.saying = (effect.utterance.said, time.monotonic() + effect.duration)
        self.speaker.speak(effect)

    # -- the loop

    def run(self) -> int:
        self.link.leaving = "face node finished"
        # Left in the reverse order: the speaker, the JPEGs, the camera, then ROS.
        with self.link, self.robot.camera, self.jpeg, self.speaker:
            return self._run()

    def _run(self) -> int:
        sys.setswitchinterval(SWITCH_INTERVAL)
        young, middle, _ = gc.get_threshold()
        gc.set_threshold(young, middle, FULL_COLLECTION_EVERY)
        # A plain flag: a handler runs between any two steps of the loop, inside `wake.wait()`
        # too, where setting an Event would wait for the lock that very wait holds. The loop
        # looks at the flag at least once a tick.
        for signum in (signal.SIGINT, signal.SIGTERM):
            signal.signal(signum, lambda *_: setattr(self, "stopping", True))
        carried = f"; ROS 2 transport: {self.link.transport}" if self.link.transport else ""
        self.link.log("info", f"baxterface face node: listening on {self.link.resolve(CHATTER)}{carried}")
        self.link.log("info", f"baxterface face node: {detector_note()}")
        self.link.stay_connected(self.log.info)
        period = 1.0 / self.fps
        next_tick = time.monotonic()
        while not self.stopping and self.link.ok():
            now = time.monotonic()
            took = self._take_commands(now)
            self._raise(self.faces.check(now) + self.sonar.check(now), "")
            face, cues = self.session.frame(now)
            for cue in cues:
                self.robot.take(cue.effect, now)
            self._watch_camera()
            state = self.robot.look(face, now)
            self.robot.tick(now)
            if self.live.exited:
                self._publish_frame(state, now, force=True)
                self._publish_state(state, now, force=True)
                time.sleep(0.5)  # let the last frame reach its subscribers
                break
            # The cap: frames at most `fps` a second (a little slack for a
            # tick that comes early; ticks themselves keep the average).
            if now >= self.last_frame_at + 0.75 * period and self._publish_frame(state, now):
                self.first_motion.shown()
            self._publish_state(state, now)
            self.jpeg.tick(now)
            # Ticks keep their own rhythm, publishing or not, whatever woke the loop
            # between them; a late loop skips the ticks it missed rather than hurrying.
            if now >= next_tick:
                next_tick += period
                if next_tick < now:
                    next_tick = now + period
            if took:
                self.first_motion.heard(now)
            wake_at = self.first_motion.next_look(next_tick, now)
            self.wake.wait(max(0.0, wake_at - time.monotonic()))  # or until a command comes
            self.wake.clear()
        self.intake.close()
        self.log.flush(timeout=0.3)
        self.log.close()
        return 0

    def _take_commands(self, now: float) -> bool:
        """True if the session began a step since the last look (its worker did)."""
        timeline = self.live.timeline
        if timeline is self.shown_timeline:
            return False
        self.shown_timeline = timeline
        self.last_state_at = -math.inf  # report the change at once
        if self.saying is not None and now < self.saying[1]:  # cut off with the step that said it
            self.saying = None
            self.speaker.stop()
        return True

    def _publish_frame(self, state: FaceState, now: float, force: bool = False) -> bool:
        """Publish the frame of `state` if it changed (or `force`); True if one went out."""
        key = self.renderer.frame_key(state)
        if key == self.last_key and not force:
            return False
        frame = self.renderer.render(state)
        self.image_pub.publish(**image_fields(frame))
        self.jpeg.offer(frame)
        self.last_key, self.last_frame_at = key, now
        return True

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
            "queued": len(self.intake.waiting),
            "handlers": self.intake.counts,
            "saying": self.saying[0] if self.saying and now < self.saying[1] else None,
        }
        text = json.dumps(report, sort_keys=True)
        if text != self.last_state_text or force:
            self.state_pub.publish(data=text)
            self.last_state_text = text
        self.last_state_at = now


def run_node(argv: List[str], version: int = 1) -> int:
    """Run the face node on ROS `version` with the command line's ROS arguments `argv`."""
    if version == 2:
        try:
            from_ros_args(argv)  # read again as the link joins; a bad one is a bad parameter
        except TransportError as e:
            raise SettingError(PARAMETER, e.problem) from None
    link = open_link(version, NODE_NAME, argv, node=True)
    try:
        node = FaceNode(link)
    except BaseException:  # closed here only if the node cannot start; else `run` closes it
        link.close("the face node could not start")
        raise
    return node.run()
