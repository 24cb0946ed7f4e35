"""What keeps a live session in time whatever a script says (issue 43's hostile scripts): a
`forever`'s least round, no recursion through signals, a face that fell behind its clock, and the
handlers a face keeps, in number and in what each holds."""

from __future__ import annotations

import pytest

from baxterface_cli import parse
from baxterface_cli.core.face_constants import LIMITS
from baxterface_cli.engine.live_session import MAX_BEHIND, LiveSession
from baxterface_cli.engine.session_run import run_over
from baxterface_cli.language import syntax_tree as n
from baxterface_cli.language.diagnostics import ScriptError


def session(text: str, keep_up: bool = False) -> LiveSession:
    return LiveSession(parse(text, "t.face"), idle=False, keep_up=keep_up)


def lines(s: LiveSession, *words: str):
    return [e for e in s.log if all(w in e.text for w in words)]


def test_a_forever_whose_rounds_end_at_once_takes_fifty_rounds_a_second():
    # `wait until ... timeout 0.000001s` in a `forever` spun a core and froze the screen and the node.
    s = session("forever { wait until signal x timeout 0.000001s }")
    s.advance(2.0)
    rounds = len(lines(s, "timed out"))
    assert 2.0 / LIMITS.least_round - 1 <= rounds <= 2.0 / LIMITS.least_round + 1
    times = [e.at for e in lines(s, "timed out")]
    assert min(b - a for a, b in zip(times, times[1:])) == pytest.approx(LIMITS.least_round)


def test_a_forever_of_tiny_waits_renders_at_the_least_round_and_longer_rounds_are_untouched():
    short = run_over(parse("forever { wait 0.00001s }", "t.face"), duration=1.0).session
    assert short.steps <= 2 * (1.0 / LIMITS.least_round + 1)  # a Lap and a wait a round
    s = session("forever { blink; wait 0.5s }")
    s.advance(3.0)
    # A round that is long enough is not stretched: its blinks come every 0.5 s plus the blink.
    assert s.steps < 3.0 / 0.5 * 3 + 3


def test_a_thousand_signals_in_a_row_run_without_running_out_of_stack():
    # `repeat 1000 { signal x }` was a RecursionError: an internal error, a 500 at the screen.
    for text in (
        "on signal x { wait 0s }\nrepeat 1000 { signal x }",
        "repeat 1000 { signal x }",
        "on signal x queue { blink }\non touch { repeat 1000 { signal x } }",
    ):
        s = session(text)
        s.post(n.Event("touch"), 1.0)
        s.advance(100.0)
        assert len(lines(s, "event signal x")) == 1000, text
    s = session("on signal x queue { blink }\non touch { repeat 1000 { signal x } }")
    s.post(n.Event("touch"), 1.0)
    s.advance(100.0)
    counts = s.counts()["line 1 'on signal x'"]
    assert counts["runs"] >= 1 and counts["runs"] + counts["dropped"] == 1000


def test_a_live_face_that_falls_behind_its_clock_stops_the_run_and_goes_on_from_now():
    # Ten thousand 10 us waits, each a step of its own (a signal between), each a compile: never
    # catching up with a real clock. The run is stopped with one line once it is a second behind,
    # and the face takes what comes next at once.
    s = session("on touch { happy }", keep_up=True)
    s.run(parse("repeat 10000 { wait 0.00001s; signal tick }", "t.face"), 0.0)
    s.advance(5.0)
    stopped = lines(s, "stopped:", "behind the clock")
    assert len(stopped) == 1 and stopped[0].text.startswith("main script stopped: ")
    assert s.steps < 3 * MAX_BEHIND  # of 20,000
    s.post(n.Event("touch"), 5.0)
    assert lines(s, "'on touch' runs")[0].at == 5.0
    # A recorded run has no wall clock to fall behind: it takes every step.
    assert not session("repeat 300 { wait 0.00001s }").keep_up


def test_a_script_past_the_handlers_a_face_keeps_is_refused_whole_and_changes_nothing():
    s = session("on touch { happy }")
    many = "\n".join(f"on signal s{i} {{ blink }}" for i in range(LIMITS.max_handlers))
    with pytest.raises(ScriptError) as refused:
        s.run(parse(many, "many.face"), 1.0)
    assert f"more handlers than the {LIMITS.max_handlers} a face keeps: it has 1" in refused.value.summary()
    assert [h.label for h in s.handlers] == ["line 1 'on touch'"]
    # Replacing handlers is not adding them: the same events sent again are taken.
    s.run(parse("\n".join(f"on signal s{i} {{ blink }}" for i in range(LIMITS.max_handlers - 1)), "m"), 2.0)
    s.run(parse("\n".join(f"on signal s{i} {{ nod }}" for i in range(LIMITS.max_handlers - 1)), "m"), 3.0)
    assert len(s.handlers) == LIMITS.max_handlers


def test_more_every_handlers_than_a_face_keeps_in_time_are_refused():
    s = session("on touch { happy }")
    many = "\n".join(f"on every {0.1 + i / 1000:g}s {{ blink }}" for i in range(LIMITS.max_every + 1))
    with pytest.raises(ScriptError) as refused:
        s.run(parse(many, "every.face"), 1.0)
    assert f"more 'every' handlers than the {LIMITS.max_every} a face keeps" in refused.value.summary()
    assert len(s.handlers) == 1


def test_every_handlers_of_many_periods_each_tick_on_time():
    periods = [0.1 + i / 100 for i in range(LIMITS.max_every)]
    s = session("\n".join(f"on every {p:g}s queue {{ wait 0s }}" for p in periods))
    s.advance(10.0)
    runs = {label: c["runs"] + c["dropped"] for label, c in s.counts().items()}
    for line, period in enumerate(periods, start=1):
        assert runs[f"line {line} 'on every {period:g}s'"] == int(10.0 / period + 1e-9)


def test_a_handler_keeps_only_the_definitions_it_calls():
    # Each handler kept its whole script: 4.5 MB a handler for a script of 3,000 definitions.
    defines = "\n".join(f"define d{i} {{ blink }}" for i in range(3000))
    s = session(defines + "\ndefine nodding { nod; d7 }\non touch { nodding }")
    (handler,) = s.handlers
    assert [d.name for d in handler.script.body] == ["d7", "nodding"]
    s.post(n.Event("touch"), 1.0)
    s.advance(5.0)
    assert lines(s, "'on touch' ends")


def test_a_recorded_run_whose_handler_runs_a_forever_asks_for_a_duration():
    # It ran on to the step bound at 500 s of run, and said so as if the rounds were the fault.
    from baxterface_cli.engine.session_run import NeverRests
    from baxterface_cli.language.event_trace import parse_trace

    script = parse("on signal go { forever { wait until face seen timeout 0.5s } }", "h.face")
    with pytest.raises(NeverRests) as never:
        run_over(script, parse_trace("0.5 signal go", "go.events"))
    said = "'forever' on line 1 never ends once line 1 'on signal go' runs it; give --duration"
    assert str(never.value) == said
    ended = run_over(script, parse_trace("0.5 signal go", "go.events"), duration=3.0)
    assert len([line for line in ended.log if "timed out" in line.text]) == 5
