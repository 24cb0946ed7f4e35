"""A tap on the screen's page, in a real browser, raises `touch` with where on the face it landed."""

from __future__ import annotations

import pytest

from browser import chromium, errors_in_console, wait_for
from studio_server import running_screen
from waiting import eventually

pytestmark = [pytest.mark.xdist_group("screen_touch_browser"), pytest.mark.one_python]
TABLET = (1280, 800)  # the 1024x600 face drawn 1280x750, with 25-pixel bars above and below


def tap(driver, x: int, y: int) -> None:
    for kind in ("mousePressed", "mouseReleased"):
        driver.execute_cdp_cmd(
            "Input.dispatchMouseEvent", {"type": kind, "x": x, "y": y, "button": "left", "clickCount": 1}
        )


def test_a_tap_on_the_face_raises_touch_where_it_landed(tmp_path):
    (tmp_path / "greeter.face").write_text("on touch left eye { wink left }\non touch { happy }\n")
    with running_screen(tmp_path, str(tmp_path / "greeter.face"), "--no-idle") as screen, chromium(
        *TABLET
    ) as driver:
        width, height = TABLET
        driver.execute_cdp_cmd(
            "Emulation.setDeviceMetricsOverride",
            {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False},
        )
        driver.get(screen.url)
        wait_for(driver, "window.screenFace && window.screenFace.frames >= 1")
        # The robot's left eye is on the screen's right: 0.7 of the frame across, 0.4 down, below the bar.
        tap(driver, round(0.7 * width), 25 + round(0.4 * 750))
        wait_for(driver, "window.screenFace.touches.length >= 1")
        tap(driver, round(0.1 * width), 10)  # on the black bar above the face: a touch, nowhere on it
        wait_for(driver, "window.screenFace.touches.length >= 2")
        assert driver.execute_script("return window.screenFace.touches") == ["touch left eye", "touch"]

        def runs():
            handlers = screen.json("GET", "/api/state")[1]["handlers"]
            return {h["on"]: h["runs"] + h["dropped"] for h in handlers}

        # Both handlers took their taps (the second may have come while the first still ran: dropped).
        eventually(lambda: runs() == {"touch left eye": 1, "touch": 2})
        assert errors_in_console(driver) == []
