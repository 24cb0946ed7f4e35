"""The studio's page in a real browser: Debian's chromium, headless."""

from __future__ import annotations

import re
import subprocess

import pytest

from browser import chromium, errors_in_console, wait_for
from studio_server import baxterface, running_studio

# The preview as a number the page can compare: the sum of a few rows of its pixels.
PREVIEW_PIXELS = """
const img = document.getElementById('preview');
if (!img.complete || !img.naturalWidth) return null;
const c = document.createElement('canvas');
c.width = img.naturalWidth; c.height = img.naturalHeight;
const g = c.getContext('2d'); g.drawImage(img, 0, 0);
const d = g.getImageData(0, 0, c.width, c.height).data;
let s = 0; for (let i = 0; i < d.length; i += 4) s += d[i] + 2 * d[i + 1] + 3 * d[i + 2];
return s;
"""


@pytest.fixture()
def folder(tmp_path):
    (tmp_path / "show.face").write_text("happy\nlook left in 1s\nwait 1s\n")
    return tmp_path


@pytest.fixture()
def page(folder):
    with running_studio(folder / "show.face", "--no-idle") as studio, chromium() as driver:
        driver.get(studio.url)
        wait_for(driver, "window.studio && document.querySelector('.cm-editor') && window.__frames >= 1")
        yield studio, driver
        assert errors_in_console(driver) == []


def test_a_typo_is_underlined_with_checks_message(page):
    studio, driver = page
    assert (
        driver.execute_script("return window.studio.editor.getText();") == "happy\nlook left in 1s\nwait 1s\n"
    )
    content = driver.find_element("css selector", ".cm-content")
    content.click()
    driver.execute_script(
        "const v = window.studio.editor.view; v.dispatch({selection: {anchor: v.state.doc.length}});"
    )
    content.send_keys("mouth smil")
    wait_for(driver, "document.querySelector('.cm-lintRange-error')")
    messages = wait_for(
        driver, "[...document.querySelectorAll('.diagnostic')].map(e => e.textContent).join('\\n') || null"
    )
    assert "4:7: error: unknown mouth 'smil'; did you mean 'smile'?" in messages
    underlined = driver.find_element("css selector", ".cm-lintRange-error").text
    assert underlined == "smil"
    content.send_keys("e")  # fixed: the underline and the message go
    wait_for(
        driver, "!document.querySelector('.cm-lintRange-error') && !document.querySelector('.diagnostic')"
    )


def test_a_button_and_a_shortcut_change_the_preview_and_are_logged(page):
    studio, driver = page
    before = wait_for(driver, f"(() => {{ {PREVIEW_PIXELS} }})()")
    button = next(b for b in driver.find_elements("css selector", "button.press") if "Look left" in b.text)
    button.click()
    wait_for(driver, f"(() => {{ {PREVIEW_PIXELS} }})() !== {before}")
    driver.find_element("css selector", "body").click()
    driver.find_element("css selector", "body").send_keys("s")  # Sad's shortcut in the default panel
    log = wait_for(
        driver,
        "document.getElementById('session').textContent.includes('sad') && "
        "document.getElementById('session').textContent",
    )
    assert log.index("look left in 0.4s") < log.index("sad")
    # The clock and the slider follow the live session: its time never passes its length.
    clock = wait_for(
        driver,
        "(() => { const s = document.getElementById('scrub');"
        " return s.disabled && Number(s.value) > 1 && Number(s.value) <= Number(s.max)"
        " && document.getElementById('time').textContent; })()",
    )
    shown, length = map(float, re.fullmatch(r"([\d.]+) / ([\d.]+) s", clock).groups())
    assert 1 < shown <= length
    _, session = studio.json("GET", "/api/state")
    assert [p["command"] for p in session["session"]["presses"]] == ["look left in 0.4s", "sad"]


