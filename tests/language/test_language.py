"""The script language: each statement, blocks, definitions, units, positions."""

from __future__ import annotations

import math
import re
import sys

import pytest

from baxterface_cli import ScriptError, parse
from baxterface_cli.core.face_constants import LIMITS
from baxterface_cli.language import syntax_tree as n
from baxterface_cli.language.checker import measure
from baxterface_cli.language.parser import grammar
from baxterface_cli.language.statements import KEYWORDS

pytestmark = pytest.mark.language


def body(text):
    return parse(text).body


def errors(text):
    with pytest.raises(ScriptError) as caught:
        parse(text, "t.face")
    return [(d.line, d.column, d.message) for d in caught.value.errors]


def test_the_users_own_example():
    assert body("happy; look 40 -20 in 0.5s; wobble 0.3") == (
        n.Emotion("happy"),
        n.Look(40, -20, n.Timing(0.5)),
        n.Wobble(0.3),
    )


def test_newlines_semicolons_comments_and_blank_lines_separate_statements():
    text = "\n# a show\n\nhappy   # grin\n;; blink\r\n\n  sad ;\n"
    assert body(text) == (n.Emotion("happy"), n.Blink(), n.Emotion("sad"))
    assert body("") == ()
    assert body("# only a comment") == ()


def test_keywords_and_names_are_case_insensitive():
    assert body("LOOK Left IN 1S Ease-In-Out") == body("look left in 1s ease-in-out")
    assert body("Mouth SMILE-OPEN; BROWS Raised") == (n.Mouth("smile-open"), n.Brows("raised"))


@pytest.mark.parametrize(
    "text, node",
    [
        ("look 40 -20", n.Look(40, -20)),
        ("look 40 -20 in 500ms", n.Look(40, -20, n.Timing(0.5))),
        ("look 40 -20 in 2", n.Look(40, -20, n.Timing(2.0))),
        ("look 10px 20px", n.Look(10, 20)),
        ("look 40 -20 in 0.5s ease-in-out", n.Look(40, -20, n.Timing(0.5, "ease-in-out"))),
        ("look 40 -20 ease-out", n.Look(40, -20, n.Timing(None, "ease-out"))),
        ("look left", n.Look(65, 0)),
        ("look right", n.Look(-65, 0)),
        ("look up", n.Look(0, -97.5)),
        ("look down in 1s", n.Look(0, 97.5, n.Timing(1.0))),
        ("look center", n.Look(0, 0)),
        ("look centre", n.Look(0, 0)),
        ("dynamic look 30 0 in 1s ease-in", n.Look(30, 0, n.Timing(1.0, "ease-in"), dynamic=True)),
        ("blink", n.Blink()),
        ("wait 2s", n.Wait(2.0)),
        ("wait 250ms", n.Wait(0.25)),
        ("wobble 0.3", n.Wobble(0.3)),
        ("wobble 0.3 in 1s ease-in-out", n.Wobble(0.3, n.Timing(1.0, "ease-in-out"))),
        ("nod", n.Nod()),
        ("enable", n.Enable()),
        ("disable", n.Disable()),
        ("exit", n.Exit()),
        ("sleep", n.Emotion("sleep")),
        ("wake up", n.Emotion("wake up")),
        ("skin 5", n.Skin(5)),
        ("mouth teeth", n.Mouth("teeth")),
        ("brows worried", n.Brows("worried")),
        ("eyelids 0.5", n.Eyelids(0.5)),
        ("eyelids 0 in 1s", n.Eyelids(0.0, n.Timing(1.0))),
        ("eyelids 25%", n.Eyelids(0.25)),
        ("follow human", n.Follow("human")),
        ("follow left arm dynamic", n.Follow("left arm", True)),
        ("follow off", n.Follow(None)),
    ],
)
def test_each_statement(text, node):
    assert body(text) == (node,)


def test_degrees_become_radians():
    (wobble,) = body("wobble 20deg")
    assert math.isclose(wobble.angle, math.radians(20))


