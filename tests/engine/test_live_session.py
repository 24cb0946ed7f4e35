"""The live session (engine/live_session.py) on a clock the test gives: handlers and their
policies, waits, timers, signals and choices, as a user of `on ... { }` would see them."""

from __future__ import annotations

from typing import List

import pytest

from baxterface_cli import parse
from baxterface_cli.engine import live_session
from baxterface_cli.engine.live_session import LiveSession
from baxterface_cli.engine.session_run import run_over
from baxterface_cli.language import syntax_tree as n
from baxterface_cli.language.diagnostics import ScriptError
from baxterface_cli.language.event_trace import parse_trace

SEEN = n.Event("face seen")


def session(text: str, seed: int = 0) -> LiveSession:
    return LiveSession(parse(text, "t.face"), seed=seed, idle=False)


def said(s: LiveSession, *words: str) -> List[str]:
    """The log's lines that contain every word, as 'time text'."""
    return [f"{e.at:g} {e.text}" for e in s.log if all(w in e.text for w in words)]


def test_drop_ignores_the_event_while_its_handler_runs_and_counts_it():
    s = session("on face seen { wait 2s }")
    s.post(SEEN, 1.0)
    s.post(SEEN, 1.5)
    s.post(SEEN, 2.9)
    s.post(SEEN, 3.0)  # the handler ended at 3: this one runs
    assert said(s, "runs") == ["1 line 1 'on face seen' runs", "3 line 1 'on face seen' runs"]
    assert s.counts()["line 1 'on face seen'"] == {"runs": 2, "dropped": 2, "queued": 0}


def test_queue_runs_each_event_after_the_one_running_in_order():
    s = session('on face seen { wait 1s }\non word "hi" queue { wait 1s }\non touch queue { wait 1s }')
    s.post(SEEN, 0.0)
    s.post(n.Event("touch", "mouth"), 0.2)
    s.post(n.Event("word", "hi"), 0.4)
    s.advance(10.0)
    assert said(s, "runs") == [
        "0 line 1 'on face seen' runs",
        "1 line 3 'on touch' runs",
        "2 line 2 'on word \"hi\"' runs",
    ]


def test_interrupt_stops_what_runs_and_the_main_script_resumes_where_it_stopped():
    s = session(
        "look left in 1s\nwait 4s\nlook right in 1s\non face seen { wait 1s }\non touch interrupt { nod }"
    )
    s.post(SEEN, 2.0)  # the main script is 1 s into its wait: paused
    s.post(n.Event("touch"), 2.5)  # the face seen handler is cut short by the touch's
    s.advance(20.0)
    assert said(s, "runs") == ["2 line 4 'on face seen' runs", "2.5 line 5 'on touch' runs"]
    assert said(s, "interrupted") == ["2.5 line 4 'on face seen' interrupted"]
    assert said(s, "goes on") == ["3.5 main script goes on"]  # a nod takes 1 s
    timeline = run_over(parse(s.main.script.source), parse_trace("2 face seen\n2.5 touch")).timeline
    spans = [(round(x.start, 3), round(x.end, 3), x.text) for x in timeline.spans]
    # The wait waits out the 3 s it had left; the main script's next statement follows.
    assert spans[-2:] == [(3.5, 6.5, "wait 3s"), (6.5, 7.5, "look -65 0 in 1s")]
    assert spans[1] == (1.0, 2.0, "wait 4s (stopped)")
    assert s.main.done


def test_an_interrupt_stops_moves_where_they_are_a_drop_handler_lets_them_finish():
    text = "look left in 2s\non face seen { wait 1s }\non touch interrupt { wait 1s }"
    moved = run_over(parse(text), parse_trace("1 face seen")).timeline
    stopped = run_over(parse(text), parse_trace("1 touch")).timeline
    assert moved.sample(1.5).eye_x > stopped.sample(1.5).eye_x == stopped.sample(1.0).eye_x
    assert moved.sample(2.0).eye_x == run_over(parse("look left in 2s")).timeline.sample(2.0).eye_x


