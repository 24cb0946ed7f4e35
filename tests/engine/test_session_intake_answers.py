"""The intake's answers (engine/session_intake.py): a sender that must say what its input did (the
screen's HTTP requests) gets a future, done once the worker has handed the input to the session.
The clock is the test's; the worker is real."""

from __future__ import annotations

import pytest

from baxterface_cli.engine.live_session import LiveSession
from baxterface_cli.engine.session_intake import Refused, SessionIntake
from baxterface_cli.language import syntax_tree as n
from baxterface_cli.language.diagnostics import ScriptError
from baxterface_cli.language.parser import parse

OK = n.Event("button", "ok")
WAIT = 30  # seconds a future may take before the test fails: a hang, not a slow machine


@pytest.fixture()
def live():
    session = LiveSession(idle=False, now=10.0)
    intake = SessionIntake(session, lambda: 10.0)
    yield session, intake
    intake.close()


def test_an_event_answers_what_it_did_to_its_handlers(live):
    session, intake = live
    assert intake.take(parse("on button ok { nod; wait 1s }", "c")).result(WAIT) is None
    assert [h.label for h in session.handlers] == ["line 1 'on button ok'"]  # in, once answered
    assert intake.posting(OK).result(WAIT) == {"runs": 1, "dropped": 0, "queued": 0}
    assert intake.posting(OK).result(WAIT) == {"runs": 0, "dropped": 1, "queued": 0}  # it still runs
    assert intake.posting(n.Event("signal", "nobody")).result(WAIT) == {"runs": 0, "dropped": 0, "queued": 0}


def test_a_script_that_cannot_run_answers_why_and_is_not_logged(live):
    session, intake = live
    logged = []
    intake.log = lambda level, text: logged.append(text)
    taken = intake.take(parse('say file "gone.wav"', "c.face"))
    with pytest.raises(ScriptError) as e:
        taken.result(WAIT)
    assert "cannot read recording 'gone.wav'" in e.value.diagnostics[0].message and logged == []


def test_settled_waits_until_everything_handed_over_is_in(live):
    session, intake = live
    intake.submit("on button ok { nod }")
    for _ in range(500):
        intake.post(OK, "storm")
    assert intake.settled(WAIT)
    assert intake.posted == 500 and sum(session.counts()["line 1 'on button ok'"].values()) == 500


def test_a_closed_intake_refuses_at_once(live):
    _, intake = live
    intake.close()
    with pytest.raises(Refused, match="stopped"):
        intake.posting(OK).result(WAIT)
    with pytest.raises(Refused, match="stopped"):
        intake.take(parse("happy", "c")).result(WAIT)