def test_blocks_and_definitions():
    script = parse(
        """
        define greet {
            happy
            look left in 1s
        }
        repeat 3 { blink; wait 1s }
        together {
            greet
            wobble 0.3 in 1s
        }
        """
    )
    define, repeat, together = script.body
    assert define == n.Define("greet", (n.Emotion("happy"), n.Look(65, 0, n.Timing(1.0))))
    assert repeat == n.Repeat(3, (n.Blink(), n.Wait(1.0)))
    assert together == n.Together((n.Call("greet"), n.Wobble(0.3, n.Timing(1.0))))
    assert script.definitions == {"greet": define}


def test_a_definition_may_be_used_before_it_is_written():
    assert body("dance\ndefine dance { happy }")[0] == n.Call("dance")


def test_positions_are_line_and_column_from_one():
    script = parse("happy\n  repeat 2 {\n    look 1 2\n  }")
    happy, repeat = script.body
    assert (happy.pos.line, happy.pos.column) == (1, 1)
    assert (repeat.pos.line, repeat.pos.column) == (2, 3)
    (look,) = repeat.body
    assert (look.pos.line, look.pos.column) == (3, 5)


def test_positions_do_not_take_part_in_equality():
    assert body("look 1 2") == body("\n\n      look 1 2")


def test_eye_targets_outside_the_ellipse_warn_but_parse():
    script = parse("look 200 0\nlook 0 -120\nlook left")
    (warning,) = script.warnings
    assert warning.severity == "warning"
    assert (warning.line, warning.column) == (1, 1)
    assert "clamped to (80, 0)" in warning.message


def test_a_head_angle_beyond_the_limit_warns():
    (warning,) = parse("wobble_2.0").warnings
    assert "clamped" in warning.message


@pytest.mark.parametrize(
    "text, where, message",
    [
        ("hapy", (1, 1), "unknown command 'hapy'; did you mean 'happy'?"),
        ("mouth smil", (1, 7), "unknown mouth 'smil'; did you mean 'smile'?"),
        ("brows rasied", (1, 7), "did you mean 'raised'?"),
        ("look nowhere", (1, 6), "unknown direction 'nowhere'"),
        ("look 1 2 in 1s bouncy", (1, 16), "unknown easing 'bouncy'"),
        ("wait 2sec", (1, 7), "unknown unit 'sec' for a wait; a wait takes 's' or 'ms'"),
        ("wait 2secs", (1, 7), "unknown unit 'secs'"),
        ("wait 2mss", (1, 7), "did you mean 'ms'?"),
        ("wobble 20grad", (1, 10), "unknown unit 'grad' for a head angle"),
        ("skin 6", (1, 6), "a skin must be a whole number from 0 to 5, not 6"),
        ("skin 2.5", (1, 6), "a skin must be a whole number from 0 to 5"),
        ("skin_-1", (1, 6), "a skin must be a whole number from 0 to 5, not -1"),
        ("eyelids 1.5", (1, 9), "eyelid openness must be from 0 (closed) to 1 (open)"),
        ("wait -1s", (1, 6), "a wait cannot be negative"),
        ("look 1 2 in -1s", (1, 13), "a duration cannot be negative"),
        ("repeat 0 { blink }", (1, 8), "a repeat count must be a whole number from 1 to 10000"),
        ("repeat 10001 { blink }", (1, 8), "from 1 to 10000"),
        ("repeat 3 { }", (1, 1), "empty block: 'repeat' needs at least one statement"),
        ("together {\n}", (1, 1), "empty block: 'together'"),
        ("define d {}\nd", (1, 1), "empty block: 'define'"),
        ("look_a_b", (1, 1), "'look_a_b' is not a valid legacy command; write look_X_Y or look_X_Y_SECONDS"),
        ("look_nan_0", (1, 1), "not a valid legacy command"),
        ("wobble_x", (1, 1), "write wobble_RADIANS"),
        ("look_1", (1, 1), "'look_1' takes 2 or 3 numbers"),
        ("look_1_2_3_4", (1, 1), "takes 2 or 3 numbers"),
        ("define happy { blink }", (1, 1), "'happy' is a built-in command"),
        ("define d { blink }\ndefine d { nod }\nd", (2, 1), "'d' is already defined on line 1"),
        ("repeat 2 { define d { blink } }", (1, 12), "only allowed at the top level"),
        ("define a { b }\ndefine b { a }\na", (1, 1), "'a' calls itself (a -> b -> a)"),
        ("define a { repeat 2 { a } }\na", (1, 1), "'a' calls itself (a -> a)"),
        ("wait 3601s", (1, 1), "the script runs 1 hour 1 s; the limit is 1 hour"),
        ("repeat 10000 { repeat 10000 { skin 1 } }", (1, 1), "unrolls to 100000000 steps"),
        ("look 1e400 0", (1, 7), "unknown unit 'e400' for an eye coordinate"),
        ("look 1" + "0" * 400 + " 0", (1, 6), "an eye coordinate is too large"),
    ],
)
def test_errors_say_what_and_where(text, where, message):
    found = errors(text)
    assert found, text
    line, column, said = found[0]
    assert (line, column) == where, said
    assert message in said


