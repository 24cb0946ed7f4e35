"""The statement table (language/statements.py) is complete: a new statement is one `Kind`, its
grammar rule, its builder method and its compile step, and nothing lets one of them be forgotten."""

from __future__ import annotations

import dataclasses

import pytest

from baxterface_cli import parse
from baxterface_cli.engine import compiler
from baxterface_cli.engine.compiler import COMPILE_STEPS, compile_script
from baxterface_cli.language import syntax_tree as n
from baxterface_cli.language.builder import _Builder, grammar
from baxterface_cli.language.statements import (
    KEYWORDS,
    KINDS,
    SESSION_KINDS,
    Kind,
    describe,
    statement_seconds,
)
from baxterface_cli.language.vocabulary import BARE_WORDS


def test_every_statement_node_has_a_kind_and_a_compile_step():
    nodes = {cls for cls in vars(n).values() if isinstance(cls, type) and issubclass(cls, n.Statement)}
    # The compiler's statements, and the live session's (handlers, waits, signals, forever, one of),
    # which it walks itself and never hands to the compiler (engine/session_program.py).
    assert nodes - {n.Statement, n.Block} == set(KINDS) | set(SESSION_KINDS)
    assert set(KINDS) == set(COMPILE_STEPS) and not set(KINDS) & set(SESSION_KINDS)
    assert set(n.BLOCKS) == {n.Repeat, n.Together, n.Define, n.On, n.Forever, n.OneOf, n.State, n.Ask}


def test_every_statement_can_be_written_and_its_words_are_the_grammars():
    grammar_words = {getattr(t.pattern, "value", "") for t in grammar().terminals}
    for kind in [*KINDS.values(), *SESSION_KINDS.values()]:
        written = kind.words or ((kind.bare,) if kind.bare else ())
        assert written or kind.node is n.Call, f"{kind.node.__name__} has no words"
        assert set(kind.words) <= grammar_words, kind.node.__name__
        if kind.bare:
            assert BARE_WORDS[kind.bare] is kind.node
            (statement,) = parse(kind.bare).body
            assert type(statement) is kind.node
    assert len(KEYWORDS) == len(set(KEYWORDS))


def test_every_timed_move_says_how_long_it_takes_without_in_t():
    for kind in [*KINDS.values(), *SESSION_KINDS.values()]:
        fields = {f.name for f in dataclasses.fields(kind.node)}
        assert ("timing" in fields) == (kind.move is not None or kind.node is n.Feeling), kind.node.__name__
    (look,) = parse("look left").body
    assert statement_seconds(look) == KINDS[n.Look].move
    (timed,) = parse("look left in 2s").body
    assert statement_seconds(timed) == 2.0


def test_every_grammar_rule_has_a_builder_method():
    # Without one, lark builds a bare tree for the rule instead of a syntax-tree node.
    rules = {str(r.alias or r.origin.name) for r in grammar().rules if not r.options.expand1}
    missing = sorted(r for r in rules if not r.startswith("_") and not hasattr(_Builder, r))
    assert not missing


def test_a_statement_without_a_compile_step_is_named_when_the_engine_loads(monkeypatch):
    @dataclasses.dataclass(frozen=True)
    class WaitUntil(n.Statement):
        pos: n.Pos = n.NOWHERE

    monkeypatch.setitem(KINDS, WaitUntil, Kind(WaitUntil, words=("wait",)))
    with pytest.raises(TypeError, match=r"write _Compiler\.do_wait_until"):
        compiler._compile_steps()


@pytest.mark.parametrize(
    "text",
    [
        "happy",
        "wake up",
        "sad variant 2",
        "happy 0.6 + confused 0.4 in 1s ease-in-out",
        "happy variant 3 0.4 + confused variant 2 0.2 in 1s",
        "mood 0.6 -0.2 in 2s",
        "wink left",
        "look 40 -20 in 0.5s ease-in-out",
        "dynamic look 10 0 in 1s",
        "eyelids 0.5 in 1s",
        "wait 0.7s",
        "skin 3",
        "mouth smile",
        "brows left raised",
        "mouth curve 0.5 in 1s",
        "pupils left 0.8 in 1s",
        'say "Hello \\"there\\"." voice en-gb rate 150',
        "follow left arm dynamic",
        "follow off",
        "blink",
        "nod",
        "exit",
    ],
)
def test_explain_lists_each_statement_as_a_script_writes_it(text):
    (statement,) = parse(text).body
    (written,) = parse(describe(statement)).body
    assert written == statement
    (span,) = compile_script(parse(text)).spans
    assert span.text == describe(statement)


@pytest.mark.parametrize(
    "text",
    [
        "on face seen queue cooldown 5s { blink }",
        "on button left ok interrupt { blink }",
        'on word "hello there" { blink }',
        "on every 2.5s { blink }",
        'wait until word "hi" timeout 5s',
        "wait until touch left eye",
        "signal poke",
    ],
)
def test_the_session_s_statements_are_described_as_a_script_writes_them(text):
    (statement,) = parse(text).body
    written = describe(statement)
    assert text.startswith(written)
    (again,) = parse(text.replace(written, written, 1)).body
    assert again == statement
