"""States on the live session: a state's handlers live only while the face is in it, `go` stops
what runs as an `interrupt` does and runs the state's body, `go back` returns, and states that go
to each other in no time are stopped."""

from __future__ import annotations

from baxterface_cli import parse
from baxterface_cli.engine.live_session import LiveSession
from baxterface_cli.engine.session_records import LogKind
from baxterface_cli.engine.session_run import run_over
from baxterface_cli.language import syntax_tree as n
from baxterface_cli.language.event_trace import parse_trace

GREETER = """\
state asleep {
    sleep
    on button wheel { go awake }
}
state awake {
    wake up; happy
    on touch { nod }
    on button wheel { sad }
}
on signal back { go back }
go asleep
"""
WHEEL, TOUCH = n.Event("button", "wheel up"), n.Event("touch")


def session(text: str = GREETER) -> LiveSession:
    return LiveSession(parse(text, "g.face"), idle=False)


def lines(s: LiveSession, kind: str):
    return [f"{e.at:g} {e.text}" for e in s.log if e.kind == kind]


def test_while_asleep_only_the_asleep_states_handlers_run_and_awake_its_own():
    s = session()
    s.post(TOUCH, 1.0)  # asleep: nothing handles a touch (the greeter greeted while asleep)
    s.post(WHEEL, 2.0)  # asleep's wheel: go awake
    s.post(TOUCH, 5.0)
    s.post(WHEEL, 7.0)  # awake's own wheel handler, not asleep's
    s.advance(10.0)
    assert lines(s, LogKind.ENTERED) == [
        "0 state asleep entered: main script, line 11 'go asleep'",
        "2 state awake entered: line 3 'on button wheel', line 3 'go awake'",
    ]
    assert lines(s, LogKind.STARTED) == [
        "2 line 3 'on button wheel' runs",
        "5 line 7 'on touch' runs",
        "7 line 8 'on button wheel' runs",
    ]
    assert s.states.current == "awake"


def test_go_stops_what_runs_where_it_is_and_go_back_returns_to_the_state_before():
    s = session(GREETER.replace("wake up; happy", "wake up; happy; look left in 3s; wait 5s"))
    s.post(WHEEL, 1.0)  # awake: its look begins at 2.1 s and is stopped at 3.1 s
    s.advance(3.1)
    eyes = s.face.state(3.1).eye_x
    s.post(n.Event("signal", "back"), 3.1)
    went = "3.1 state asleep entered: line 10 'on signal back', line 10 'go back'"
    assert lines(s, LogKind.ENTERED)[-1] == went
    s.advance(3.5)
    assert 0 < abs(s.face.state(3.5).eye_x) <= abs(eyes) + 1e-6  # stopped where it was, not finished
    s.post(n.Event("signal", "back"), 6.0)
    assert lines(s, LogKind.ENTERED)[-1].startswith("6 state awake entered")


def test_states_that_go_to_each_other_in_no_time_are_stopped_and_the_face_goes_on():
    s = session("state a { go b }\nstate b { go a }\non touch { nod }\ngo a")
    stopped = lines(s, LogKind.STOPPED)
    assert len(stopped) == 1 and "100 states were entered without time passing" in stopped[0]
    s.post(TOUCH, 1.0)
    assert lines(s, LogKind.STARTED) == ["1 line 3 'on touch' runs"]


def test_a_conversation_with_states_renders_the_same_twice_to_the_bit():
    script = parse(GREETER, "g.face")
    trace = parse_trace("1 touch\n2 button wheel up\n5 touch\n8 signal back\n9 touch", "g.events")
    first, again = run_over(script, trace), run_over(script, trace)
    assert [(e.at, e.text) for e in first.log] == [(e.at, e.text) for e in again.log]
    for t in (0.5, 2.5, 5.2, 8.5, 9.5):
        assert first.timeline.sample(t) == again.timeline.sample(t)
    assert "state awake entered" in " ".join(e.text for e in first.log)


def test_a_script_of_states_alone_sent_to_a_running_face_installs_them_and_takes_nothing_over():
    s = session("look left in 5s")
    s.run(parse("state calm { happy }\non touch { go calm }", "later"), 1.0)
    assert s.main is not None and s.main.label == "main script" and not s.main.done
    s.post(TOUCH, 2.0)
    assert lines(s, LogKind.ENTERED) == ["2 state calm entered: line 2 'on touch', line 2 'go calm'"]


def test_idle_counts_from_when_its_script_arrived_not_from_the_faces_start():
    # Sent to a node up for a minute, `on idle 30s` ran at once: the minute counted as idle.
    s = LiveSession(idle=False, now=0.0)
    s.run(parse("on idle 30s { nod }", "later"), 60.0)
    s.advance(89.0)
    assert lines(s, LogKind.STARTED) == []
    s.advance(91.0)
    assert lines(s, LogKind.STARTED) == ["90 line 1 'on idle 30s' runs"]