def test_every_error_is_reported_not_only_the_first():
    found = errors("hapy\nmouth smil\nskin 9\nwait 1parsec")
    assert [f[0] for f in found] == [1, 2, 3, 4]


def test_an_unknown_command_is_reported_beside_a_syntax_error_on_its_line():
    found = errors("happy\nblinkk left\nrepeat 2 { hapy 3 }")
    assert found == [
        (2, 1, "unknown command 'blinkk'; did you mean 'blink'?"),
        (2, 8, "unexpected 'left'; expected ';', 'in', 'variant', '}', a new line or a number"),
        (3, 12, "unknown command 'hapy'; did you mean 'happy'?"),
    ]
    # A known word stays quiet: only what is really wrong is said.
    assert errors("define wave { blink }\nwave left; happy 3") == [
        (2, 6, "unexpected 'left'; expected ';', 'in', 'variant', '}', a new line or a number"),
        (2, 18, "an intensity must be from 0 to 1, not 3"),
    ]


def test_repeat_and_define_limits_follow_through_definitions():
    # 100 x 100 x 100 one-second waits: an hour is passed only once unrolled.
    text = "define a { wait 1s }\ndefine b { repeat 100 { a } }\nrepeat 100 { repeat 100 { b } }"
    assert "the limit is 1 hour" in errors(text)[0][2]
    seconds, steps = measure(parse("repeat 3 { blink; wait 1s }").body, {})
    assert math.isclose(seconds, 3 * 1.5) and steps == 6


def test_the_longest_together_child_sets_its_length():
    seconds, _ = measure(parse("together { wait 2s; look 1 1 in 0.5s }").body, {})
    assert seconds == 2.0


def test_a_long_chain_of_definitions_does_not_exhaust_the_checkers_stack():
    # Checked without recursion; refused because compiling it would recurse.
    chain = "\n".join(f"define d{i} {{ d{i + 1} }}" for i in range(3000))
    (found,) = errors(chain + "\ndefine d3000 { blink }\nd0")
    assert found[:2] == (3002, 1) and "nest 3001 levels deep" in found[2]


def test_nesting_is_bounded():
    deep = "together {" * (LIMITS.max_depth + 1) + "blink" + "}" * (LIMITS.max_depth + 1)
    assert "nest too deeply" in errors(deep)[0][2]
    fine = "together {" * LIMITS.max_depth + "blink" + "}" * LIMITS.max_depth
    parse(fine)


