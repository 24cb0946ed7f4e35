"""The screen reacts: a real `baxterface screen` runs a script's handlers, raised by `POST /api/event`
and by taps (`POST /api/touch`), and says their counts in `/api/state`."""

from __future__ import annotations

import json

import pytest
from test_web import decoded, pages

from studio_server import running_screen
from waiting import eventually

pytestmark = pytest.mark.xdist_group("screen_events")

GREETER = """\
on signal poke { happy }
on touch left eye { wink left }
on touch mouth { sad }
on signal hold { look left in 0.3s; wait 60s }
on signal stop interrupt { look 0 0 in 0.2s }
"""


@pytest.fixture(scope="module")
def screen(tmp_path_factory):
    folder = tmp_path_factory.mktemp("screen_events")
    (folder / "greeter.face").write_text(GREETER)
    with running_screen(folder, str(folder / "greeter.face"), "--no-idle") as server:
        server.before = server.json("GET", "/api/state")[1]
        yield server


def state(screen):
    return screen.json("GET", "/api/state")[1]


def runs(screen, on):
    (handler,) = [h for h in state(screen)["handlers"] if h["on"] == on]
    return handler


def test_a_script_that_reacts_waits_for_the_first_page_then_its_handlers_are_listed(screen):
    assert screen.before["waiting"] and screen.before["handlers"] == []
    with pages(screen) as (page,):
        page.until(lambda m: isinstance(m, bytes))
        now = state(screen)
    assert not now["waiting"]
    assert [(h["on"], h["line"], h["policy"]) for h in now["handlers"]] == [
        ("signal poke", 1, "drop"),
        ("touch left eye", 2, "drop"),
        ("touch mouth", 3, "drop"),
        ("signal hold", 4, "drop"),
        ("signal stop", 5, "interrupt"),
    ]


def test_an_event_runs_its_handler_and_a_page_gets_the_changed_frame(screen):
    with pages(screen) as (page,):
        page.until(lambda m: isinstance(m, bytes))
        before = decoded(page.frames[-1])
        status, answer = screen.json("POST", "/api/event", "signal poke")
        assert status == 200 and answer["event"] == "signal poke" and answer["runs"] == 1
        page.until(lambda m: isinstance(m, bytes) and abs(decoded(m) - before).mean() > 1.0)
    eventually(lambda: state(screen)["face"]["emotion"] == "happy")
    assert runs(screen, "signal poke")["runs"] == 1 and state(screen)["events"] >= 1


def test_an_event_nobody_listens_to_is_taken_and_changes_nothing(screen):
    status, answer = screen.json("POST", "/api/event", "button ok")
    assert status == 200 and answer == {"event": "button ok", "runs": 0, "dropped": 0, "queued": 0}


def test_a_bad_event_gets_a_400_positioned_and_logged(screen):
    asked = [
        ("sigal poke", 1, 1, "unknown event 'sigal'; did you mean 'signal'?"),
        ("touch left eye\nsignal poke", 2, 1, "one event at a time"),
        ("button okk", 1, 8, "unknown button 'okk'"),
        ("every 5s", 1, 1, "'every' is the script's own clock"),
        ("", 1, 1, "no event"),
    ]
    for text, line, column, message in asked:
        status, answer = screen.json("POST", "/api/event", text)
        (first, *_) = answer["diagnostics"]
        assert status == 400 and (first["line"], first["column"]) == (line, column), text
        assert first["message"].startswith(message), first
    assert any("POST /api/event: 400 1:8: unknown button 'okk'" in line for line in screen.log())


