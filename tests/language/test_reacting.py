"""Reacting in the language: `on`, `wait until`, `signal`, `forever`, `one of`, and events files.

Each mistake is named where it is written, with the message a user reads (checked exactly)."""

from __future__ import annotations

import pytest
from diagnosed import errors, warnings

from baxterface_cli import parse
from baxterface_cli.language import syntax_tree as n
from baxterface_cli.language.diagnostics import ScriptError
from baxterface_cli.language.event_trace import parse_trace
from baxterface_cli.language.events import matches


def test_a_handler_with_its_event_policy_and_cooldown():
    (on,) = parse("on face seen queue cooldown 5s {\n  happy\n  wink left\n}").body
    assert on == n.On(n.Event("face seen"), (n.Emotion("happy"), n.Wink("left")), "queue", 5.0)
    assert (on.pos.line, on.pos.column, on.event.pos.column) == (1, 1, 4)


@pytest.mark.parametrize(
    "written, event",
    [
        ("face lost", n.Event("face lost")),
        ("person near", n.Event("person near")),
        ("person gone", n.Event("person gone")),
        ("button ok", n.Event("button", "ok")),
        ("button torso_left up", n.Event("button", "torso_left up")),
        ("button wheel", n.Event("button", "wheel")),
        ("button wheel down", n.Event("button", "wheel down")),
        ("button left_cuff dash", n.Event("button", "left_cuff dash")),
        ("button right_cuff squeeze", n.Event("button", "right_cuff squeeze")),
        ("button circle", n.Event("button", "circle")),
        ('word "Hello   There"', n.Event("word", "hello there")),
        ("touch", n.Event("touch")),
        ("touch left eye", n.Event("touch", "left eye")),
        ("touch mouth", n.Event("touch", "mouth")),
        ("signal poke", n.Event("signal", "poke")),
        ("every 500ms", n.Event("every", seconds=0.5)),
        ("idle 30s", n.Event("idle", seconds=30.0)),
    ],
)
def test_every_event_reads_as_written(written, event):
    (on,) = parse(f"on {written} {{ blink }}").body
    assert on.event == event and on.policy == "drop" and on.cooldown == 0.0


def test_wait_until_signal_forever_and_one_of():
    wait, signal, forever, choice = parse(
        'wait until word "hello" timeout 5s\nsignal Poke\nforever { blink; wait 1s }\n'
        "one of {\n  nod\n  | blink; wink left\n}"
    ).body
    assert wait == n.WaitUntil(n.Event("word", "hello"), 5.0)
    assert signal == n.Signal("poke")
    assert forever == n.Forever((n.Blink(), n.Wait(1.0)))
    assert choice == n.OneOf(((n.Nod(),), (n.Blink(), n.Wink("left"))))