def test_keyword_list_matches_the_grammar():
    statement_starters = set()
    for terminal in grammar().terminals:
        value = getattr(terminal.pattern, "value", "")
        if re.fullmatch(r"[a-z]+", value):
            statement_starters.add(value)
    contextual = {"in", "up", "arm", "human", "face", "off", "left", "right", "voice", "rate"}
    contextual |= {"file", "text", "language"}  # say's, for a recording
    assert statement_starters - contextual == set(KEYWORDS)


def test_an_unclosed_brace_does_not_hide_the_other_errors():
    text = "repeat 3 {\n  blink\n  mouth smil\nhapy\ntogether {\n  look lft\n"
    assert errors(text) == [
        (1, 10, "this '{' is never closed"),
        (3, 9, "unknown mouth 'smil'; did you mean 'smile'?"),
        (4, 1, "unknown command 'hapy'; did you mean 'happy'?"),
        (5, 10, "this '{' is never closed"),
        (6, 8, "unknown direction 'lft'; did you mean 'left'?"),
    ]


def test_an_unclosed_brace_keeps_later_positions_and_line_numbers():
    text = "repeat 2 {\n  blink\ndefine a { happy }\ndefine a { sad }\na"
    assert errors(text) == [
        (1, 10, "this '{' is never closed"),
        (4, 1, "'a' is already defined on line 3"),
    ]


UNIT_HINT = "write the unit straight after the number, as in"


@pytest.mark.parametrize(
    "text, where, message",
    [
        ("look left in 0.5 s", (1, 18), f"unknown easing 's' in '0.5 s': {UNIT_HINT} '0.5s'"),
        ("wobble 20 deg", (1, 11), f"unknown easing 'deg' in '20 deg': {UNIT_HINT} '20deg'"),
        ("wait 1 ms", (1, 8), f"unexpected 'ms' in '1 ms': {UNIT_HINT} '1ms'"),
        ("eyelids 50 %", (1, 12), f"unexpected '%' in '50 %': {UNIT_HINT} '50%'"),
        ("look 40 px -20", (1, 9), f"unexpected 'px' in '40 px': {UNIT_HINT} '40px'"),
    ],
)
def test_a_unit_apart_from_its_number_is_explained(text, where, message):
    assert [(line, column, m) for line, column, m in errors(text) if "unit" in m] == [(*where, message)]


def test_a_misspelt_direction_keeps_its_own_suggestion_beside_the_unit_hint():
    assert errors("look lft in 0.5 s") == [
        (1, 6, "unknown direction 'lft'; did you mean 'left'?"),
        (1, 17, f"unknown easing 's' in '0.5 s': {UNIT_HINT} '0.5s'"),
    ]


def warnings(text):
    return [(d.line, d.column, d.message) for d in parse(text).warnings]


@pytest.mark.parametrize(
    "text, where, exit_line",
    [
        ("happy\nexit\nblink\nsad", (3, 1), 2),
        ("repeat 2 { happy; exit; sad }", (1, 25), 1),
        ("together { exit; nod }", (1, 18), 1),
        ("together { blink; repeat 3 { exit } }\nhappy", (2, 1), 1),
        ("define bye { sad\n exit }\nbye\nblink", (4, 1), 2),
    ],
)
def test_what_follows_exit_is_warned_about(text, where, exit_line):
    assert warnings(text) == [(*where, f"never runs: 'exit' on line {exit_line} ends the script")]


def test_the_warned_statement_is_really_dropped():
    from baxterface_cli.engine.compiler import compile_script

    script = parse("happy\nexit\nblink")
    assert [s.line for s in compile_script(script).spans] == [1, 2]
    assert warnings("happy\nexit") == [] and warnings("define d { exit }\nblink\nd") == []


def definition_chain(count):
    """`define d0 { blink }`, each next one calling the last, then a call of the last."""
    lines = ["define d0 { blink }"] + [f"define d{i} {{ d{i - 1} }}" for i in range(1, count)]
    return "\n".join(lines + [f"d{count - 1}"])


def togethers(depth, inner):
    return "together { " * depth + inner + " }" * depth


