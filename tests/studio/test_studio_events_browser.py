"""The studio's events bar in a real browser (Debian's chromium, headless): a button for each event
the script listens to, and a field for any event line."""

from __future__ import annotations

import json

import pytest

from browser import chromium, errors_in_console, wait_for
from studio_server import running_studio

pytestmark = pytest.mark.one_python

SCRIPT = "sad\non signal poke {\n  happy\n  wait 1s\n}\nwait 5s\n"


def test_the_events_bar_fires_the_events_the_script_listens_to(tmp_path):
    (tmp_path / "greeter.face").write_text(SCRIPT)
    with running_studio(tmp_path / "greeter.face", "--no-idle") as studio, chromium() as driver:
        driver.get(studio.url)
        wait_for(driver, "window.studio && document.querySelector('.cm-editor') && window.__frames >= 1")
        buttons = wait_for(
            driver, "[...document.querySelectorAll('#event-buttons button')].map(b => b.textContent)"
        )
        assert buttons == ["signal poke"]
        driver.find_element("css selector", "#event-buttons button").click()
        said = wait_for(driver, "document.getElementById('event-result').textContent || null")
        assert said.startswith("signal poke at ") and "ran 1" in said
        assert studio.json("GET", "/api/state")[1]["status"]["face"]["emotion"] == "happy"
        assert errors_in_console(driver) == []
        field = driver.find_element("css selector", "#event-line")
        field.send_keys("signal")
        driver.find_element("css selector", "#events-bar button[type=submit]").click()
        error = wait_for(driver, "document.getElementById('event-result').textContent.includes('1:') || null")
        assert error and driver.find_element("css selector", "#event-line").get_attribute("value") == "signal"
        assert studio.json("GET", "/api/state")[1]["timeline"]["fired"] == 1
        # the one error the console has is the bad line's answer, shown in the bar
        logged = [e["message"].split(" - ")[0] for e in errors_in_console(driver)]
        assert [where.rsplit("/", 1)[-1] for where in logged] == ["event"]


def test_a_click_on_the_preview_raises_touch_where_it_lands(tmp_path):
    (tmp_path / "eyes.face").write_text("on touch left eye {\n  wink left\n}\n")
    with running_studio(tmp_path / "eyes.face", "--no-idle") as studio, chromium() as driver:
        from selenium.webdriver.common.action_chains import ActionChains

        driver.get(studio.url)
        wait_for(
            driver, "window.studio && window.__frames >= 1 && document.getElementById('preview').naturalWidth"
        )
        preview = driver.find_element("css selector", "#preview")
        size = preview.size
        # The robot's left eye is on the screen's right: at 0.7 across, 0.4 down (from the middle).
        across, down = round((0.7 - 0.5) * size["width"]), round((0.4 - 0.5) * size["height"])
        ActionChains(driver).move_to_element_with_offset(preview, across, down).click().perform()
        said = wait_for(driver, "document.getElementById('event-result').textContent || null")
        assert said.startswith("touch left eye at ") and "ran 1" in said, said
        assert studio.json("GET", "/api/state")[1]["timeline"]["fired"] == 1
        size = preview.size  # as laid out now: the answer shown above may have moved it
        ActionChains(driver).move_to_element_with_offset(
            preview, 0, round(0.45 * size["height"])
        ).click().perform()
        again = wait_for(
            driver,
            f"(t => t !== {json.dumps(said)} && t)(document.getElementById('event-result').textContent)",
        )
        assert again.startswith("touch at "), again  # below the mouth: anywhere
        assert errors_in_console(driver) == []
