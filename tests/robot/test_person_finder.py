"""Following a face with the head camera: the goals on synthetic streams (tests/support/face_streams.py,
and far_streams.py for faces 24 to 46 pixels wide).

The streams are real face photos (scikit-image's) pasted at known places over
real backgrounds, so each frame's truth is known. The goals: a target in at
least 95 % of the frames with a face in full view after the first second,
within 2 eye pixels RMS of the truth; let go within a second of a face
leaving; never a target from a cat, a page of text or anything else that is
not a face; no swapping between two faces of about the same size; a nearer
face followed within half a second. The streams are cut short here (the
bench runs them whole); times are the bench's (bench/follow_camera.py),
never asserted here.
"""

from __future__ import annotations

import importlib
import math
import sys
from typing import Dict, Tuple

import numpy as np
import pytest

from baxterface_cli.core.geometry import inside_ellipse
from baxterface_cli.extras import MissingTool
from baxterface_cli.robot.following import DEGREES_PER_RADIAN, PIXELS_PER_ELEVATION
from baxterface_cli.robot.haar_detector import Cascades
from baxterface_cli.robot.person_finder import BAXTER_HEAD_CAMERA_HFOV, FaceFollower, eye_target, focal_length
from conftest import needs

# One worker runs the module, so the followers' runs over each stream are made once, not once a worker.
pytestmark = pytest.mark.xdist_group("face_streams")

_RESULTS: Dict[Tuple[str, str], object] = {}


def streams():
    """The stream module, or a skip without OpenCV or scikit-image."""
    needs("cv2")
    needs("skimage")
    import face_streams

    return face_streams


# Seconds of each stream the tests look at: enough for what happens in it.
SECONDS = {
    "moving": 3.0,
    "tilting": 3.0,
    "shrinking": 4.0,
    "brightness": 3.5,
    "two faces": 3.0,
    "cat": 3.0,
    "text poster": 3.0,
    "posters 9": 3.0,
    "posters 0": 3.0,
    "combined": 4.0,
    "nearer face": 3.0,
    "far moving": 3.0,
    "far tilting": 3.0,
    "far tilted": 3.0,
    "far two": 3.0,
    "far nearer": 3.5,
    "far distractors": 3.0,
    "crowd": 3.0,
}


def stream_named(name: str):
    fs = streams()
    import far_streams

    makers = (*fs.SCENARIOS, fs.nearer, fs.centred, *far_streams.FAR_SCENARIOS, far_streams.crowd)
    stream = {make().name: make for make in makers}[name]()
    stream.seconds = SECONDS.get(name, stream.seconds)
    return stream


def result(name: str, policy: str = "nearest"):
    """Our follower over the named scenario, run once a session."""
    if (name, policy) not in _RESULTS:
        _RESULTS[name, policy] = streams().run(stream_named(name), FaceFollower(policy=policy).update)
    return _RESULTS[name, policy]


WITH_A_FACE = ["moving", "tilting", "shrinking", "brightness", "two faces", "leaving", "combined"]
FAR = ["far moving", "far tilting", "far tilted", "walking away", "far two", "far leaving"]
DISTRACTORS = ["cat", "text poster", "posters 9", "posters 0", "far distractors"]

# -- the geometry -----------------------------------------------------------------------------------


def test_the_default_field_of_view_is_baxters_head_camera_at_640x400():
    across = 2 * math.degrees(math.atan(320 / 410))  # focal 410 px, 640 px wide
    assert abs(BAXTER_HEAD_CAMERA_HFOV - across) < 0.1


def test_a_point_at_the_image_centre_is_straight_ahead_at_any_size():
    for width, height in ((640, 400), (1280, 800), (320, 240), (7, 5)):
        assert eye_target(width / 2, height / 2, width, height) == pytest.approx((0.0, 0.0))


def test_the_image_left_edge_is_half_the_field_of_view_to_the_robots_left():
    x, y = eye_target(0, 200, 640, 400)
    assert x == pytest.approx(BAXTER_HEAD_CAMERA_HFOV / 2, abs=0.01) and y == pytest.approx(0.0)
    x, y = eye_target(640, 200, 640, 400)
    assert x == pytest.approx(-BAXTER_HEAD_CAMERA_HFOV / 2, abs=0.01)
    # In degrees, as the arm follower's azimuth: 20 degrees of field of view, 10 at the edge.
    assert eye_target(0, 200, 640, 400, hfov_deg=20)[0] == pytest.approx(10.0, abs=0.01)