def stack_depth():
    frame, depth = sys._getframe(), 0
    while frame is not None:
        frame, depth = frame.f_back, depth + 1
    return depth


def test_a_script_nested_to_the_limit_compiles_in_a_third_of_the_default_stack():
    from baxterface_cli.engine.compiler import compile_script

    # `b` nests 1 + 31 blocks + 1 + 31 blocks = 64 levels, most of them
    # `together`, which costs the compiler the most frames a level.
    text = f"define a {{ {togethers(31, 'blink')} }}\ndefine b {{ {togethers(31, 'a')} }}\nb"
    assert LIMITS.max_nesting == 64
    script = parse(text)
    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(stack_depth() + 1000 // 3)
    try:
        timeline = compile_script(script)
    finally:
        sys.setrecursionlimit(limit)
    assert timeline.duration > 0
    assert "nest 65 levels deep" in errors(text[:-1] + "together { b }")[0][2]


@pytest.mark.parametrize(
    "text, where, depth",
    [
        (definition_chain(65), (66, 1), 65),
        (definition_chain(331), (332, 1), 331),
        (definition_chain(500), (501, 1), 500),
        (
            "\n".join(
                [f"define t0 {{ {togethers(31, 'blink')} }}"]
                + [f"define t{i} {{ {togethers(31, f't{i - 1}')} }}" for i in range(1, 9)]
                + ["t8"]
            ),
            (10, 1),
            288,
        ),
    ],
)
def test_nesting_through_definitions_is_bounded(text, where, depth):
    message = (
        f"blocks and calls nest {depth} levels deep here, counting each call into a definition; "
        "the limit is 64 levels"
    )
    assert errors(text) == [(*where, message)]


def test_the_size_limit_counts_utf8_bytes_not_characters():
    emoji = "\N{GRINNING FACE}" * (LIMITS.max_bytes // 4 + 1)
    found = errors(emoji)
    assert found == [(0, 0, f"script is too large ({len(emoji) * 4} bytes; the limit is {LIMITS.max_bytes})")]
    parse("# " + "\N{GRINNING FACE}" * (LIMITS.max_bytes // 4 - 3) + "\nhappy")


def test_a_flood_of_errors_keeps_the_first_and_counts_the_rest():
    with pytest.raises(ScriptError) as caught:
        parse("a\n" * 1000 + "hapy\n", "display_chatter")
    e = caught.value
    assert len(e.diagnostics) == LIMITS.max_shown and e.more_errors == 1001 - LIMITS.max_shown
    assert e.render().splitlines()[-1] == "display_chatter: ... and 951 more errors"
    assert e.summary() == "display_chatter:1:1: error: unknown command 'a' (and 1000 more problems)"


def test_errors_are_kept_before_warnings():
    with pytest.raises(ScriptError) as caught:
        parse("look 500 0 in 0s\n" * 100 + "hapy\n")
    e = caught.value
    assert e.errors[0].message.startswith("unknown command 'hapy'")
    assert (len(e.diagnostics), e.more_errors, e.more_warnings) == (50, 0, 51)
    script = parse("look 500 0 in 0s\n" * 60)
    assert (len(script.warnings), script.more_warnings) == (50, 10)


def test_follow_face_is_a_statement_and_face_stays_a_name_elsewhere():
    assert parse("follow face").body == (n.Follow("face"),)
    assert parse("follow face dynamic; face_follow_off").body == (n.Follow("face", True), n.Follow(None))
    assert parse("dynamic_face_follow_on").body == (n.Follow("face", True),)
    assert parse("define face { blink }; face").body == (n.Define("face", (n.Blink(),)), n.Call("face"))


def test_a_huge_unknown_word_is_shown_cut_short():
    with pytest.raises(ScriptError) as e:
        parse("x" * 100_000)
    message = e.value.diagnostics[0].message
    assert message == "unknown command '" + "x" * 40 + "...'"