def test_a_tap_raises_touch_where_the_face_is_drawn(screen):
    with pages(screen) as (page,):  # the script starts with the first page (when run alone too)
        page.until(lambda m: isinstance(m, bytes))
    # The robot's left eye is on the screen's right; the mouth below the middle.
    status, answer = screen.json("POST", "/api/touch", {"x": 0.7, "y": 0.4})
    assert status == 200 and answer["event"] == "touch left eye" and answer["runs"] == 1
    eventually(lambda: runs(screen, "touch left eye")["runs"] == 1)
    assert screen.json("POST", "/api/touch", {"x": 0.3, "y": 0.4})[1]["event"] == "touch right eye"
    assert screen.json("POST", "/api/touch", {"x": 0.02, "y": 0.97})[1]["event"] == "touch"
    eventually(lambda: screen.json("POST", "/api/touch", {"x": 0.5, "y": 0.8})[1]["runs"] == 1)
    eventually(lambda: state(screen)["face"]["emotion"] == "sad")
    status, answer = screen.json("POST", "/api/touch", {"x": "left"})
    assert status == 400 and "x and y" in answer["error"]
    # Off the frame, however far, is on no place of the face; an integer of hundreds of digits is
    # refused for its length (both were a 500).
    assert screen.json("POST", "/api/touch", {"x": 1e308, "y": 0.5})[1]["event"] == "touch"
    status, answer = screen.json("POST", "/api/touch", {"x": 10**400, "y": 0.5})
    assert (
        status == 400
        and answer["error"] == "the body has a number of 401 digits; a number here has at most 100"
    )


def test_a_handler_sent_as_a_command_installs_itself(screen):
    status, answer = screen.json("POST", "/api/command", "on signal wave { happy }")
    assert status == 200 and answer["installed"] == ["signal wave"]
    assert "signal wave" in [h["on"] for h in state(screen)["handlers"]]
    eventually(lambda: screen.json("POST", "/api/event", "signal wave")[1]["runs"] == 1)
    eventually(lambda: state(screen)["face"]["emotion"] == "happy")
    status, answer = screen.json("POST", "/api/command", "on signal wave { sad }")  # sent twice: replaced
    assert status == 200 and [h["on"] for h in state(screen)["handlers"]].count("signal wave") == 1


def test_while_a_handler_runs_the_same_event_is_dropped_and_counted_and_interrupt_cuts_in(screen):
    eventually(lambda: state(screen)["running"] is None)  # what the tests before began has ended
    assert screen.json("POST", "/api/event", "signal hold")[1]["runs"] == 1
    assert state(screen)["running"].startswith("line 4")
    dropped = screen.json("POST", "/api/event", "signal hold")[1]
    assert dropped == {"event": "signal hold", "runs": 0, "dropped": 1, "queued": 0}
    assert runs(screen, "signal hold")["dropped"] == 1
    stop = screen.json("POST", "/api/event", "signal stop")[1]
    assert stop["runs"] == 1
    eventually(lambda: state(screen)["running"] is None)
    assert json.dumps(state(screen))  # the state is plain JSON throughout


def test_it_stops_on_sigterm_while_a_forever_of_millisecond_rounds_plays(tmp_path):
    import signal

    # The frame pump's wait for a wake lost the server's cancel when a wake came with it (Python
    # before 3.12), and wakes came every few milliseconds: the process never ended.
    with running_screen(tmp_path, "--no-idle") as screen, pages(screen) as (page,):
        page.until(lambda m: isinstance(m, bytes))
        answer = screen.json("POST", "/api/command", "forever { wait 0.001s; look left in 0.001s }")
        assert answer[0] == 200, answer
        eventually(lambda: state(screen)["face"]["eye_x"] != 0)
        assert screen.stop(signal.SIGTERM, timeout=30) == 128 + signal.SIGTERM
        assert screen.log()[-1] == "baxterface screen: stopped"


@pytest.mark.parametrize(
    "spin",
    [
        "forever { wait until signal x timeout 0.000001s }",
        "forever { wait 0.00001s }",
        "on signal go { forever { wait until face seen timeout 0.000001s } }\nsignal go",
    ],
)
def test_a_script_of_rounds_that_end_at_once_leaves_the_face_answering(tmp_path, spin):
    import signal

    # Each of these passed `check` and froze the screen: no answer to anything after it, a core
    # busy, SIGTERM ignored. Now each round lasts a fiftieth of a second at least.
    with running_screen(tmp_path, "--no-idle") as screen:
        assert screen.json("POST", "/api/command", spin)[0] == 200
        for _ in range(3):
            status, answer = screen.json("POST", "/api/event", "touch")
            assert status == 200 and answer["event"] == "touch", answer
            assert state(screen)["face"] is not None
        assert screen.json("POST", "/api/command", "sad")[0] == 200
        eventually(lambda: state(screen)["face"]["emotion"] == "sad")
        assert screen.stop(signal.SIGTERM, timeout=30) == 128 + signal.SIGTERM