def test_speech_stops_at_once_and_the_mouth_comes_to_rest():
    text = 'say "Hello there, how are you today?"\non touch interrupt { wait 1s }'
    run = run_over(parse(text), parse_trace("0.5 touch"))
    cut, again = run.timeline.speech  # cut short, then said again when the main script goes on
    assert cut.end <= 0.5 + 1e-6 and again.at == 1.5
    assert run.timeline.sounding(0.6) == []
    quiet = run_over(parse("wait 1s")).timeline.sample(0.7)
    assert run.timeline.sample(0.7).expression == quiet.expression


def test_cooldown_ignores_its_event_for_a_while_after_its_handler_started():
    s = session("on face seen cooldown 5s { blink }")
    for at in (0.0, 1.0, 4.9, 5.0, 6.0):
        s.post(SEEN, at)
    assert [e.split()[0] for e in said(s, "runs")] == ["0", "5"]
    assert said(s, "cools down") == [
        "1 dropped face seen: line 1 'on face seen' cools down till 5.00 s",
        "4.9 dropped face seen: line 1 'on face seen' cools down till 5.00 s",
        "6 dropped face seen: line 1 'on face seen' cools down till 10.00 s",
    ]


def test_wait_until_goes_on_at_the_event_or_at_its_timeout():
    s = session('wait until face seen\nsignal first\nwait until word "hi" timeout 2s\nsignal second')
    s.advance(3.0)
    assert said(s, "signal") == []
    s.post(SEEN, 3.0)
    s.advance(10.0)
    assert said(s, "event signal") == ["3 event signal first (line 2)", "5 event signal second (line 4)"]
    assert said(s, "timed out") == ["5 main script: 'wait until word \"hi\"' timed out"]


def test_every_ticks_on_the_clock_and_idle_comes_after_nothing_happened():
    s = session("on every 2s { signal tick }\non idle 5s { signal bored }\non signal tick queue { blink }")
    s.advance(6.5)
    assert [e.split()[0] for e in said(s, "event signal tick")] == ["2", "4", "6"]
    assert said(s, "event signal bored") == []  # the signals ticking are events: not idle
    quiet = session("on idle 5s { nod }")
    quiet.post(n.Event("touch"), 3.0)
    quiet.advance(20.0)
    assert said(quiet, "runs") == ["8 line 1 'on idle 5s' runs"]  # once, until an event comes


def test_one_of_is_repeatable_with_the_seed_and_varies_with_it():
    text = "repeat 12 { one of { signal a | signal b | signal c } }"
    runs = {
        seed: [e.text.split()[2] for e in session(text, seed).log if "signal" in e.text] for seed in (1, 2)
    }
    again = [e.text.split()[2] for e in session(text, 1).log if "signal" in e.text]
    assert runs[1] == again and len(again) == 12 and set(again) == {"a", "b", "c"}
    assert runs[1] != runs[2]


def test_a_signal_raised_by_a_statement_runs_its_handler_and_the_main_script_goes_on():
    s = session("signal hello\nwait 1s\non signal hello { wait 1s }")
    s.advance(5.0)
    assert said(s, "runs") == ["0 line 3 'on signal hello' runs"]
    assert said(s, "goes on") == ["1 main script goes on"] and said(s, "main script ends") == [
        "2 main script ends"
    ]


def test_ticks_give_the_face_and_the_robot_cues_once_each():
    s = session("on face seen { nod }")
    s.post(SEEN, 1.0)
    _, before = s.tick(0.9)
    _, cues = s.tick(1.5)
    _, again = s.tick(1.6)
    assert before == [] and [type(c.effect).__name__ for c in cues] == ["HeadNod"] and again == []


