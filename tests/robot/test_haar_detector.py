"""The whole-image search cut into jobs, and what the sweep, near and check searches find."""

from __future__ import annotations

import math
import os
import shutil

import numpy as np
import pytest

from baxterface_cli.robot import haar_detector as fc
from conftest import needs


@pytest.mark.parametrize("width, height", [(640, 400), (1280, 800), (320, 240)])
def test_a_plan_covers_every_row_and_every_size_from_the_smallest_in_jobs_of_about_one_cost(width, height):
    large, passes = fc.plan(width, height)
    scale = width / 640
    for turn, jobs in zip((0.0, *fc.TURNS), passes):
        assert all(job.turn == turn for job in jobs)
        sizes = fc.sizes_of(jobs + (large if turn == 0.0 else []))
        smallest = fc.SMALLEST if turn == 0.0 else fc.SMALLEST_TURNED
        assert max(smallest * scale, fc.WINDOW) <= sizes[0] < max(smallest * scale, fc.WINDOW) * 1.2
        assert sizes[-1] > 0.75 * min(width, height)  # up to a face filling the image
        steps = [b / a for a, b in zip(sizes, sizes[1:])]
        assert max(steps) <= max(fc.FINE_STEP, fc.TURNED_STEP, fc.COARSE_STEP) + 1e-9
        for size in sizes:  # every row of the image, for every size, in some job
            rows = sorted(job.rows for job in jobs + large if size in job.sizes and job.turn == turn)
            assert rows[0][0] == 0.0 and rows[-1][1] == 1.0
            assert all(a[1] == b[0] for a, b in zip(rows, rows[1:]))
    for job in large + [job for jobs in passes for job in jobs]:
        windows = sum(fc._windows(width, height, s, job.turn) for s in job.sizes) * (
            job.rows[1] - job.rows[0]
        )
        assert windows <= 2 * fc.JOB_WINDOWS


def test_an_image_too_small_for_the_window_has_no_jobs():
    large, passes = fc.plan(15, 15)
    assert large == [] and passes == [[], [], []]


def picture(width, angle, where=(300.0, 180.0)):
    """The astronaut's face `width` px wide, tilted `angle`, over the workshop photo; grey."""
    cv2 = needs("cv2")
    needs("skimage")
    import face_streams as fs

    frame = fs.background("motorcycle").astype(np.float32)
    fs.paste(frame, fs.sprites()["astronaut"], *where, width, angle)
    return cv2.cvtColor(np.clip(frame, 0, 255).astype(np.uint8), cv2.COLOR_BGR2GRAY)


def found(cascades, grey, jobs, width, where=(300.0, 180.0)):
    return [
        box
        for job in jobs
        for box in cascades.sweep(grey, job)
        if math.hypot(box.x - where[0], box.y - where[1]) < 0.3 * width and 0.7 < box.size / width < 1.4
    ]


def test_the_upright_pass_finds_a_face_24_pixels_wide_and_the_turned_one_a_face_tilted_20_degrees():
    cv2 = needs("cv2")
    cascades = fc.Cascades(cv2)
    _, (upright, left, right) = fc.plan(640, 400)
    assert found(cascades, picture(24, 0), upright, 24)
    tilted = picture(28, -20)  # clockwise in the image
    assert not found(cascades, tilted, upright, 28)  # an upright cascade misses it ...
    assert not found(cascades, tilted, right, 28)
    boxes = found(cascades, tilted, left, 28)  # ... the image turned back 20 degrees shows it
    assert boxes and all(box.turn == 20.0 for box in boxes)
    assert cascades.verdict(tilted, boxes[0]) == fc.SURE


def test_near_finds_the_tracked_face_turned_and_the_check_turns_down_the_background():
    cv2 = needs("cv2")
    cascades = fc.Cascades(cv2)
    grey = picture(30, -15)
    assert cascades.near(grey, 305, 176, 32, 0.0) is None  # upright, the tilted face is not found ...
    box = cascades.near(grey, 305, 176, 32, 20.0)  # ... turned back, it is
    assert box is not None and math.hypot(box.x - 300, box.y - 180) < 4 and 24 < box.size < 38
    assert cascades.verdict(grey, box, strict=False) == fc.FOUND
    assert cascades.near(grey, 500, 300, 30, 0.0) is None  # nothing there
    assert cascades.verdict(grey, fc.Box(500, 300, 30)) == fc.NOT_A_FACE