def test_the_exported_log_replays_the_session(page, folder):
    studio, driver = page
    for command in ("happy", "look up in 0.4s", "blink"):
        driver.execute_script("return window.studio.press(arguments[0]);", command)
        wait_for(driver, f"document.getElementById('session').textContent.includes({command!r})")
    driver.find_element("css selector", "#export").click()
    name = wait_for(
        driver,
        "(document.getElementById('export-result').textContent.match(/session-[\\w-]+\\.face/) || [])[0]",
    )
    exported = folder / name
    assert exported.exists()
    done = subprocess.run([baxterface(), "explain", str(exported)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    said = [m.group(1) for m in re.finditer(r" line \d+ +(.*)", done.stdout)]
    assert [text for text in said if not text.startswith("wait")] == [
        "happy",
        "look 0 -97.5 in 0.4s",
        "blink",
    ]


def test_a_change_on_disk_reaches_the_editor_and_the_preview(page, folder):
    studio, driver = page
    (folder / "show.face").write_text("sad\nwait 3s\n")
    wait_for(driver, "window.studio.editor.getText() === 'sad\\nwait 3s\\n'")
    _, state = studio.json("GET", "/api/state")
    assert [s["text"] for s in state["timeline"]["spans"]] == ["sad", "wait 3s"]


def test_what_the_face_says_is_heard_and_the_switch_silences_it(page, engine):
    studio, driver = page
    button = next(b for b in driver.find_elements("css selector", "button.press") if "Say again?" in b.text)
    button.click()  # a click: the page may make sound from now on
    started = wait_for(driver, "window.__sounds.length && window.__sounds[0]")
    sounding = wait_for(driver, "window.studio.sounds().filter(s => !s.paused && s.t > 0.3).length")
    assert sounding == 1  # the sound goes on in the browser
    code, wav = studio.request("GET", f"/api/sound/{started['key']}.wav")
    assert code == 200 and len(wav) > 2 * engine.say("Sorry, could you say that again?").sample_rate
    driver.find_element("css selector", "#sound").click()  # off: silence at once
    assert driver.execute_script("return window.studio.sounds().length;") == 0
    driver.execute_script("return window.studio.press('say \"Thank you!\"');")
    wait_for(driver, "document.getElementById('session').textContent.includes('Thank you')")
    driver.execute_script("return new Promise(r => setTimeout(r, 500));")
    assert driver.execute_script("return window.__sounds.length;") == 1


def test_the_script_is_heard_from_where_it_is_played_and_pausing_stops_it(page, folder, engine):
    studio, driver = page
    said = "One, two, three, four, five, six, seven, eight, nine, ten."
    (folder / "show.face").write_text(f'say "{said}"\n')
    wait_for(driver, f"window.studio.editor.getText().includes({said!r})")
    driver.find_element("css selector", "body").click()
    driver.execute_script("return window.studio.api('POST', '/api/transport', {action: 'seek', t: 1.5});")
    driver.find_element("css selector", "#play").click()
    started = wait_for(driver, "window.__sounds.length && window.__sounds[0]")
    assert started["at"] == 0 and started["offset"] >= 1.5  # from the middle, where the preview is
    wait_for(driver, "window.studio.sounds().length === 1")
    driver.find_element("css selector", "#play").click()  # pause
    wait_for(driver, "window.studio.sounds().length === 0")


def test_ctrl_s_asks_before_it_overwrites_a_change_made_on_disk(folder):
    from selenium.webdriver.common.keys import Keys
    from selenium.webdriver.support import expected_conditions
    from selenium.webdriver.support.ui import WebDriverWait

    script = folder / "show.face"
    with running_studio(script, "--no-idle") as studio, chromium() as driver:
        driver.get(studio.url)
        wait_for(driver, "window.studio && document.querySelector('.cm-editor')")
        content = driver.find_element("css selector", ".cm-content")
        content.click()
        driver.execute_script(
            "const v = window.studio.editor.view; v.dispatch({selection: {anchor: v.state.doc.length}});"
        )
        content.send_keys("blink")
        wait_for(driver, "document.getElementById('saved').textContent === 'unsaved'")
        script.write_text("sad\nwait 3s\n")  # someone else's change, while the editor has its own
        wait_for(driver, "document.getElementById('notice').textContent.includes('changed on disk')")

        def ctrl_s():
            content.send_keys(Keys.CONTROL, "s")
            return WebDriverWait(driver, 10).until(expected_conditions.alert_is_present())

        asked = ctrl_s()
        assert "changed on disk" in asked.text
        asked.dismiss()
        wait_for(driver, "document.getElementById('notice').textContent.startsWith('not saved')")
        assert script.read_text() == "sad\nwait 3s\n"  # kept
        ctrl_s().accept()
        wait_for(driver, "document.getElementById('saved').textContent === 'saved'")
        assert script.read_text() == "happy\nlook left in 1s\nwait 1s\nblink"
        # The page's one failed request is the refused save, answered 409 as meant.
        assert all("409" in e["message"] for e in errors_in_console(driver))