@pytest.mark.parametrize(
    "text, message",
    [
        ("on face sen { blink }", "t.face:1:9: error: unknown event 'face sen'; did you mean 'face seen'?"),
        ("on fase seen { blink }", "t.face:1:4: error: unknown event 'fase'; did you mean 'face'?"),
        ("on button okk { blink }", "t.face:1:11: error: unknown button 'okk'; did you mean 'ok'?"),
        ("on button dahs { blink }", "t.face:1:11: error: unknown button 'dahs'; did you mean 'dash'?"),
        (
            "on button left_cuf dash { blink }",
            "t.face:1:11: error: unknown button 'left_cuf'; did you mean 'left_cuff'?",
        ),
        (
            "on button right_cuff ok { blink }",
            "t.face:1:22: error: unknown button 'ok' on 'right_cuff'; its buttons are 'dash', 'circle' or "
            "'squeeze'",
        ),
        (
            "on button left_cuff sqeeze { blink }",
            "t.face:1:21: error: unknown button 'sqeeze' on 'left_cuff'; did you mean 'squeeze'?",
        ),
        (
            "wait until button left_cuff",
            "t.face:1:19: error: 'button left_cuff' needs one of its buttons: 'dash', 'circle' or 'squeeze'",
        ),
        (
            "on button torso_left dash { blink }",
            "t.face:1:22: error: unknown button 'dash' on 'torso_left'; its buttons are 'ok', 'up' or 'down'",
        ),
        (
            "on face seen qeue { blink }",
            "t.face:1:14: error: unknown option 'qeue' for 'on face seen'; did you mean 'queue'?",
        ),
        (
            "on touch mouht { blink }",
            "t.face:1:10: error: unknown option 'mouht' for 'on touch'; did you mean 'mouth'?",
        ),
        (
            "on face seen timeout 5s { blink }",
            "t.face:1:14: error: 'timeout' fits 'wait until', not 'on face seen'",
        ),
        ("wait until face seen queue", "t.face:1:22: error: 'queue' fits 'on', not 'wait until face seen'"),
        ("wait until every 5s", "t.face:1:12: error: 'wait until' cannot wait for 'every'; write 'wait 5s'"),
        ("on face seen drop queue { blink }", "t.face:1:19: error: 'on face seen' has its policy already"),
        ("on face seen cooldown { blink }", "t.face:1:14: error: 'cooldown' needs a time: 'cooldown 5s'"),
        ("on signal { blink }", "t.face:1:4: error: 'signal' needs a name: 'signal poke'"),
        ("on every 0s { blink }", "t.face:1:10: error: an 'every' time must be 0.1 s at least, not 0s"),
        ("on every 0.05s { blink }", "t.face:1:10: error: an 'every' time must be 0.1 s at least, not 0.05s"),
        ("on idle 0s { blink }", "t.face:1:9: error: an 'idle' time must be more than 0 s, not 0s"),
        (
            "on idle 1e9s { blink }",
            "t.face:1:10: error: unknown unit 'e9s' for an 'idle' time; an 'idle' time takes 's' or 'ms'",
        ),
        ("wait until face seen timeout -1s", "t.face:1:30: error: a timeout cannot be negative"),
        (
            "on touch left { blink }",
            "t.face:1:10: error: 'left' alone is not a place on the face; write 'touch left eye'",
        ),
        (
            'on word "hello!" { blink }',
            "t.face:1:9: error: 'word' spots a few words of letters (8 at most, 60 letters), not \"hello!\"",
        ),
        (
            "repeat 2 { on face seen { blink } }",
            "t.face:1:12: error: 'on' is only allowed at the top level of a script or of a state",
        ),
        (
            "together { wait until face seen; blink }",
            "t.face:1:12: error: 'wait until' cannot be inside 'together', whose statements run side by side",
        ),
        (
            "define hold { signal poke }\ntogether { hold; blink }",
            "t.face:2:12: error: 'hold' cannot be inside 'together': it holds a 'signal' (line 1), "
            "and the statements of a 'together' run side by side",
        ),
        (
            "forever { skin 3 }",
            "t.face:1:1: error: 'forever' would repeat without end in no time: its body needs a statement "
            "that takes time, or a 'wait until'",
        ),
        ("on face seen { }", "t.face:1:1: error: empty block: 'on' needs at least one statement"),
        ("define one { blink }", "t.face:1:1: error: 'one' is a built-in command; choose another name"),
    ],
)
def test_each_mistake_is_named_where_it_is(text, message):
    assert errors(text) == [message]


def test_what_never_runs_after_forever_and_a_second_handler_are_warned():
    assert warnings("forever { blink }\nnod") == [
        "t.face:2:1: warning: never runs: 'forever' on line 1 does not end"
    ]
    assert warnings("on face seen { blink }\non face seen queue { nod }") == [
        "t.face:2:1: warning: 'face seen' already has a handler, on line 1: "
        "this one runs only when that one is not running, by its policy"
    ]
    # handlers after a forever are installed at the start: nothing to warn of
    assert warnings("forever { blink }\non face seen { nod }") == []


def test_a_handler_counts_on_its_own_against_the_length_limit():
    assert errors("on face seen { wait 3601s }") == [
        "t.face:1:1: error: the handler runs 1 hour 1 s; the limit is 1 hour"
    ]
    parse("wait 3000s\non face seen { wait 3000s }")  # each within the hour


def test_a_script_with_more_handlers_than_a_face_keeps_is_refused_at_the_first_past_the_bound():
    # 1,000 `on every 0.1000XXs` lines passed `check` and froze the screen and the node.
    every = "\n".join(f"on every {0.1 + i / 1e6:.6f}s {{ blink }}" for i in range(20))
    assert errors(every) == ["t.face:17:1: error: more 'every' handlers than the 16 a face keeps in time"]
    signals = "\n".join(f"on signal s{i} {{ blink }}" for i in range(300))
    assert errors(signals) == ["t.face:257:1: error: more handlers than the 256 a face keeps"]
    parse("\n".join(f"on signal s{i} {{ blink }}" for i in range(256)))


def test_a_button_without_a_navigator_takes_any_navigators_and_wheel_either_turn():
    assert matches(n.Event("button", "ok"), n.Event("button", "left ok"))
    assert not matches(n.Event("button", "left ok"), n.Event("button", "right ok"))
    assert matches(n.Event("button", "wheel"), n.Event("button", "wheel up"))
    assert not matches(n.Event("button", "up"), n.Event("button", "wheel up"))
    assert matches(n.Event("button", "dash"), n.Event("button", "right_cuff dash"))
    assert not matches(n.Event("button", "left_cuff dash"), n.Event("button", "right_cuff dash"))
    assert not matches(n.Event("button", "squeeze"), n.Event("button", "left_cuff dash"))
    assert matches(n.Event("touch"), n.Event("touch", "mouth"))
    assert not matches(n.Event("touch", "mouth"), n.Event("touch", "left eye"))


