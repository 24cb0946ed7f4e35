"""The run's log under the studio's preview, in a real browser (Debian's chromium, headless): its
events, handlers, states and speech as bars in time, and a click on them puts the preview there."""

from __future__ import annotations

import pytest

from browser import chromium, errors_in_console, wait_for
from studio_server import running_studio

pytestmark = pytest.mark.one_python

SCRIPT = (
    "sad\nstate calm {\n  wait 6s\n  on signal poke {\n    happy\n    wait 1s\n  }\n}\n"
    "on signal hush {\n  look left in 0.5s\n  go calm\n}\nwait 6s\n"
)
BARS = "[...document.querySelectorAll('#lanes .lane[data-lane={}] .bar')].map(b => b.textContent)"


def test_a_click_on_a_handlers_bar_puts_the_preview_at_that_moment(tmp_path):
    (tmp_path / "greeter.face").write_text(SCRIPT)
    with running_studio(tmp_path / "greeter.face", "--no-idle") as studio, chromium() as driver:
        driver.get(studio.url)
        wait_for(driver, "window.studio && window.__frames >= 1 && document.querySelector('#lanes .track')")
        for at, name in ((1.0, "hush"), (3.0, "poke")):  # each fired where the preview is
            assert studio.json("POST", "/api/transport", {"action": "pause"})[0] == 200
            assert studio.json("POST", "/api/transport", {"action": "seek", "t": at})[0] == 200
            status, answer = studio.json("POST", "/api/event", f"signal {name}")
            assert status == 200 and answer["at"] == at, answer
        assert studio.json("POST", "/api/transport", {"action": "pause"})[0] == 200
        assert studio.json("POST", "/api/transport", {"action": "seek", "t": 0})[0] == 200
        handlers = wait_for(driver, BARS.format("handlers") + ".filter(t => t.includes('poke')).length && "
                            + BARS.format("handlers"))  # fmt: skip
        assert handlers == ["line 9 'on signal hush'", "line 4 'on signal poke'"], handlers
        assert wait_for(driver, BARS.format("events")) == ["signal hush", "signal poke"]
        assert wait_for(driver, BARS.format("states")) == ["calm"]
        assert studio.json("GET", "/api/state")[1]["status"]["face"]["emotion"] == "sad"
        poke = driver.find_elements("css selector", "#lanes .lane[data-lane=handlers] .bar")[1]
        poke.click()  # in its middle: the handler's `happy` shows there
        wait_for(driver, "(t => t > 3.0 && t < 4.3)(Number(document.getElementById('scrub').value))")
        status = studio.json("GET", "/api/state")[1]["status"]
        assert 3.0 < status["t"] < 4.3 and status["face"]["emotion"] == "happy", status
        assert errors_in_console(driver) == []
