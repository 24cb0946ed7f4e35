"""The studio's page in a real browser: Debian's chromium, headless."""

from __future__ import annotations

import re
import subprocess

import pytest

from browser import chromium, errors_in_console, wait_for
from studio_server import baxterface, running_studio
from waiting import eventually

# The page's own scripts, in a browser: the same whichever Python serves them (the servers are tested
# under every Python by tests/studio/test_studio.py).
pytestmark = pytest.mark.one_python

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
        # Read with the clock's text past 1 s too: the text is rounded (1.03 s reads '1.0'), so a
        # slider just past 1 s, read on a loaded machine, showed '1.0'.
        "(() => { const s = document.getElementById('scrub');"
        " const text = document.getElementById('time').textContent;"
        " return s.disabled && Number(s.value) > 1 && Number(s.value) <= Number(s.max)"
        " && parseFloat(text) > 1 && text; })()",
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
        "(document.getElementById('export-result').textContent.match(/session-[\\w-]+\\.jsonl/) || [])[0]",
    )
    exported = folder / name
    assert exported.exists()
    done = subprocess.run([baxterface(), "explain", str(exported)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    said = [m.group(1) for m in re.finditer(r" line \d+ +(.*)", done.stdout)]
    # Each press took over from the face as it was, as on the robot: one after another.
    pressed = [text.replace(" (stopped)", "") for text in said if not text.startswith("wait")]
    assert pressed[-3:] == ["happy", "look 0 -97.5 in 0.4s", "blink"]


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


# Every request the page sends to /api/command, with the page's clock: the moving controls' pace.
RECORD_COMMANDS = """
window.__commands = [];
const original = window.fetch;
window.fetch = (url, init) => {
  if (String(url).endsWith('/api/command')) window.__commands.push([performance.now(), init.body]);
  return original(url, init);
};
"""
MOOD_LINE = re.compile(r"mood (-?\d+(?:\.\d{1,2})?) (-?\d+(?:\.\d{1,2})?) in 0\.2s")


def face_now(studio):
    """The preview's face as the state JSON gives it: its expression and mood among the rest."""
    code, state = studio.json("GET", "/api/state")
    assert code == 200
    return state["status"]["face"]


def session_commands(studio):
    return [p["command"] for p in studio.json("GET", "/api/state")[1]["session"]["presses"]]


def test_dragging_the_mood_pad_performs_mood_lines_that_the_session_logs(page, folder):
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.keys import Keys

    studio, driver = page
    before = face_now(studio)
    assert before["expression"] is not None
    pad = driver.find_element("css selector", "#mood-pad")
    driver.execute_script("arguments[0].scrollIntoView({block: 'center'});", pad)
    driver.execute_script(RECORD_COMMANDS)
    w, h = pad.size["width"], pad.size["height"]
    drag = ActionChains(driver, duration=10).move_to_element(pad).click_and_hold()
    for _ in range(8):  # toward the top right, a move every 30 ms: faster than the pad sends
        drag.move_by_offset(round(w * 0.05), -round(h * 0.05)).pause(0.03)
    drag.move_by_offset(0, -h)  # far past the top edge: the arousal stays at 1
    drag.release().perform()
    # The last line sent is where the dot was let go, and the log shows it as a press does.
    shown = wait_for(driver, "document.getElementById('mood-value').textContent")
    valence, arousal = shown.split()
    assert arousal == "1" and 0.5 < float(valence) < 1
    last = f"mood {valence} {arousal} in 0.2s"
    wait_for(driver, f"document.getElementById('session').textContent.trim().endsWith({last!r})")
    commands = session_commands(studio)
    assert commands[-1] == last and len(commands) >= 2
    for command in commands:  # every one a mood line, in range, to 2 decimals
        v, a = map(float, MOOD_LINE.fullmatch(command).groups())
        assert -1 <= v <= 1 and -1 <= a <= 1
    sent = driver.execute_script("return window.__commands;")
    assert [body for _, body in sent] == commands
    gaps = [b[0] - a[0] for a, b in zip(sent, sent[1:])]
    assert min(gaps) > 95, gaps  # at most one every ~100 ms
    # The face took the mood: its state says so, and its expression moved.
    face = eventually(lambda: (lambda f: f["mood"] == [float(valence), 1.0] and f)(face_now(studio)))
    assert face["expression"] != before["expression"]
    # The arrow keys move the focused pad, not the eyes (ArrowDown is Look down's shortcut).
    pad.send_keys(Keys.ARROW_DOWN)
    down = f"mood {valence} 0.9 in 0.2s"
    wait_for(driver, f"document.getElementById('session').textContent.trim().endsWith({down!r})")
    assert not any(c.startswith("look") for c in session_commands(studio))
    # Exported, the drag is a session that `explain` replays: the same moods, each taking over.
    code, exported = studio.json("POST", "/api/session/export")
    assert code == 200
    done = subprocess.run(
        [baxterface(), "explain", str(folder / exported["path"])], capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr
    moods = [m.replace(" (stopped)", "") for m in re.findall(r" line \d+ +(mood .*)", done.stdout)]
    assert moods == [*commands, down]


def test_the_intensity_slider_performs_an_emotion_at_its_intensity(page):
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.keys import Keys
    from selenium.webdriver.support.ui import Select

    studio, driver = page
    before = face_now(studio)
    Select(driver.find_element("css selector", "#intensity-emotion")).select_by_value("sad")
    wait_for(driver, "document.getElementById('session').textContent.includes('sad 0.5 in 0.2s')")
    slider = driver.find_element("css selector", "#intensity")
    driver.execute_script("arguments[0].scrollIntoView({block: 'center'});", slider)
    width = slider.size["width"]
    # From the middle to the right end, past where the thumb stops: 1, no further.
    drag = ActionChains(driver).click_and_hold(slider).move_by_offset(width // 4, 0).pause(0.05)
    drag.move_by_offset(width // 2 - width // 4 - 2, 0).release().perform()
    wait_for(driver, "document.getElementById('session').textContent.trim().endsWith('sad 1 in 0.2s')")
    face = eventually(lambda: (lambda f: f["expression"]["mouth_curve"] < -0.9 and f)(face_now(studio)))
    assert face["expression"] != before["expression"] and face["emotion"] == "sad"
    # From the keyboard: the arrows move the slider, not the eyes.
    slider.send_keys(Keys.HOME)
    wait_for(driver, "document.getElementById('session').textContent.trim().endsWith('sad 0 in 0.2s')")
    slider.send_keys(Keys.ARROW_RIGHT)
    wait_for(driver, "document.getElementById('session').textContent.trim().endsWith('sad 0.01 in 0.2s')")
    assert driver.find_element("css selector", "#intensity-value").text == "0.01"
    commands = session_commands(studio)
    assert all(re.fullmatch(r"sad (0|1|0\.\d{1,2}) in 0\.2s", c) for c in commands), commands


def test_out_of_range_moods_and_intensities_are_refused_with_diagnostics(page):
    studio, driver = page
    code, answer = studio.json("POST", "/api/command", "mood 1.5 0 in 0.2s")
    assert code == 400
    assert answer["diagnostics"][0]["message"] == "valence must be from -1 to 1, not 1.5"
    code, answer = studio.json("POST", "/api/command", "happy 1.2 in 0.2s")
    assert code == 400
    assert answer["diagnostics"][0]["message"] == "an intensity must be from 0 to 1, not 1.2"
    assert session_commands(studio) == []
    # The lines the controls make stay in range whatever they are given.
    lines = driver.execute_script(
        "const s = window.studio;"
        " return [s.moodLine(1.7, -3), s.moodLine(-0.004, 0.996), s.moodLine(NaN, 0.5),"
        " s.intensityLine('happy', 1.2), s.intensityLine('wake_up', -0.1), s.intensityLine('sad', 0.333)];"
    )
    assert lines == [
        "mood 1 -1 in 0.2s",
        "mood 0 1 in 0.2s",
        "mood 0 0.5 in 0.2s",
        "happy 1 in 0.2s",
        "wake_up 0 in 0.2s",
        "sad 0.33 in 0.2s",
    ]
    options = driver.execute_script(
        "return [...document.querySelectorAll('#intensity-emotion option')].map(o => o.value);"
    )
    assert options[0] == "happy" and "wake_up" in options and "default" not in options
    for line in lines:
        assert studio.json("POST", "/api/command", line)[0] == 200
