"""The robot's side of the face, without ROS: what to send it, and when.

`Robot` takes a script's effects as they fall due, and what the robot reports
(its head's angle, whether it is enabled), and decides what goes to the robot:

- the head pans and nods only while the robot is not known to be disabled;
- a head pan is asked again every tick until the head is within 8 degrees of
  it, for up to 10 s past its move, as baxter_interface does;
- enable and disable are asked every 0.1 s until the robot agrees, up to 5 s;
- while following, the eyes go to the person, face or hand (`Gaze`), turning
  the head by the one dynamic-look rule; the camera's images go through a
  `CameraWatch` only while a face is followed.

What to send goes out through `send(effect)` (HeadPan, HeadNod, SetEnabled),
speech through `speak(effect)` (to a sound device or sound_play), problems
through `warn(text)`. The clock is passed to every call, so all of
it is tested without a robot; the ROS node and `stream` are thin adapters.
"""

from __future__ import annotations

import math
from collections import deque
from typing import Any, Callable, Deque, Dict, Optional, Sequence, Tuple

from ..core.face_constants import FollowTarget
from ..core.face_state import FaceState
from ..core.geometry import clamp_to_ellipse, dynamic_look, to_pixels, to_radians
from ..engine.effects import (
    Effect,
    EffectHandler,
    HeadNod,
    HeadPan,
    SetEnabled,
    SetFollowing,
    ShutDown,
    Speech,
)
from .camera_watch import CameraWatch
from .following import ArmFollower, HumanFollower

PAN_TOLERANCE = 0.1396263401  # baxter_interface's: 8 degrees
HEAD_TIMEOUT = 10.0  # seconds past a move to keep asking the head, as baxter_interface does
ENABLE_TIMEOUT = 5.0  # seconds to keep asking for enable or disable
ENABLE_EVERY = 0.1  # seconds between asks
FOLLOW_SMOOTHING = 0.25  # of the way to a followed target, each frame
FOLLOW_RELEASE = 0.5  # seconds the eyes take to hand back from following to the script
HEAD_FOLLOW_STEP = 0.1  # radians a followed target must move before the head is asked again
SONAR_BACKLOG = 100  # sonar readings kept between frames

Point = Tuple[float, float]


