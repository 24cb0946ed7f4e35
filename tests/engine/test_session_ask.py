"""`ask` on the live session: the question said, then the first answer heard runs (a word, or a
whole utterance that holds one), `else` for speech that is none, `nothing` when nobody spoke; and
nothing heard while the question is said counts."""

from __future__ import annotations

from baxterface_cli import parse
from baxterface_cli.engine.session_records import LogKind
from baxterface_cli.engine.session_run import run_over
from baxterface_cli.language.event_trace import parse_trace

ASK = """\
ask "Shall we play a game?" {
    "yes" | "sure" { happy }
    "no" { sad }
    else { confused }
    nothing 5s { bored }
}
nod
"""


def answered(events: str):
    run = run_over(parse(ASK, "ask.face"), parse_trace(events, "ask.events"), duration=12.0)
    lines = [f"{e.at:g} {e.text}" for e in run.log if e.kind == LogKind.ANSWERED]
    return lines, run


def test_a_word_heard_after_the_question_runs_its_answer_and_the_script_goes_on():
    lines, run = answered('2.5 word "sure"')
    assert lines == ['2.5 main script: line 1 \'ask "Shall we play a game?"\' answered "sure" (line 2)']
    assert run.timeline.sample(2.9).emotion == "happy"
    assert any("nod" in str(s) for s in run.timeline.spans)


def test_a_whole_utterance_chooses_the_answer_it_holds_or_else():
    lines, run = answered('2.5 heard "oh no thanks"')
    assert lines[0].endswith('answered "no" in "oh no thanks"') and run.timeline.sample(2.9).emotion == "sad"
    lines, run = answered('2.5 heard "maybe later"')
    assert lines[0].endswith('answered none of its answers: "maybe later"')
    assert run.timeline.sample(2.9).emotion == "confused"


def test_nobody_speaking_runs_nothing_and_a_word_said_during_the_question_is_not_an_answer():
    lines, run = answered('0.3 word "yes"')  # while it asks: the face does not hear itself answered
    assert len(lines) == 1 and "nothing heard within 5 s" in lines[0]
    asked = float(lines[0].split()[0])
    assert asked > 5.0 and run.timeline.sample(asked + 0.4).emotion == "bored"
