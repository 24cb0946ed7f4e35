"""Following without a robot: `play --follow-from FILE`.

A recorded trace (sonar readings and hand positions, one JSON object a
line) or camera images (a video, or one picture) stand in for the robot's
sensors. They go, on the script's clock, to the same `Robot` the face node
uses, so the eyes follow exactly as they would on the robot; a head that
following turns is shown in the status line. The file is taken to be
recorded with the head straight ahead: turning the head turns the eyes'
aim, not what the file shows.

A trace line is `{"t": SECONDS, ...}` with one of
`"sonar": [[SENSOR_ID, ...], [DISTANCE_M, ...]]`, `"left": [X, Y, Z]`
or `"right": [X, Y, Z]` (a hand's position in metres, the robot's base frame).
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any, Callable, Iterator, List, Optional, Tuple

from ..core.face_state import FaceState
from ..engine.effects import Effect, HeadPan, SetFollowing
from ..engine.timeline import RobotStatus
from ..extras import need
from .camera_watch import CameraWatch
from .person_choice import DEFAULT_FACE_POLICY, check_face_policy
from .robot_rules import Robot

TRACE_SUFFIXES = (".jsonl", ".ndjson")
PICTURE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".webp")
STILL_RATE = 30.0  # images a second from one picture
MAX_TRACE_LINES = 1_000_000  # hours of readings: more is not a trace but a mistake

Event = Tuple[float, str, Any]  # (seconds, "sonar" | "left" | "right" | "image", value)


class FollowSourceError(ValueError):
    """A --follow-from file that cannot be used; the message is one line, with where."""


class SensorTrace:
    """A recorded trace of the robot's sensors (sonar, hands), read whole: its readings in time order."""

    kinds = ("sonar", "left", "right")

    def __init__(self, path: Path) -> None:
        self.events: List[Event] = []
        try:
            lines = path.read_text(encoding="utf-8").splitlines()
        except (OSError, UnicodeDecodeError) as e:
            raise FollowSourceError(f"{path}: cannot read it: {e}") from None
        if len(lines) > MAX_TRACE_LINES:
            raise FollowSourceError(f"{path}: over {MAX_TRACE_LINES} lines")
        for number, line in enumerate(lines, 1):
            if line.strip():
                self.events.append(self._event(line, f"{path}:{number}"))
        self.events.sort(key=lambda event: event[0])  # stable: equal times keep their order
        self.has = {kind for _, kind, _ in self.events}

    def _event(self, line: str, where: str) -> Event:
        try:
            item = json.loads(line)
        except ValueError as e:
            raise FollowSourceError(f"{where}: not JSON: {e}") from None
        if not isinstance(item, dict):
            raise FollowSourceError(f'{where}: a line must be a JSON object, like {{"t": 0.5, ...}}')
        t = item.get("t")
        if not isinstance(t, (int, float)) or isinstance(t, bool) or not math.isfinite(t) or t < 0:
            raise FollowSourceError(f"{where}: 't' must be a time in seconds from 0, not {t!r}")
        kinds = [kind for kind in self.kinds if kind in item]
        if len(kinds) != 1:
            raise FollowSourceError(f"{where}: a line needs one of 'sonar', 'left' or 'right'")
        kind, value = kinds[0], item[kinds[0]]
        if kind == "sonar":
            ok = isinstance(value, list) and len(value) == 2 and all(isinstance(v, list) for v in value)
            if not ok or not all(_number(v) for v in value[0] + value[1]):
                raise FollowSourceError(f"{where}: 'sonar' must be [[sensor ids], [distances]] of numbers")
            return float(t), kind, (value[0], value[1])
        if not (isinstance(value, list) and len(value) == 3 and all(_number(v) for v in value)):
            raise FollowSourceError(f"{where}: '{kind}' must be [x, y, z] in metres")
        return float(t), kind, tuple(float(v) for v in value)

    def rewind(self) -> Iterator[Event]:
        return iter(self.events)


def _number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


class Pictures:
    """Camera images from a video (each at its own time) or one picture (always there)."""

    has = frozenset({"image"})

    def __init__(self, path: Path) -> None:
        self.cv2 = need("cv2", "camera", "--follow-from with camera images")
        self.path = path
        self.still = None
        if path.suffix.lower() in PICTURE_SUFFIXES:
            self.still = self.cv2.imread(str(path), self.cv2.IMREAD_COLOR)
            if self.still is None:
                raise FollowSourceError(f"{path}: cannot read it as a picture")
        else:
            self._open()  # fail now, not at the first frame

    def _open(self) -> Any:
        capture = self.cv2.VideoCapture(str(self.path))
        if not capture.isOpened():
            raise FollowSourceError(f"{self.path}: cannot read it as a video (or a .jsonl trace)")
        return capture

    def rewind(self) -> Iterator[Event]:
        if self.still is not None:
            return self._stills()
        return self._frames(self._open())

    def _stills(self) -> Iterator[Event]:
        index = 0
        while True:  # the same picture, as a camera that sees a still scene would give it
            yield index / STILL_RATE, "image", self.still
            index += 1

    def _frames(self, capture: Any) -> Iterator[Event]:
        try:
            fps = capture.get(self.cv2.CAP_PROP_FPS) or 30.0
            index = 0
            while True:
                ok, image = capture.read()
                if not ok:
                    return
                yield index / fps, "image", image
                index += 1
        finally:
            capture.release()


