"""The screen's page in a real browser: Debian's chromium, headless, in a landscape tablet's window.

One screen and one browser for the module; the last test restarts the screen under the page.
"""

from __future__ import annotations

import io
import signal
from contextlib import ExitStack

import numpy as np
import pytest

from browser import chromium, errors_in_console, wait_for
from conftest import free_port
from studio_server import running_screen

pytestmark = [pytest.mark.xdist_group("screen_browser"), pytest.mark.one_python]
TABLET = (1280, 800)  # a landscape tablet's window: 16:10, where the face is 1024x600 (about 16:9.4)

# The face shown as a number the page can compare: a weighted sum of its pixels.
FACE_PIXELS = """(() => {
  const c = document.getElementById('face');
  if (c.hidden) return null;
  const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  let s = 0; for (let i = 0; i < d.length; i += 4) s += d[i] + 2 * d[i + 1] + 3 * d[i + 2];
  return s;
})()"""


class Bench:
    """The screen (replaceable: it is restarted) and the page that shows it."""

    def __init__(self, folder, port, stack) -> None:
        self.folder, self.port, self.stack = folder, port, stack
        self.screen = self.start()

    def start(self):
        script = str(self.folder / "first.face")
        return self.stack.enter_context(running_screen(self.folder, script, "--no-idle", port=self.port))


@pytest.fixture(scope="module")
def bench(tmp_path_factory):
    folder = tmp_path_factory.mktemp("screen")
    (folder / "first.face").write_text("happy\nlook left in 0.5s\n")
    with ExitStack() as stack:
        made = Bench(folder, free_port(), stack)
        driver = stack.enter_context(chromium(*TABLET))
        width, height = TABLET
        driver.execute_cdp_cmd(
            "Emulation.setDeviceMetricsOverride",
            {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False},
        )
        assert face_state(made.screen)["waiting"]  # the script waits for a page to show it on
        driver.get(made.screen.url)
        wait_for(driver, "window.screenFace && window.screenFace.frames >= 1")
        # The page opened: the script plays, and ends happy and looking left.
        state = "fetch('/api/state').then(r => r.json()).then(s => s.face.emotion + ' ' + s.face.eye_x)"
        assert wait_for(driver, f"{state}.then(f => f === 'happy 65' && f)") == "happy 65"
        made.driver = driver
        yield made
        # The page's only failures are its tries to reconnect while the screen was restarting.
        refused = "/api/live' failed: Error in connection establishment: net::ERR_CONNECTION_REFUSED"
        assert [e for e in errors_in_console(driver) if refused not in e["message"]] == []


def face_state(screen):
    code, state = screen.json("GET", "/api/state")
    assert code == 200
    return state


def test_the_face_fills_a_landscape_tablet_window_with_its_aspect_and_nothing_else(bench):
    from PIL import Image

    driver = bench.driver
    shot = np.asarray(Image.open(io.BytesIO(driver.get_screenshot_as_png())).convert("RGB"), dtype=int)
    assert shot.shape == (800, 1280, 3)
    # 1024x600 scaled to the window's width is 1280x750: black bars of 25 pixels above and below.
    bright = shot.sum(axis=2) > 60
    rows = np.flatnonzero(bright.any(axis=1))
    assert (rows[0], rows[-1]) in {(25, 774), (24, 775), (25, 775), (24, 774)}
    assert bright[30:770, 0].all() and bright[30:770, 1279].all()  # edge to edge across
    assert not bright[:24].any() and not bright[776:].any()
    page = driver.execute_script(
        "const e = document.documentElement;"
        " return [e.scrollWidth, e.scrollHeight, innerWidth, innerHeight,"
        " getComputedStyle(document.body).cursor, getComputedStyle(document.getElementById('face')).cursor];"
    )
    assert page == [1280, 800, 1280, 800, "none", "none"]  # nothing to scroll, no cursor
    # On this machine's own address the browser gives the page its wake lock.
    assert driver.execute_script("return window.screenFace.awake;") == "held"


def test_a_tap_lets_the_sound_in_and_what_the_face_says_is_heard(bench, engine):
    driver, screen = bench.driver, bench.screen
    # Headless chromium, as a tablet's browser, makes no sound before the page is used: it asks.
    assert driver.execute_script("return window.screenFace.sound();") == "suspended"
    tap = driver.find_element("css selector", "#tap")
    assert tap.is_displayed() and tap.text == "Tap for sound"
    tap.click()
    wait_for(driver, "window.screenFace.sound() === 'running' && document.getElementById('tap').hidden")
    # Twenty seconds of it, cut short by the next test's command: the page fetches and decodes the
    # sound while the face says it and skips one it comes to too late, so the sentence outlasts
    # whatever a busy machine keeps the browser waiting (a short one may pass unheard there).
    said = "Hello from the screen, this is a sentence long enough to hear." + " And it goes on." * 16
    assert screen.json("POST", "/api/command", f'say "{said}"')[0] == 200
    started = wait_for(driver, "window.screenFace.started.length && window.screenFace.started[0]")
    wait_for(driver, "window.screenFace.sounds().filter(s => !s.paused && s.t > 0.3).length === 1")
    state = face_state(screen)  # the very utterance the face says, from its start
    assert state["saying"] == said and started["key"] == state["sounds"][0]["key"]
    assert started["at"] == state["sounds"][0]["at"]  # the start of that very sound


def test_a_command_changes_the_face_on_the_page(bench):
    driver, screen = bench.driver, bench.screen
    # The old node's look is instant: one frame, and the face is still again.
    shown = driver.execute_script("return window.screenFace.frames;")
    assert screen.json("POST", "/api/command", "look_-60_0_0")[0] == 200
    wait_for(driver, f"window.screenFace.frames > {shown}")
    before = wait_for(driver, FACE_PIXELS)
    assert screen.json("POST", "/api/command", "look_60_0_0")[0] == 200
    wait_for(driver, f"{FACE_PIXELS} !== {before}")
    assert face_state(screen)["face"]["eye_x"] == 60


def test_the_page_comes_back_by_itself_after_the_screen_restarts(bench):
    driver = bench.driver
    old = bench.screen
    old.process.send_signal(signal.SIGTERM)
    assert old.process.wait(timeout=30) == 128 + signal.SIGTERM
    wait_for(driver, "!window.screenFace.connected")
    wait_for(driver, "!document.getElementById('offline').hidden")  # says so, keeping the last face
    bench.screen = bench.start()  # the same port, a new process
    wait_for(driver, "window.screenFace.connected && window.screenFace.connections === 2")
    wait_for(driver, "document.getElementById('offline').hidden")
    before = wait_for(driver, FACE_PIXELS)
    assert bench.screen.json("POST", "/api/command", "angry")[0] == 200
    wait_for(driver, f"{FACE_PIXELS} !== {before}")
    assert face_state(bench.screen)["screens"] == 1