class Gaze:
    """Where the eyes look while following: smoothed, and handed back smoothly.

    Sonar readings, hand positions and the face the camera sees (`face`, an
    eye target from a `faces.FaceFollower`, or None) are handed in as they
    arrive (from any thread: only appends and assignments); `aim` runs the
    filters once a frame. With nothing to look at, the eyes go where the
    script has them.
    """

    def __init__(self) -> None:
        self.target: Optional[str] = None  # "human", "face", "left arm", "right arm" or None
        self.dynamic = False
        self.human = HumanFollower()
        self.arm = ArmFollower()
        self.sonar: Deque[Tuple[list, list]] = deque(maxlen=SONAR_BACKLOG)
        self.hands: Dict[str, Optional[Tuple[float, float, float]]] = {"left": None, "right": None}
        self.face: Optional[Point] = None  # where the camera sees the face, as an eye target
        # The head angle the sonar and camera look from: None, where the head is (they turn
        # with it); a number for readings recorded with the head held there (`play --follow-from`).
        self.sensors_at: Optional[float] = None
        self.eye: Optional[Point] = None  # where following has the eyes
        self.release: Optional[Tuple[float, Point]] = None  # (since, from) while handing back

    @property
    def wants_sonar(self) -> bool:
        return self.target == "human"

    @property
    def wants_camera(self) -> bool:
        return self.target == "face"

    @property
    def seen(self) -> Optional[bool]:
        """Whether what is followed is seen now (None when following nothing)."""
        if self.target is None:
            return None
        if self.target == "human":
            return self.human.eye_x is not None
        if self.target == "face":
            return self.face is not None
        return self.hands[FollowTarget(self.target).hand] is not None

    def follow(self, target: Optional[str], dynamic: bool, now: float) -> None:
        if (target, dynamic) == (self.target, self.dynamic):
            return
        if target is None and self.eye is not None:
            self.release = (now, self.eye)
        if target == "human":
            self.human = HumanFollower()
            self.sonar.clear()  # readings from before following began are stale
        if target == "face":
            self.face = None  # nor is a face seen before
        self.target, self.dynamic, self.eye = target, dynamic, None

    def aim(
        self, state: FaceState, now: float, head: float, can_pan: bool = True
    ) -> Tuple[FaceState, Optional[float]]:
        """The face with its eyes on what is followed, and where the head should pan (or None)."""
        if self.target is None:
            return self._handing_back(state, now), None
        goal, pan = self._goal(head, can_pan)
        here = self.eye or (state.eye_x, state.eye_y)
        if goal is None:  # nothing to look at (yet, or any more): the script's eyes
            goal = (state.eye_x, state.eye_y)
        here = (
            here[0] + (goal[0] - here[0]) * FOLLOW_SMOOTHING,
            here[1] + (goal[1] - here[1]) * FOLLOW_SMOOTHING,
        )
        self.eye = here
        return state.replace(eye_x=here[0], eye_y=here[1]), pan

    def _handing_back(self, state: FaceState, now: float) -> FaceState:
        if self.release is None:
            return state
        since, (x, y) = self.release
        u = (now - since) / FOLLOW_RELEASE
        if u >= 1.0:
            self.release = None
            return state
        return state.replace(eye_x=x + (state.eye_x - x) * u, eye_y=y + (state.eye_y - y) * u)

    def _facing(self, head: float) -> float:
        return head if self.sensors_at is None else self.sensors_at

    def _goal(self, head: float, can_pan: bool) -> Tuple[Optional[Point], Optional[float]]:
        """Where the eyes should go, and where the head should pan if it must."""
        if self.target == "human":
            eye_x = None
            while self.sonar:
                seen = self.human.update(*self.sonar.popleft())
                eye_x = seen if seen is not None else eye_x
            if eye_x is None:
                return self.eye, None
            want, eye_y = self._facing(head) + to_radians(eye_x), 0.0  # the sonar turns with the head
        elif self.target == "face":
            if self.face is None:
                return None, None
            eye_x, eye_y = self.face
            want = self._facing(head) + to_radians(eye_x)  # so does the camera
        else:
            hand = self.hands[FollowTarget(self.target).hand]
            if hand is None:
                return None, None
            eye_x, eye_y = self.arm.eye_target(*hand)
            want = to_radians(eye_x)  # the hand is in the base frame
        if not (self.dynamic and can_pan):
            return clamp_to_ellipse(to_pixels(want - head), eye_y), None
        pan, eye_x = dynamic_look(want, head)
        return clamp_to_ellipse(eye_x, eye_y), pan


