"""Property tests: scripts drawn from the grammar parse; nothing else escapes.

`from_lark` walks grammar/face.lark itself, so a rule added there is
exercised here without a change to this file. Terminals are given explicit
strategies that put a space around each token: lark's generator would
otherwise glue `look` and `40` into the one name `look40`.
"""

from __future__ import annotations

import re
import sys

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra.lark import from_lark
from lark import Lark
from lark.lexer import PatternStr

from baxterface_cli import ScriptError, parse
from baxterface_cli.cli.app import check_recordings
from baxterface_cli.core.face_constants import BROWS, DIRECTIONS, MOUTHS
from baxterface_cli.engine.compiler import compile_script
from baxterface_cli.engine.session_run import reactive, run_over
from baxterface_cli.engine.timeline import state_record
from baxterface_cli.language.checker import measure
from baxterface_cli.language.parser import decode, grammar
from baxterface_cli.language.vocabulary import BARE_WORDS
from baxterface_cli.resources import resource

pytestmark = pytest.mark.language

KEYWORDS = {t.pattern.value for t in grammar().terminals if isinstance(t.pattern, PatternStr)}


def spaced(strategy):
    return strategy.map(lambda s: f" {s} ")


def any_case(word):
    return st.sampled_from([word, word.upper(), word.capitalize()])


LEGACY_RE = re.compile(grammar().get_terminal("LEGACY").pattern.to_regexp())
# `left` and `right` are left out: where a side may come before a name (`brows left raised`),
# they are read as the side, so `brows right` drawn as a name would not be a sentence at all.
known_names = sorted(
    (set(BARE_WORDS) | set(MOUTHS) | set(BROWS) | set(DIRECTIONS) | {"linear", "ease-in-out"})
    - {"left", "right"}
)
invented_names = st.from_regex(r"[a-z_][a-z0-9_]{0,8}(-[a-z0-9_]{1,4})?", fullmatch=True).filter(
    lambda s: s not in KEYWORDS and not LEGACY_RE.fullmatch(s)
)
number = st.from_regex(r"[-+]?([0-9]{1,4}(\.[0-9]{0,3})?|\.[0-9]{1,3})", fullmatch=True)
unit = st.sampled_from(["", "", "s", "ms", "deg", "rad", "px", "%", "parsec"])
legacy = st.builds(
    lambda head, args: head + "".join("_" + a for a in args),
    st.sampled_from(["look", "dynamic_look", "wobble", "skin", "LOOK"]),
    st.lists(number, min_size=1, max_size=4),
)

EXPLICIT = {
    t.name: spaced(any_case(t.pattern.value))
    for t in grammar().terminals
    if isinstance(t.pattern, PatternStr)
}
EXPLICIT.update(
    NAME=spaced(st.one_of(st.sampled_from(known_names), invented_names)),
    QUANTITY=spaced(st.builds(str.__add__, number, unit)),
    LEGACY=spaced(legacy),
    COMMENT=st.just(" "),
    _NL=st.sampled_from(["\n", "\r\n", "\n\n"]),
    HUMAN=spaced(any_case("human")),
    OFF=spaced(any_case("off")),
    LEFT=spaced(any_case("left")),
    RIGHT=spaced(any_case("right")),
    _IN=spaced(any_case("in")),
    DYNAMIC=spaced(any_case("dynamic")),
)
# Built here rather than loaded: lark's tables loaded from the cache (as `grammar()` may give them)
# leave out the rules hypothesis draws from.
BUILT = Lark(resource("grammar/face.lark").read_text("utf-8"), parser="lalr", maybe_placeholders=False)
scripts = from_lark(BUILT, start="start", explicit=EXPLICIT)
# The search for odd scripts is the main suite's; under Python 3.8 (make test runs these there too)
# a quarter as many show that the language works there.
SEARCH = 1.0 if sys.version_info >= (3, 9) else 0.25
FAST = settings(max_examples=int(300 * SEARCH), deadline=None, suppress_health_check=list(HealthCheck))


@FAST
@given(scripts)
def test_scripts_drawn_from_the_grammar_parse(text):
    try:
        parse(text)
    except ScriptError as e:
        # Drawn text can still mean nothing (an unknown name, skin 90):
        # that is the checker's job. The grammar itself must accept it.
        syntax = [d for d in e.diagnostics if d.kind == "syntax"]
        assert not syntax, f"{text!r}: {e}"


def only_script_errors(text):
    try:
        parse(text)
    except ScriptError as e:
        assert e.diagnostics
        for d in e.diagnostics:
            assert d.message and d.line >= 0 and d.column >= 0
        e.render()  # the message itself must not fail either


@FAST
@given(st.text())
def test_arbitrary_text_raises_only_script_errors(text):
    only_script_errors(text)


fragments = st.sampled_from(
    [
        "look",
        "dynamic",
        "in",
        "1s",
        "-20",
        "{",
        "}",
        ";",
        "\n",
        "repeat",
        "3",
        "together",
        "define",
        "x",
        "x",
        "follow",
        "left",
        "arm",
        "wobble_",
        "_",
        "0.5",
        "#",
        "skin_9",
        "ease-in",
        "\t",
        "wake",
        "up",
        ".",
    ]
)


@FAST
@given(st.lists(fragments, max_size=40).map(" ".join))
def test_jumbled_language_raises_only_script_errors(text):
    only_script_errors(text)


@FAST
@given(st.binary(max_size=400))
def test_arbitrary_bytes_raise_only_script_errors(data):
    try:
        text = decode(data, "bytes")
    except ScriptError:
        return
    only_script_errors(text)


@settings(max_examples=int(150 * SEARCH), deadline=None, suppress_health_check=list(HealthCheck))
@given(st.one_of(scripts, st.lists(fragments, max_size=40).map(" ".join), st.text(max_size=200)))
def test_what_parses_compiles_samples_and_explains(text):
    # Whatever `check` accepts must compile and play: nothing but a
    # ScriptError may escape, from any step.
    try:
        script = parse(text)
        check_recordings(script)  # as `check` does: a recording it names must be there
    except ScriptError:
        return
    if measure(script.body, {})[1] > 5000:  # unrolled size, kept small for speed
        return
    if reactive(script):  # handlers, waits, signals: the live session runs them, here for 5 s
        timeline = run_over(script, seed=1, duration=5.0).timeline
        for t in (0.0, 2.5, 5.0, 6.0):
            state_record(t, timeline.sample(t), timeline.status(t))
        with pytest.raises(ScriptError):  # alone, the compiler refuses them, with a position
            compile_script(script, seed=1)
        return
    timeline = compile_script(script, seed=1)
    for t in (0.0, timeline.duration / 3, timeline.duration, timeline.duration + 1.0):
        state_record(t, timeline.sample(t), timeline.status(t))
    assert all(span.text for span in timeline.spans)
    assert timeline.frame_times(2.0)[-1] <= timeline.duration + 1e-9