def open_source(path: str) -> Any:
    """A SensorTrace or Pictures for FILE, or FollowSourceError / MissingTool saying why not."""
    file = Path(path)
    if not file.is_file():
        raise FollowSourceError(f"{path}: no such file")
    if file.suffix.lower() in TRACE_SUFFIXES:
        return SensorTrace(file)
    return Pictures(file)


class Rehearsal:
    """The script's following, played against a recorded source instead of a robot.

    `look(state, t, status)` is called once a frame with the script's face,
    time and robot status; it returns the face with the eyes where following
    puts them. Time going back (a loop, a reload) starts the source again.
    `face_policy` chooses among several faces in camera images (person_choice).
    """

    def __init__(
        self,
        source: Any,
        warn: Callable[[str], None] = lambda text: None,
        face_policy: str = DEFAULT_FACE_POLICY,
    ) -> None:
        self.source = source
        self.warn = warn
        self.face_policy = check_face_policy(face_policy)
        self.robot = self._robot()
        self.turned: Optional[float] = None  # the head pan following asked for, if any
        self.following: Tuple[Optional[str], bool] = (None, False)
        self.events: Iterator[Event] = iter(())
        self.pending: Optional[Event] = None
        self.last_t = math.inf  # so the first call starts the source
        self.warned = False

    def _sent(self, effect: Effect) -> None:
        if isinstance(effect, HeadPan):  # the head "turns" at once: there is no head to wait for
            self.turned = effect.target
            self.robot.heard_head(effect.target)

    def look(self, state: FaceState, t: float, status: RobotStatus) -> FaceState:
        if t < self.last_t:
            self._restart()
        self.last_t = t
        wanted = (status.following, status.follow_dynamic)
        if wanted != self.following:
            self.following = wanted
            self._check(wanted[0])
            self.robot.follow(SetFollowing(*wanted), t)
            if not wanted[1]:
                self.turned = None
        if self.turned is None:
            self.robot.heard_head(state.head_pan)  # the script's head, until following turns it
        self._feed(t)
        state = self.robot.look(state, t)
        return state if self.turned is None else state.replace(head_pan=self.turned)

    def note(self) -> str:
        """What following sees now, for the status line."""
        seen = self.robot.gaze.seen
        if seen is None:
            return ""
        return f"sees the {self.following[0]}" if seen else f"no {self.following[0]} seen"

    def _robot(self) -> Robot:
        def camera(hand_to):
            return CameraWatch(hand_to, threaded=False, warn=self.warn, policy=self.face_policy)

        robot = Robot(self._sent, warn=self.warn, camera=camera)
        robot.gaze.sensors_at = 0.0  # the file's sensors do not turn with our imaginary head
        return robot

    def _restart(self) -> None:
        self.robot = self._robot()
        self.turned, self.following = None, (None, False)
        self.events, self.pending = self.source.rewind(), None

    def _check(self, target: Optional[str]) -> None:
        needs = {"human": "sonar", "face": "image", "left arm": "left", "right arm": "right"}.get(str(target))
        if needs and needs not in self.source.has and not self.warned:
            what = {"sonar": "sonar readings", "image": "camera images"}.get(needs, f"{needs} hand positions")
            self.warn(f"following the {target}, but the --follow-from file has no {what}")
            self.warned = True

    def _feed(self, t: float) -> None:
        """Hand over what the source has up to `t`: every reading, but only the newest image,
        as the face node does with a camera faster than it can look."""
        image = None
        while True:
            event = self.pending or next(self.events, None)
            self.pending = None
            if event is None or event[0] > t:
                self.pending = event
                break
            at, kind, value = event
            if kind == "image":
                image = (value, at)
            elif kind == "sonar":
                problem = self.robot.heard_sonar(*value)
                if problem and not self.warned:
                    self.warn(f"skipped a sonar reading at {at:.2f} s: {problem}")
                    self.warned = True
            else:
                self.robot.gaze.hands[kind] = value
        if image is not None:
            self.robot.heard_image(*image)