def test_an_events_file_reads_one_event_a_line():
    trace = parse_trace(
        '# a visit\n\n2.5 face seen\n4 word "hello"  # said\n6 button ok\n'
        "7.2 touch left eye\n9s signal poke\n",
        "v.events",
    )
    assert [(p.at, p.event, p.line) for p in trace.events] == [
        (2.5, n.Event("face seen"), 3),
        (4.0, n.Event("word", "hello"), 4),
        (6.0, n.Event("button", "ok"), 5),
        (7.2, n.Event("touch", "left eye"), 6),
        (9.0, n.Event("signal", "poke"), 7),
    ]
    assert trace.end == 9.0


def test_an_events_file_says_every_problem_where_it_is():
    with pytest.raises(ScriptError) as caught:
        parse_trace(
            '1 face sen\nface seen\n3 every 5s\n4 face seen queue\n5 word "hi\n6x face lost\n'
            "7 face lost\n2 face seen\n9 touch nose\n8 touch\nhello\n",
            "v.events",
        )
    assert [d.head("v.events") for d in caught.value.diagnostics] == [
        "v.events:1:8: error: unknown event 'face sen'; did you mean 'face seen'?",
        "v.events:2:1: error: a line starts with the seconds its event comes at, as in '2.5 face seen'",
        "v.events:3:3: error: 'every' is the script's own clock, not an event a file can bring",
        "v.events:4:13: error: unexpected 'queue' after the event; an events file has no options",
        "v.events:5:8: error: unterminated string: it needs a closing '\"' on the same line",
        "v.events:6:1: error: unknown unit 'x' for a time; use 's' or 'ms'",
        "v.events:8:1: error: times go forward: 2 comes after 7 s",
        "v.events:9:9: error: unknown place 'nose' for a touch; it lands on 'left eye', 'right eye', 'mouth' "
        "or 'brows', or anywhere",
        # Its event was bad, its time good: the next line's time is checked against it.
        "v.events:10:1: error: times go forward: 8 comes after 9 s",
        # A line with no time and no event: the hint is a line that reads, not '2.5 hello'.
        "v.events:11:1: error: a line starts with the seconds its event comes at, as in '2.5 face seen'",
    ]


def test_an_events_file_takes_the_cuffs_and_names_a_wrong_one_where_it_is():
    trace = parse_trace("1 button left_cuff squeeze\n2 button dash\n", "c.events")
    assert [p.event for p in trace.events] == [
        n.Event("button", "left_cuff squeeze"),
        n.Event("button", "dash"),
    ]
    with pytest.raises(ScriptError) as caught:
        parse_trace("1 button left_cuff circel\n", "c.events")
    assert [d.head("c.events") for d in caught.value.diagnostics] == [
        "c.events:1:20: error: unknown button 'circel' on 'left_cuff'; did you mean 'circle'?"
    ]


@pytest.mark.parametrize(
    "written, message",
    [
        ("queue", "unexpected 'queue': a handler's policy goes before its block: on EVENT queue { ... }"),
        (
            "cooldown 2s",
            "unexpected 'cooldown': a handler's policy goes before its block: on EVENT cooldown 5s { ... }",
        ),
    ],
)
def test_a_policy_after_the_block_is_one_error_saying_where_it_goes(written, message):
    assert errors(f"on touch {{ happy }} {written}\n") == [f"t.face:1:20: error: {message}"]


def test_a_word_after_a_blocks_brace_is_one_error_not_a_made_up_one():
    assert errors("repeat 2 { blink } zzzz\nhappy\n") == [
        "t.face:1:20: error: unexpected 'zzzz'; expected ';', '}' or a new line"
    ]


def test_two_unknown_events_are_two_errors_and_no_warning_of_one_handled_twice():
    assert errors("on tuch { happy }\non fase seen { sad }\n") == [
        "t.face:1:4: error: unknown event 'tuch'; did you mean 'touch'?",
        "t.face:2:4: error: unknown event 'fase'; did you mean 'face'?",
    ]


def test_a_word_event_takes_any_of_its_phrases_and_says_them_as_written():
    script = parse('on word "Hello" | "hi  robot" { happy }\nwait until word "yes" timeout 3s')
    on, wait = script.body
    assert on.event == n.Event("word", "hello|hi robot") and wait.event.arg == "yes"
    # In a `one of`, a bar after a `wait until` is the next choice, as it always was.
    (choices,) = parse("one of { wait until signal x | nod }").body
    assert len(choices.choices) == 2
    assert matches(on.event, n.Event("word", "hi robot")) and matches(on.event, n.Event("word", "hello"))
    assert not matches(on.event, n.Event("word", "hi"))
    from baxterface_cli.language.checker import phrases_listened
    from baxterface_cli.language.events import in_words

    assert in_words(on.event) == 'word "hello" | "hi robot"'
    assert phrases_listened(script.body) == ["hello", "hi robot", "yes"]
    assert errors('on word "hello" | { nod }') == [
        "t.face:1:17: error: 'word' needs the words in double quotes: 'word \"hello\"'"
    ]
    parse("one of { nod | blink | wink left }")  # the bar is a `one of`'s too