class Robot(EffectHandler):
    """Effects and the robot's reports in; commands to send, at their times, out."""

    def __init__(
        self,
        send: Callable[[Effect], None],
        warn: Callable[[str], None] = lambda text: None,
        info: Callable[[str], None] = lambda text: None,
        speak: Callable[[Speech], None] = lambda effect: None,
        camera: Optional[Callable[..., CameraWatch]] = None,
    ) -> None:
        """`camera(hand_to)` makes the CameraWatch that finds faces (by default, one that
        looks at each image as it is given)."""
        self.send = send
        self.speak = speak
        self.warn = warn
        self.info = info
        self.head: Optional[float] = None  # measured pan, radians; None until heard
        self.enabled: Optional[bool] = None  # None until the robot says
        self.head_goal: Optional[Tuple[HeadPan, float]] = None  # the pan asked for, until when
        self.enable_goal: Optional[Tuple[bool, float, float]] = None  # value, next ask, deadline
        self.gaze = Gaze()
        make_camera = camera or (lambda hand_to: CameraWatch(hand_to, threaded=False, warn=warn))
        self.camera = make_camera(self._saw_face)

    # -- what the robot reports

    def heard_head(self, pan: float) -> bool:
        """The head's measured pan; False (and ignored) if it is not a finite number."""
        if not math.isfinite(pan):
            return False
        self.head = float(pan)
        return True

    def heard_enabled(self, enabled: bool) -> None:
        self.enabled = bool(enabled)

    def heard_sonar(self, sensor_ids: Sequence[float], distances: Sequence[float]) -> Optional[str]:
        """One sonar reading for following; what is wrong with it if it is malformed (then skipped)."""
        ids, distances = list(sensor_ids), list(distances)
        if len(ids) != len(distances):
            return f"{len(ids)} sensor ids but {len(distances)} distances"
        if not all(math.isfinite(v) for v in ids + distances):
            return "a value that is not a finite number"
        if not all(float(v).is_integer() and 0 <= v <= 11 for v in ids):
            return "a sensor id outside 0-11"
        if self.gaze.wants_sonar:  # readings from before following began would be stale
            self.gaze.sonar.append((ids, distances))
        return None

    def heard_image(self, image: Any, now: float) -> None:
        """A camera image (whatever the CameraWatch decodes), looked at only while following a face."""
        if self.gaze.wants_camera:
            self.camera.give(image, now)

    def _saw_face(self, target: Optional[Tuple[float, float]]) -> None:
        self.gaze.face = target

    # -- effects, as they fall due

    def take(self, effect: Effect, now: float) -> None:
        effect.visit(self, now)

    def head_pan(self, effect: HeadPan, now: float) -> None:
        if self.enabled is False:
            self.warn(f"the robot is disabled: not turning the head to {effect.target:.2f} rad")
            return
        self.head_goal = (effect, now + effect.duration + HEAD_TIMEOUT)
        self.send(effect)

    def head_nod(self, effect: HeadNod, now: float) -> None:
        if self.enabled is False:
            self.warn("the robot is disabled: not nodding")
            return
        self.send(effect)

    def set_enabled(self, effect: SetEnabled, now: float) -> None:
        self.enable_goal = (effect.enabled, now, now + ENABLE_TIMEOUT)
        self._ask_enable(now)

    def follow(self, effect: SetFollowing, now: float) -> None:
        if effect.target == "face":
            problem = self.camera.start()
            if problem:
                self.warn(f"not following a face: {problem}")
                effect = SetFollowing(None)
        else:
            self.camera.stop()
        self.gaze.follow(effect.target, effect.dynamic, now)
        self.info(f"following: {effect.target or 'nothing'}" + (" (dynamic)" if effect.dynamic else ""))

    def exit(self, effect: ShutDown, now: float) -> None:
        pass  # the adapter ends itself once the last frame is out

    def speech(self, effect: Speech, now: float) -> None:
        self.speak(effect)  # a disabled robot still talks: speech moves no motor

    # -- every frame

    def look(self, state: FaceState, now: float) -> FaceState:
        """The face with the eyes on what is followed, turning the head when following dynamically."""
        head = self.head if self.head is not None else 0.0
        state, pan = self.gaze.aim(state, now, head, can_pan=self.enabled is not False)
        if pan is not None:
            asked = self.head_goal[0].target if self.head_goal else self.head
            if asked is None or abs(pan - asked) > HEAD_FOLLOW_STEP:
                self.head_pan(HeadPan(pan), now)
        return state

    def tick(self, now: float) -> None:
        """Ask again what the robot has not done yet, or give up and say so."""
        if self.head_goal is not None:
            effect, deadline = self.head_goal
            if self.head is not None and abs(self.head - effect.target) <= PAN_TOLERANCE:
                self.head_goal = None
            elif now > deadline:
                self.warn(f"the head did not reach {effect.target:.2f} rad in time")
                self.head_goal = None
            elif self.enabled is not False:
                self.send(effect)
        self._ask_enable(now)

    def _ask_enable(self, now: float) -> None:
        if self.enable_goal is None:
            return
        value, next_ask, deadline = self.enable_goal
        if self.enabled is value:
            self.enable_goal = None
        elif now > deadline:
            word = "enabled" if value else "disabled"
            self.warn(f"the robot did not report itself {word} within {ENABLE_TIMEOUT:.0f} s")
            self.enable_goal = None
        elif now >= next_ask:
            self.send(SetEnabled(value))
            self.enable_goal = (value, now + ENABLE_EVERY, deadline)