def test_a_submitted_script_installs_handlers_and_signals_keep_the_main_script():
    s = session("forever { look left in 1s; look right in 1s }")
    s.run(parse("on signal poke { blink }", "display_chatter"), 0.5)
    s.run(parse("signal poke", "display_chatter"), 1.0)
    assert said(s, "runs") == ["1 line 1 'on signal poke' runs"]
    assert s.main.runner.forever
    s.run(parse("on signal poke { nod }", "display_chatter"), 2.0)
    assert said(s, "replaced") == ["2 signal poke: its handler replaced"]
    s.run(parse("happy", "display_chatter"), 3.0)
    assert not s.main.runner.forever


def test_the_face_exits_and_then_ignores_events():
    s = session("on face seen { exit }")
    s.post(SEEN, 1.0)
    s.advance(10.0)
    assert s.exited and said(s, "exits")
    s.post(SEEN, 11.0)
    assert s.ignored == 1


def test_the_old_nodes_commands_cut_on_the_session_as_the_old_node_did():
    # A legacy command's step keeps its legacy mark: no crossfade, one changed frame, not 0.2 s of them.
    session = LiveSession(idle=False, now=0.0)
    session.run(parse("skin_3", "display_chatter"), 1.0)
    shown = session.face.state(1.01)
    assert shown.skin == 3 and shown.fade == 1.0 and shown.pictured_from is None


def test_a_recorded_run_is_refused_at_its_step_bound_counting_rounds_of_waits(monkeypatch):
    # The bound made small. Rounds of a `wait until` that times out at once were not counted: such
    # a run grew its log by 8 MB a second, without end.
    monkeypatch.setattr(live_session, "LIMITS", live_session.LIMITS._replace(max_run_steps=500))
    script = parse("on signal go { forever { wait until face seen timeout 0.000001s } }", "t.face")
    with pytest.raises(ScriptError) as refused:
        run_over(script, parse_trace("0.5 signal go", "go.events"), duration=60.0)
    message = refused.value.diagnostics[0].message
    assert message.startswith("the run takes more than 500 steps by ") and "very short rounds" in message


def test_each_log_line_says_what_kind_of_thing_it_tells():
    # The node forwarded lines by matching words of their text: rewording one changed what ROS logged.
    from baxterface_cli.engine.session_records import LogKind

    s = session(
        "on touch { wait 1s }\non signal q queue { wait 1s }\non signal cut interrupt { nod }\n"
        "wait until face seen timeout 0.5s; exit"
    )
    for at, event in ((0.1, "touch"), (0.2, "touch"), (0.3, "signal q"), (0.4, "signal cut")):
        s.post(n.Event(*event.split(" ", 1)), at)
    s.advance(10.0)
    kinds = {line.kind for line in s.log}
    known = {v for k, v in vars(LogKind).items() if k.isupper()}
    assert kinds <= known
    told = {LogKind.EVENT, LogKind.STARTED, LogKind.DROPPED, LogKind.QUEUED, LogKind.INTERRUPTED}
    assert told | {LogKind.ENDED} <= kinds
    assert [line.text for line in s.log if line.kind == LogKind.DROPPED] == [
        "dropped touch: line 1 'on touch' is running"
    ]


def test_a_crossfade_begun_as_a_step_ends_goes_on_fading_in_the_next_step():
    # `sleep` changes the skin at its very end; the `wait` after it starts as that crossfade does.
    # The pictures must fade through the wait as the compiled script has them, not hold the first
    # picture of the fade until the next change (a theme of pictures showed the old face).
    from baxterface_cli.engine.compiler import compile_script

    script = parse("sleep\nwait 1s\nhappy\n")
    compiled = compile_script(script, 0)
    session = run_over(script, None, 0).timeline
    fades = [(compiled.sample(t / 50).fade, session.sample(t / 50).fade) for t in range(1, 150)]
    under_way = [(c, s) for c, s in fades if 0.0 < c < 1.0]
    assert under_way, "the script's skin change should crossfade"
    assert all(abs(c - s) < 1e-6 for c, s in under_way)
