"""`ask` in the language: a question, its answers as phrases, `else` and `nothing`; each mistake
where it is written."""

from __future__ import annotations

from diagnosed import errors

from baxterface_cli import parse
from baxterface_cli.language import syntax_tree as n
from baxterface_cli.language.checker import phrases_listened

ASK = """\
ask "Shall we play a game?" rate 150 {
    "yes" | "Sure" { happy }
    "no" { sad }
    else { confused }
    nothing 5s { say "Never mind." }
}
"""


def test_an_ask_holds_its_question_its_answers_else_and_nothing():
    (ask,) = parse(ASK, "t.face").body
    assert ask.question == n.Say("Shall we play a game?", None, 150)
    assert [a.phrases for a in ask.answers] == [("yes", "sure"), ("no",)]
    assert len(ask.otherwise) == 1 and ask.otherwise[0].pos.line == 4
    assert ask.nothing[0] == 5.0 and len(ask.nothing[1]) == 1
    assert phrases_listened(parse(ASK).body) == ["yes", "sure", "no"]


def test_each_mistake_of_an_ask_is_named_where_it_is():
    assert errors('ask "Ready?" { }') == [
        't.face:1:1: error: \'ask\' needs an answer to listen for: ask "Ready?" { "yes" { happy } }'
    ]
    assert errors('ask "x" { "yes" { nod } else { nod } else { nod } }') == [
        "t.face:1:38: error: 'ask' takes one 'else'"
    ]
    assert errors('together { ask "q" { "a" { nod } } }') == [
        "t.face:1:12: error: 'ask' cannot be inside 'together', whose statements run side by side"
    ]
    assert errors('ask "q" { "a b c d e f g h i" { nod } }')[0].startswith(
        "t.face:1:11: error: an answer is a few words of letters"
    )