def test_up_is_negative_eye_y_in_the_arm_followers_units():
    f = 320 / math.tan(math.radians(BAXTER_HEAD_CAMERA_HFOV / 2))
    x, y = eye_target(320, 0, 640, 400)
    assert x == pytest.approx(0.0)
    assert y == pytest.approx(-PIXELS_PER_ELEVATION * math.atan(200 / f)) and y < 0
    assert eye_target(320, 400, 640, 400)[1] == pytest.approx(-y)
    # A point up and to the left, off the camera's axis by known angles.
    u, v = 320 - f * math.tan(math.radians(20)), 200 - f * math.tan(math.radians(10))
    x, y = eye_target(u, v, 640, 400)
    assert x == pytest.approx(20 / 57.2958 * DEGREES_PER_RADIAN, abs=1e-3)
    assert y == pytest.approx(-PIXELS_PER_ELEVATION * math.radians(10), abs=1e-3)


def test_a_focal_length_in_pixels_is_the_field_of_view_of_the_images_width():
    assert focal_length(640, BAXTER_HEAD_CAMERA_HFOV) == pytest.approx(410.0, abs=0.5)
    for u, v in ((100, 50), (600, 390), (320, 200)):
        assert eye_target(u, v, 640, 400, focal=410.0) == pytest.approx(eye_target(u, v, 640, 400), abs=0.05)
    # Binned by 2 (focal 205 px): the same pixel is twice as far from the axis in the world.
    x, _ = eye_target(320 - 205, 200, 640, 400, focal=205.0)
    assert x == pytest.approx(45.0, abs=0.01)


def test_a_wide_camera_is_clamped_to_the_eye_ellipse():
    x, y = eye_target(0, 200, 640, 400, hfov_deg=170)  # 85 degrees left: beyond the eyes' 80
    assert (x, y) == pytest.approx((80.0, 0.0))
    x, y = eye_target(0, 0, 640, 400, hfov_deg=170)
    assert inside_ellipse(x, y) and math.hypot(x / 80, y / 120) == pytest.approx(1.0)
    assert x > 0 and y < 0  # the direction is kept


# -- OpenCV is optional -----------------------------------------------------------------------------


def test_without_opencv_the_module_imports_and_the_follower_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "cv2", None)  # `import cv2` now fails
    monkeypatch.delitem(sys.modules, "baxterface_cli.robot.person_finder")
    faces = importlib.import_module("baxterface_cli.robot.person_finder")
    assert faces.eye_target(320, 200, 640, 400) == (0.0, 0.0)
    with pytest.raises(MissingTool) as caught:
        faces.FaceFollower()
    message = str(caught.value)
    assert "\n" not in message and "following a face" in message
    assert "pip install 'baxterface[camera]'" in message


def test_bad_arguments_and_images_are_value_errors():
    streams()
    with pytest.raises(ValueError, match="field of view"):
        FaceFollower(hfov_deg=0)
    with pytest.raises(ValueError, match="frame rate"):
        FaceFollower(rate=0)
    with pytest.raises(ValueError, match="focal length"):
        FaceFollower(focal=-410.0)
    with pytest.raises(ValueError, match="face policy must be nearest, central or longest"):
        FaceFollower(policy="tallest")
    follower = FaceFollower()
    for bad in (
        np.zeros((400, 640, 3), np.float32),
        np.zeros((400, 640, 4), np.uint8),
        np.zeros((400, 640, 2), np.uint8),
        np.zeros((640,), np.uint8),
        np.zeros((0, 0), np.uint8),
        [[0, 0], [0, 0]],
        None,
    ):
        with pytest.raises(ValueError, match="camera image"):
            follower.update(bad)


# -- the goals, scenario by scenario ----------------------------------------------------------------


@pytest.mark.one_python  # whole videos through OpenCV's detector: the same under every Python
@pytest.mark.parametrize("name", WITH_A_FACE + FAR)
def test_a_face_in_view_has_a_target_in_19_frames_out_of_20_after_the_first_second(name):
    fs = streams()
    assert fs.coverage(result(name)) >= 0.95


@pytest.mark.one_python  # whole videos through OpenCV's detector: the same under every Python
@pytest.mark.parametrize("name", WITH_A_FACE + FAR + ["nearer face", "far nearer"])
def test_the_target_is_within_two_eye_pixels_rms_of_the_face(name):
    fs = streams()
    assert fs.rmse(result(name)) <= 2.0