# -- where the cascades come from: absolute paths only, never the working directory ---------------


class DebianCv2:
    """OpenCV as Debian's python3-opencv is: no `cv2.data`; records every cascade it is asked to open."""

    __file__ = "/usr/lib/python3/dist-packages/cv2.cpython-311-x86_64-linux-gnu.so"

    def __init__(self, cv2):
        self.real, self.opened = cv2, []

    def CascadeClassifier(self, path):  # noqa: N802 (OpenCV's name)
        self.opened.append(path)
        return self.real.CascadeClassifier(path)

    def __getattr__(self, name):  # the rest is the real OpenCV's
        if name == "data":
            raise AttributeError(name)
        return getattr(self.real, name)


@pytest.fixture
def planted(tmp_path, monkeypatch):
    """A working directory holding a real cascade under each name the follower loads: a planted
    file that works would be the worst case, for nothing would show it was used."""
    cv2 = needs("cv2")
    here = tmp_path / "here"
    here.mkdir()
    for name in (fc.Cascades.FIND, fc.Cascades.CHECK, fc.Cascades.AGREE):
        shutil.copy(cv2.data.haarcascades + fc.Cascades.CHECK, str(here / name))
    monkeypatch.chdir(here)
    return cv2


def test_without_cv2_data_or_debians_cascades_a_planted_cascade_is_not_used_and_apt_is_named(
    planted, tmp_path, monkeypatch
):
    monkeypatch.setattr(fc, "SYSTEM_CASCADES", (str(tmp_path / "no-opencv-data"),))
    debian = DebianCv2(planted)
    with pytest.raises(fc.MissingTool) as refused:
        fc.Cascades(debian)
    assert debian.opened == []  # nothing was opened, least of all ./haarcascade_*.xml
    message = str(refused.value)
    assert "apt install opencv-data" in message and "pip install" not in message
    assert fc.Cascades.FIND in message and str(tmp_path / "no-opencv-data") in message


def test_with_debians_opencv_data_the_cascades_are_read_from_it_by_absolute_path(
    planted, tmp_path, monkeypatch
):
    system = tmp_path / "usr-share-opencv4-haarcascades"
    system.mkdir()
    for name in (fc.Cascades.FIND, fc.Cascades.CHECK, fc.Cascades.AGREE):
        shutil.copy(planted.data.haarcascades + name, str(system / name))
    monkeypatch.setattr(fc, "SYSTEM_CASCADES", ("/nonexistent/opencv4", str(system)))
    debian = DebianCv2(planted)
    cascades = fc.Cascades(debian)
    assert debian.opened == [
        str(system / n) for n in (fc.Cascades.FIND, fc.Cascades.CHECK, fc.Cascades.AGREE)
    ]
    assert found(cascades, picture(24, 0), fc.plan(640, 400)[1][0], 24)  # the real find cascade


def test_the_wheels_cascades_are_read_by_absolute_path_from_any_working_directory(planted):
    class Wheel(DebianCv2):
        __file__ = planted.__file__
        data = planted.data

    wheel = Wheel(planted)
    cascades = fc.Cascades(wheel)
    assert os.path.isabs(planted.data.haarcascades)
    assert wheel.opened == [
        planted.data.haarcascades + n for n in (fc.Cascades.FIND, fc.Cascades.CHECK, fc.Cascades.AGREE)
    ]
    assert found(cascades, picture(24, 0), fc.plan(640, 400)[1][0], 24)


def test_a_pip_opencv_without_its_cascades_names_the_camera_extra(tmp_path, monkeypatch):
    monkeypatch.setattr(fc, "SYSTEM_CASCADES", ())
    monkeypatch.chdir(tmp_path)
    wheel = type("Cv2", (), {"__file__": str(tmp_path / "site-packages/cv2/__init__.py")})()
    with pytest.raises(fc.MissingTool, match=r"pip install 'baxterface\[camera\]'"):
        fc.Cascades(wheel)
