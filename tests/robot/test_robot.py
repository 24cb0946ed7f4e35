"""The robot's side of the face, without ROS: what is sent, and when, on a clock we hand in."""

from __future__ import annotations

import math

import pytest

from baxterface_cli.core.face_state import FaceState
from baxterface_cli.engine import effects as fx
from baxterface_cli.robot.robot_rules import ENABLE_EVERY, ENABLE_TIMEOUT, HEAD_TIMEOUT, Robot


class Wire:
    """What a Robot sends and says, in order."""

    def __init__(self) -> None:
        self.sent, self.warnings = [], []

    def robot(self) -> Robot:
        return Robot(self.sent.append, warn=self.warnings.append)


def test_the_head_pans_unless_the_robot_says_it_is_disabled():
    wire = Wire()
    robot = wire.robot()
    pan = fx.HeadPan(0.5, 0.25, 2.0)
    robot.take(pan, 0.0)  # nothing heard yet: go ahead
    assert wire.sent == [pan]
    robot.heard_enabled(False)
    robot.take(fx.HeadPan(-0.5), 1.0)
    robot.take(fx.HeadNod(), 1.0)
    assert wire.sent == [pan]
    assert wire.warnings == [
        "the robot is disabled: not turning the head to -0.50 rad",
        "the robot is disabled: not nodding",
    ]


def test_a_head_pan_is_asked_again_until_the_head_is_there():
    wire = Wire()
    robot = wire.robot()
    pan = fx.HeadPan(1.0, 0.5, 2.0)
    robot.take(pan, 0.0)
    robot.heard_head(0.2)
    robot.tick(0.1)
    robot.tick(0.2)
    assert wire.sent == [pan, pan, pan]
    robot.heard_head(0.9)  # within 8 degrees
    robot.tick(0.3)
    robot.tick(0.4)
    assert len(wire.sent) == 3 and wire.warnings == []


def test_a_head_that_never_gets_there_is_given_up_on_with_a_warning():
    wire = Wire()
    robot = wire.robot()
    robot.take(fx.HeadPan(1.0, 0.5, 2.0), 0.0)
    robot.heard_head(0.0)
    robot.tick(2.0 + HEAD_TIMEOUT - 0.01)
    assert wire.warnings == []
    robot.tick(2.0 + HEAD_TIMEOUT + 0.01)
    sent = len(wire.sent)
    robot.tick(20.0)
    assert wire.warnings == ["the head did not reach 1.00 rad in time"] and len(wire.sent) == sent


def test_enable_is_asked_every_tenth_of_a_second_until_the_robot_agrees():
    wire = Wire()
    robot = wire.robot()
    robot.heard_enabled(False)
    robot.take(fx.SetEnabled(True), 0.0)
    for k in range(1, 10):
        robot.tick(k * ENABLE_EVERY / 2)  # ticks twice as often as it asks
    assert wire.sent == [fx.SetEnabled(True)] * 5
    robot.heard_enabled(True)
    robot.tick(1.0)
    assert len(wire.sent) == 5 and wire.warnings == []


def test_enable_gives_up_after_its_timeout_and_says_so():
    wire = Wire()
    robot = wire.robot()
    robot.take(fx.SetEnabled(False), 0.0)
    t = 0.0
    while t < ENABLE_TIMEOUT + 1:
        t += 0.05
        robot.tick(t)
    assert wire.warnings == [f"the robot did not report itself disabled within {ENABLE_TIMEOUT:.0f} s"]
    # Asked every 0.1 s, on ticks 0.05 s apart: at most one ask a tick too late.
    assert ENABLE_TIMEOUT / (ENABLE_EVERY + 0.05) <= len(wire.sent) <= ENABLE_TIMEOUT / ENABLE_EVERY + 1


def test_a_head_state_that_is_not_a_number_is_ignored():
    robot = Wire().robot()
    assert robot.heard_head(0.4)
    assert not robot.heard_head(float("nan")) and not robot.heard_head(float("inf"))
    assert robot.head == 0.4


def test_following_a_hand_moves_the_eyes_smoothly_and_hands_them_back():
    robot = Wire().robot()
    face = FaceState()
    robot.take(fx.SetFollowing("left arm"), 0.0)
    robot.gaze.hands["left"] = (0.5, 0.5, 0.75)  # out to the robot's left, at face height
    xs = [robot.look(face, 0.1 * k).eye_x for k in range(30)]
    assert xs[0] > 0 and all(a < b for a, b in zip(xs, xs[1:])) and xs[-1] == pytest.approx(45, abs=0.5)
    robot.take(fx.SetFollowing(None), 3.0)
    assert robot.look(face, 3.0).eye_x == pytest.approx(xs[-1])  # no jump
    assert 0 < robot.look(face, 3.25).eye_x < xs[-1]
    assert robot.look(face, 3.5).eye_x == 0.0  # the script's eyes again