@pytest.mark.parametrize("name", ["leaving", "far leaving"])
def test_a_face_that_leaves_is_let_go_within_a_second(name):
    fs = streams()
    run = result(name)
    after = fs.let_go_after(run)
    assert after is not None and after <= 1.0
    # ... and is held a little first, not dropped at the first frame it is not found.
    assert after >= 0.2


@pytest.mark.one_python  # whole videos through OpenCV's detector: the same under every Python
@pytest.mark.parametrize("name", DISTRACTORS)
def test_a_cat_a_page_of_text_or_a_picture_that_is_not_a_face_is_never_followed(name):
    assert all(target is None for target in result(name).targets)


def test_the_checks_turn_down_what_a_sweep_that_takes_any_window_for_a_face_finds():
    # With a single window enough, the sweep finds the cat's face, the pages' corners and
    # patches of the workshop in image after image; without the checks the eyes would follow them.
    fs = streams()

    class Credulous(Cascades):
        NEIGHBOURS = 0

    class Follower(FaceFollower):
        def __init__(self):
            super().__init__(detector="cascades")
            self.detector = Credulous(self.cv2)

    stream = stream_named("posters 9")
    stream.seconds = 2.0
    follower = Follower()
    seen = []
    run = fs.run(stream, lambda image, t: (follower.update(image, t), seen.append(len(follower.people)))[0])
    assert max(seen) >= 1  # it did find things ...
    assert all(target is None for target in run.targets)  # ... and followed none


@pytest.mark.one_python  # whole videos through OpenCV's detector: the same under every Python
@pytest.mark.parametrize("name", ["two faces", "far two"])
def test_two_faces_of_about_the_same_size_do_not_swap(name):
    fs = streams()
    run = result(name)
    stream = run.stream
    for k, target in enumerate(run.targets):
        if target is None:
            continue
        t = k / stream.fps
        first, second = stream.scene(t)[1]
        to_first = math.dist(target, fs.eye_truth(first.u, first.v))
        to_second = math.dist(target, fs.eye_truth(second.u, second.v))
        assert to_first < 3.0 and to_second > 10.0, f"at {t:.2f} s"


def followed_faces(run, policy_from=0.5):
    """(t, index of the face nearest the target) for each frame with a target after `policy_from` s."""
    fs = streams()
    followed = []
    for k, target in enumerate(run.targets):
        t = k / run.stream.fps
        faces = run.stream.scene(t)[1]
        if target is None or t < policy_from:
            continue
        nearest = min(
            range(len(faces)), key=lambda i: math.dist(target, fs.eye_truth(faces[i].u, faces[i].v))
        )
        assert math.dist(target, fs.eye_truth(faces[nearest].u, faces[nearest].v)) < 3.0
        followed.append((t, nearest))
    return followed


@pytest.mark.one_python  # whole videos through OpenCV's detector: the same under every Python
@pytest.mark.parametrize("name", ["nearer face", "far nearer"])
def test_a_clearly_nearer_face_takes_over_within_half_a_second_once_and_for_good(name):
    run = result(name)
    followed = followed_faces(run)
    switches = [t for (t, a), (_, b) in zip(followed, followed[1:]) if a != b]
    # The stream's switch window: from when the other face is nearer to half a second after.
    start, end = run.stream.switch
    assert len(switches) == 1 and start < switches[0] <= end
    assert followed[-1][1] == 1


@pytest.mark.one_python  # whole videos through OpenCV's detector: the same under every Python
@pytest.mark.parametrize("policy, face", [("nearest", 1), ("central", 2), ("longest", 0)])
def test_the_policy_chooses_among_three_faces(policy, face):
    # The first seen (off the middle, from the start), the nearest and the most central (from 0.6 s;
    # the nearest is followed within half a second, the others when a whole search has found them).
    followed = followed_faces(result("crowd", policy), policy_from=2.0)
    assert len(followed) > 25 and {index for _, index in followed} == {face}


def test_the_focal_length_given_or_told_later_sets_where_the_eyes_look():
    frames = [frame for _, frame in zip(range(12), stream_named("far two").frames())]
    u = frames[-1].centre[0]  # the first face, left of the middle
    wide = FaceFollower(focal=205.0)  # a camera twice as wide as Baxter's
    told = FaceFollower()
    for frame in frames:
        a, b = wide.update(frame.image, frame.t), told.update(frame.image, frame.t)
        if frame is frames[5]:
            told.focal = 205.0  # as the node does when the camera's camera_info comes
    assert a is not None and b is not None
    assert a == pytest.approx(b) and a[0] == pytest.approx(
        math.degrees(math.atan((320 - u) / 205.0)), abs=1.5
    )
    assert a[0] > 1.7 * eye_target(u, 200, 640, 400)[0]  # the same pixel is further round


