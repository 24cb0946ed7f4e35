"""The live session behind a worker (engine/session_intake.py), as the face node drives it:
commands and events from other threads, steps compiled on the worker, the frame loop never
waiting. The clock is the test's; the worker is real."""

from __future__ import annotations

import threading
from typing import List, Tuple

import pytest

from baxterface_cli.engine.live_session import MAX_QUEUE, LiveSession
from baxterface_cli.engine.session_intake import SessionIntake
from baxterface_cli.language import syntax_tree as n
from tests.support.waiting import eventually

OK = n.Event("button", "left ok")


class Clock:
    def __init__(self) -> None:
        self.now = 10.0

    def __call__(self) -> float:
        return self.now


@pytest.fixture()
def live():
    clock = Clock()
    session = LiveSession(idle=False, now=clock.now)
    logged: List[Tuple[str, str]] = []
    intake = SessionIntake(session, clock, log=lambda level, text: logged.append((level, text)))
    yield session, intake, clock, logged
    intake.close()


def runs(session: LiveSession, label: str) -> int:
    return session.counts().get(label, {}).get("runs", 0)


def test_a_handler_sent_installs_itself_and_a_signal_sent_runs_it(live):
    session, intake, clock, _ = live
    intake.submit("on signal poke { happy }")
    eventually(lambda: session.handlers)
    before = session.face.timeline
    intake.submit("signal poke")
    eventually(lambda: runs(session, "line 1 'on signal poke'") == 1)
    assert session.face.timeline is not before
    clock.now += 5.0
    assert session.frame(clock.now)[0].emotion == "happy"


def test_a_handler_sent_twice_replaces_the_first_and_says_so(live):
    session, intake, _, logged = live
    intake.submit("on button ok { sad }")
    intake.submit("on button ok { happy }")  # a take-over replaces one still unread: submit apart
    eventually(lambda: intake.idle() and session.handlers)
    intake.submit("on button ok { angry }")
    eventually(lambda: ("info", "button ok: its handler replaced") in logged)
    assert [h.on.body[0].name for h in session.handlers] == ["angry"]  # one handler, the newest


def test_a_plain_command_takes_over_and_a_queued_one_waits_for_the_main_script(live):
    session, intake, clock, _ = live
    intake.submit("sad; wait 2s")
    eventually(lambda: session.main is not None)
    intake.submit("happy", queued=True)
    eventually(lambda: intake.idle() and len(intake.waiting) == 1)
    clock.now += 3.0  # the main script ends: the queued one starts
    intake.post(n.Event("signal", "tick"))
    eventually(lambda: not intake.waiting)
    clock.now += 2.0
    assert session.frame(clock.now)[0].emotion == "happy"


def test_a_bad_command_is_one_line_and_the_next_one_runs(live):
    session, intake, clock, logged = live
    intake.submit("on nonsense { nod }")
    eventually(lambda: any(level == "error" for level, _ in logged))
    assert logged[0][1].startswith("bad command: display_chatter:1:4: error: unknown event 'nonsense'")
    intake.submit("angry")
    clock.now += 3.0
    eventually(lambda: session.tick(clock.now)[0].emotion == "angry")


def test_a_storm_of_events_keeps_every_handler_in_its_policy(live):
    session, intake, clock, _ = live
    intake.submit("on button ok { nod; wait 1s }\non button up queue { blink }")
    eventually(lambda: len(session.handlers) == 2)
    for i in range(3000):
        clock.now += 0.001
        intake.post(OK if i % 2 else n.Event("button", "left up"), "storm")
    eventually(intake.idle)
    counts = session.counts()
    ok, up = counts["line 1 'on button ok'"], counts["line 2 'on button up'"]
    assert intake.posted == 3000 and intake.events_dropped == 0
    assert ok["runs"] + ok["dropped"] == 1500  # drop: each press ran or was counted
    waiting = len(session.pending)
    assert waiting <= MAX_QUEUE and up["dropped"] > 0  # queue: bounded, the rest counted
    assert up["runs"] + waiting + up["dropped"] == 1500  # each ran, waits its turn, or was counted


def test_the_frame_loop_never_waits_for_the_worker(live):
    session, _, clock, _ = live
    held, release = threading.Event(), threading.Event()

    def busy_worker():
        with session.lock:  # as the worker holds it while it compiles a `say`
            held.set()
            release.wait(30)

    thread = threading.Thread(target=busy_worker)
    thread.start()
    held.wait(30)
    try:
        state, cues = session.frame(clock.now)  # returns at once, the face as it plays
        assert state is not None and cues == []
    finally:
        release.set()
        thread.join()