def test_following_a_person_on_sonar_recentres_when_they_walk_out_of_the_eyes_reach():
    wire = Wire()
    robot = wire.robot()
    robot.take(fx.SetFollowing("human", dynamic=True), 0.0)
    for k in range(60):  # someone far to the robot's left, on sensor 9
        assert robot.heard_sonar([9, 10], [1.0, 1.1]) is None
        robot.look(FaceState(), 0.03 * k)
    pans = [e for e in wire.sent if isinstance(e, fx.HeadPan)]
    assert pans and pans[0].target > 0.25  # the head turned toward them
    assert robot.heard_sonar([9], [1.0, 2.0]) == "1 sensor ids but 2 distances"
    assert robot.heard_sonar([42], [1.0]) == "a sensor id outside 0-11"


def test_following_dynamically_while_disabled_moves_only_the_eyes():
    wire = Wire()
    robot = wire.robot()
    robot.heard_enabled(False)
    robot.take(fx.SetFollowing("left arm", dynamic=True), 0.0)
    robot.gaze.hands["left"] = (0.2, 0.6, 0.75)  # far to the left: beyond the eyes' reach
    for k in range(40):
        face = robot.look(FaceState(), 0.03 * k)
    assert wire.sent == []
    assert face.eye_x == pytest.approx(math.degrees(math.atan2(0.6, 0.2)), abs=1)  # 71.6: where it is


class FakeCamera:
    """A CameraWatch stand-in: each image given is already the eye target it shows (or None)."""

    def __init__(self, hand_to, problem=None) -> None:
        self.hand_to, self.problem, self.started, self.stopped = hand_to, problem, 0, 0

    def start(self):
        self.started += 1
        return self.problem

    def stop(self) -> None:
        self.stopped += 1

    def give(self, image, at) -> None:
        self.hand_to(image)


def test_following_a_face_looks_where_the_camera_sees_it_and_back_at_the_script_when_it_goes():
    robot = Robot(lambda effect: None, camera=FakeCamera)
    robot.heard_image((30.0, -20.0), 0.0)  # not following a face: ignored
    assert robot.gaze.face is None and robot.gaze.seen is None
    robot.take(fx.SetFollowing("face"), 0.0)
    assert robot.camera.started == 1
    robot.heard_image((30.0, -20.0), 0.0)  # up and to the robot's left
    for k in range(40):
        face = robot.look(FaceState(eye_x=-50.0), k / 30)
    assert (face.eye_x, face.eye_y) == pytest.approx((30.0, -20.0), abs=0.1) and robot.gaze.seen is True
    robot.heard_image(None, 1.4)  # let go: back to where the script has the eyes
    for k in range(40):
        face = robot.look(FaceState(eye_x=-50.0), 1.4 + k / 30)
    assert (face.eye_x, face.eye_y) == pytest.approx((-50.0, 0.0), abs=0.1) and robot.gaze.seen is False
    robot.take(fx.SetFollowing("human"), 3.0)
    assert robot.camera.stopped == 1 and not robot.gaze.wants_camera


def test_following_a_face_dynamically_turns_the_head_from_where_the_camera_points():
    wire = Wire()
    robot = Robot(wire.sent.append, camera=FakeCamera)
    robot.heard_head(0.2)
    robot.take(fx.SetFollowing("face", dynamic=True), 0.0)
    robot.heard_image((20.0, 0.0), 0.0)  # 20 eye pixels left of where the head (and camera) points
    robot.look(FaceState(), 0.0)
    (pan,) = [e for e in wire.sent if isinstance(e, fx.HeadPan)]
    assert pan.target == pytest.approx(0.2 + 20.0 * 3 / 160)


def test_a_face_cannot_be_followed_without_opencv_and_the_robot_says_so():
    wire = Wire()
    robot = Robot(
        wire.sent.append,
        warn=wire.warnings.append,
        camera=lambda hand_to: FakeCamera(
            hand_to, "following a face needs the 'cv2' module: pip install ..."
        ),
    )
    robot.take(fx.SetFollowing("face"), 0.0)
    assert wire.warnings == ["not following a face: following a face needs the 'cv2' module: pip install ..."]
    assert robot.gaze.target is None


def test_the_camera_watch_finds_the_face_on_its_thread_and_survives_bad_images():
    import threading

    from baxterface_cli.robot.camera_watch import CameraWatch
    from conftest import ROOT, needs

    cv2 = needs("cv2")

    picture = cv2.imread(str(ROOT / "scripts_examples" / "someone.jpg"))
    seen, warnings, arrived, warned = [], [], threading.Event(), threading.Event()

    def hand_to(target):
        seen.append(target)
        if target is not None:
            arrived.set()

    watch = CameraWatch(hand_to, warn=lambda text: (warnings.append(text), warned.set()))
    assert watch.start() is None and seen == [None]
    watch.give("not an image", 0.0)
    assert warned.wait(10)
    for k in range(200):  # the newest image is what counts; the worker may skip some
        watch.give(picture, k / 30)
        if arrived.wait(0.02):
            break
    watch.close()
    assert arrived.is_set() and seen[-1][0] == pytest.approx(25.6, abs=2.0)
    assert len(warnings) == 1 and warnings[0].startswith("skipped a camera image: ")