def test_a_face_at_the_image_centre_is_looked_at_straight_ahead_and_steadily():
    targets = [target for target in result("centred").targets[10:]]
    assert all(target is not None for target in targets)
    xs, ys = np.array(targets).T
    assert np.abs(xs).max() < 1.0 and np.abs(ys).max() < 1.0
    # No trembling: the eyes move well under a screen pixel while the face stands still.
    assert np.ptp(xs) < 0.5 and np.ptp(ys) < 0.5


# -- images, sizes and time -------------------------------------------------------------------------


def first_frames(stream, count):
    return [frame for _, frame in zip(range(count), stream.frames())]


def test_grey_images_and_other_sizes_are_followed_the_same_way():
    cv2 = needs("cv2")
    fs = streams()
    frames = first_frames(fs.centred(), 12)
    colour, grey, small, large = FaceFollower(), FaceFollower(), FaceFollower(), FaceFollower()
    for frame in frames:
        a = colour.update(frame.image)
        b = grey.update(cv2.cvtColor(frame.image, cv2.COLOR_BGR2GRAY))
        c = small.update(cv2.resize(frame.image, (320, 200), interpolation=cv2.INTER_AREA))
        d = large.update(cv2.resize(frame.image, (1280, 800), interpolation=cv2.INTER_LINEAR))
    # A grey image is the same face to the cascades; the networks, which see colour, put it a
    # little differently.
    assert a is not None and b is not None and math.dist(a, b) < 1.0
    for other in (c, d):  # the same field of view at another resolution: the same direction
        assert other is not None and math.dist(a, other) < 1.0


def test_the_hold_is_in_seconds_on_the_callers_clock_or_at_the_given_rate():
    fs = streams()
    frames = first_frames(fs.centred(), 15)
    blank = fs.background("brick")

    def frames_to_let_go(follower, clock):
        k = 0
        for frame in frames:
            follower.update(frame.image, clock(k))
            k += 1
        assert follower.update(frames[-1].image, clock(k)) is not None
        for gone in range(1, 100):
            if follower.update(blank, clock(k + gone)) is None:
                return gone
        raise AssertionError("never let go")

    # Not found for more than `hold` seconds: let go (holds chosen off the frame grid).
    assert frames_to_let_go(FaceFollower(hold=0.45), lambda k: None) == 14  # 30 frames a second
    assert frames_to_let_go(FaceFollower(hold=0.45, rate=10), lambda k: None) == 5
    assert frames_to_let_go(FaceFollower(hold=0.21), lambda k: k / 30) == 7
    assert frames_to_let_go(FaceFollower(hold=0.45), lambda k: 100 + k / 50) == 23  # 50 a second, told


def test_the_same_images_at_the_same_times_give_the_same_targets():
    fs = streams()
    frames = first_frames(fs.tilting(), 40)
    runs = []
    for _ in range(2):
        follower = FaceFollower()
        runs.append([follower.update(frame.image, frame.t) for frame in frames])
    assert runs[0] == runs[1] and sum(target is not None for target in runs[0]) > 30


def test_reset_forgets_the_face():
    fs = streams()
    frames = first_frames(fs.centred(), 10)
    follower = FaceFollower()
    for frame in frames:
        target = follower.update(frame.image, frame.t)
    assert target is not None and follower.face is not None
    follower.reset()
    assert follower.face is None
    assert follower.update(frames[0].image, 0.0) is None  # a new face is confirmed before it is followed


def test_a_clock_set_back_starts_afresh_and_a_bad_time_is_a_value_error():
    fs = streams()
    frames = first_frames(fs.centred(), 12)
    follower = FaceFollower()
    late = [follower.update(frame.image, 100.0 + frame.t) for frame in frames]
    again = [follower.update(frame.image, frame.t) for frame in frames]  # a new run of the caller's clock
    assert late[-1] is not None and again[0] is None and again[-1] is not None
    with pytest.raises(ValueError, match="finite"):
        follower.update(frames[0].image, float("nan"))


def test_images_too_small_for_a_face_are_no_trouble():
    streams()
    follower = FaceFollower()
    for shape in ((1, 1), (2, 3), (30, 30), (45, 50), (1, 1, 3), (39, 41, 3)):
        assert follower.update(np.full(shape, 128, np.uint8)) is None
