"""Where the screen's page puts the face and its 'Tap for sound' prompt, in real chromium windows:
Baxter's own 1024x600, a tablet's 1280x800 and portrait ones, the prompt never over the face's
features, awake or asleep (the Zzz)."""

from __future__ import annotations

import io

import numpy as np
import pytest

from browser import chromium, wait_for
from studio_server import running_screen
from waiting import eventually

pytestmark = [pytest.mark.xdist_group("screen_layout"), pytest.mark.one_python]

BOX = "(el => { const r = el.getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom]; })"


@pytest.fixture(scope="module", params=["happy", "sleep"])
def screen(request, tmp_path_factory):
    folder = tmp_path_factory.mktemp("layout")
    (folder / "first.face").write_text(request.param + "\n")
    with running_screen(folder, str(folder / "first.face"), "--no-idle") as server:
        yield server


def shown(screen, width, height):
    """The page in a window of that size: a screenshot without the prompt, the prompt's box (shown,
    as where the browser asks for a tap first) and the face's."""
    from PIL import Image

    with chromium(width, height) as driver:
        driver.execute_cdp_cmd(
            "Emulation.setDeviceMetricsOverride",
            {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False},
        )
        driver.get(screen.url)
        wait_for(driver, "window.screenFace && window.screenFace.frames >= 1")
        driver.execute_script("document.getElementById('tap').hidden = true")
        # the script played out (asleep: its Zzz shown) and the page holds its last frame
        eventually(lambda: not screen.json("GET", "/api/state")[1]["playing"])
        shots = [driver.get_screenshot_as_png()]
        eventually(lambda: shots.append(driver.get_screenshot_as_png()) or shots[-1] == shots[-2])
        shot = np.asarray(Image.open(io.BytesIO(shots[-1])).convert("RGB"), dtype=int)
        driver.execute_script("document.getElementById('tap').hidden = false")
        tap = driver.execute_script(f"return {BOX}(document.getElementById('tap'))")
        face = driver.execute_script(f"return {BOX}(document.getElementById('face'))")
    return shot, [round(v) for v in tap], face


@pytest.mark.parametrize("width, height", [(1024, 600), (1280, 800)])
def test_a_landscape_window_has_the_prompt_on_plain_skin_in_the_lower_left_corner(screen, width, height):
    shot, (left, top, right, bottom), _ = shown(screen, width, height)
    assert shot.shape == (height, width, 3)
    assert left < 100 and top > height - 100  # the lower left corner, far from the mouth and the Zzz
    under = shot[top:bottom, left:right].reshape(-1, 3)
    # Only skin under it: no outline, eye white, mouth or Zzz (the skin's gradient varies a little).
    assert (under.max(axis=0) - under.min(axis=0)).max() < 40  # one colour, give or take its gradient
    luma = under @ np.array([0.299, 0.587, 0.114])
    assert luma.min() > 120  # a light skin: not an outline, a mouth or the Zzz


@pytest.mark.parametrize("width, height", [(600, 1024), (800, 1280)])
def test_a_portrait_window_letterboxes_the_face_in_its_middle_and_the_prompt_is_above_it(
    screen, width, height
):
    shot, tap, face = shown(screen, width, height)
    # The face keeps its aspect (1024x600) across the whole width, in the middle: black above and below.
    drawn = np.nonzero(shot.sum(axis=(1, 2)) > 0)[0]
    assert abs(len(drawn) - width * 600 / 1024) <= 2
    assert abs(drawn[0] - (height - len(drawn)) / 2) <= 2
    assert face[0] == 0 and face[2] == width
    assert tap[1] > drawn[-1]  # the prompt is on the black bar below the face
