"""The live session behind a worker (engine/session_intake.py), as the face node drives it:
commands and events from other threads, steps compiled on the worker, the frame loop never
waiting. The clock is the test's; the worker is real."""

from __future__ import annotations

import threading
from typing import List, Tuple

import pytest

from baxterface_cli.engine.live_session import LiveSession
from baxterface_cli.engine.session_handlers import MAX_QUEUE
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
    assert session.face.state(clock.now).emotion == "happy"


def test_a_handler_sent_twice_replaces_the_first_and_says_so(live):
    session, intake, _, logged = live
    intake.submit("on button ok { sad }")
    intake.submit("on button ok { happy }")  # back to back: each is taken, in the order sent
    intake.submit("on button ok { angry }")
    # Said once: the same line again within a second is counted, and told with the next one.
    eventually(lambda: ("info", "button ok: its handler replaced") in logged and intake.idle())
    assert [h.on.body[0].name for h in session.handlers] == ["angry"]  # one handler, the newest


def test_handler_lines_sent_back_to_back_are_all_installed_and_a_take_over_between_them_is_let_go(live):
    # 50 handler lines through `send --stdin` installed 2 (the first and the last): a handler-only
    # command was taken for a take-over, and one still unread was replaced by the next.
    session, intake, _, _ = live
    with session.lock:  # all sent before the worker hands the first over
        for i in range(50):
            intake.submit(f"on signal s{i} {{ nod }}")
            if i == 10:
                intake.submit("sad; wait 5s")  # a take-over that a later one replaces before it starts
        intake.submit("happy")
    eventually(lambda: intake.idle() and len(session.handlers) == 50)
    assert sorted(h.on.event.arg for h in session.handlers) == sorted(f"s{i}" for i in range(50))
    assert intake.dropped == 1  # "sad; wait 5s", whose main statements never started
    assert session.main is not None and session.main.script.source == "happy"


def test_commands_past_the_unread_bound_are_refused_with_a_reason():
    session = LiveSession(idle=False)
    intake = SessionIntake(session, lambda: 0.0, max_unread=3)
    with intake:
        session.lock.acquire()  # the worker cannot hand anything over meanwhile
        try:
            answers = [intake.submit(f"on signal s{i} {{ nod }}") for i in range(6)]
        finally:
            session.lock.release()
        refused = [a for a in answers if a is not None]
        assert refused and all(a == "refused a command: 3 are already waiting to be read" for a in refused)
        assert intake.settled(60.0)
    assert len(session.handlers) == 6 - len(refused)


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
    assert session.face.state(clock.now).emotion == "happy"


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
        assert session.catch_up(clock.now) == []  # returns at once, the cues wait
        assert session.face.state(clock.now) is not None  # the face as it plays
    finally:
        release.set()
        thread.join()


def test_a_line_repeated_every_round_is_forwarded_once_a_second_with_its_count(live):
    # A `forever` of waits that time out at once logged fifty lines a second to the node's log.
    session, intake, clock, logged = live
    intake.submit("forever { wait until signal x timeout 0.000001s }")
    eventually(lambda: intake.idle() and session.main is not None)
    clock.now += 5.0
    intake.post(n.Event("touch"))  # the worker goes on to the clock's time
    eventually(lambda: intake.idle() and session.clock >= clock.now)
    timed = [text for _, text in logged if "timed out" in text]
    assert 4 <= len(timed) <= 6, timed
    assert timed[-1].endswith("more like it in the second before)")


def test_a_take_over_let_go_for_a_later_one_still_installs_its_states(live):
    session, intake, _, _ = live
    with session.lock:  # both sent before the worker hands the first over
        intake.submit("state calm { happy }\non touch { go calm }\nsad; wait 5s")
        intake.submit("nod")
    eventually(lambda: intake.idle() and session.main is not None and session.main.script.source == "nod")
    assert "calm" in session.states.known and intake.dropped == 1


def slow_synthesis(monkeypatch, clock) -> List[str]:
    """Each text's first synthesis takes 0.4 s on the test's clock; the texts synthesised, in order."""
    from baxterface_cli.engine import compiler

    synthesised: List[str] = []
    real = compiler.engine_say

    def slow(text, voice, rate):
        if text not in synthesised:
            synthesised.append(text)
            clock.now += 0.4  # the time the synthesis took, on the test's clock
        return real(text, voice, rate)

    monkeypatch.setattr(compiler, "engine_say", slow)
    return synthesised


def test_a_command_that_speaks_starts_once_its_words_are_synthesised_its_sound_whole(live, monkeypatch):
    # Synthesis takes time (a natural voice 20 to 190 ms, more on a busy machine). Started at its
    # arrival, the command's first words were behind the clock by then, cut from sound and mouth.
    session, intake, clock, _ = live
    synthesised = slow_synthesis(monkeypatch, clock)
    intake.submit('say "Hello there"')
    eventually(lambda: session.face.timeline.speech)
    assert synthesised == ["Hello there"]  # once: ahead, and kept for the compile
    assert session.face.started == pytest.approx(10.4)  # when its words were ready, not 10.0
    said = session.face.timeline.speech[0]
    assert said.at == 0.0  # its sound from its first sample, at the face's start


def test_an_ask_sent_starts_once_its_question_is_synthesised_not_its_answers(live, monkeypatch):
    # The answers are said later, if ever: making them first would hold the question back.
    session, intake, clock, _ = live
    synthesised = slow_synthesis(monkeypatch, clock)
    intake.submit('ask "Ready?" { "yes" { say "Great" } nothing 3s { say "Bye" } }')
    eventually(lambda: session.face.timeline.speech)
    assert synthesised == ["Ready?"]
    assert session.face.started == pytest.approx(10.4)
