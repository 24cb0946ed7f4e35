"""States in the language: `state NAME { ... }` at the top level, `go NAME`, `go back`; each
mistake named where it is written, with the message a user reads."""

from __future__ import annotations

from diagnosed import errors, warnings

from baxterface_cli import parse
from baxterface_cli.language import syntax_tree as n

GREETER = """\
state asleep {
    sleep
    on button wheel { go awake }
}
state awake {
    wake up; happy
    on touch { say "Hello" }
}
on signal back { go back }
go asleep
"""


def test_a_state_holds_its_body_and_its_own_handlers_and_go_names_it():
    script = parse(GREETER, "t.face")
    asleep, awake = script.states["asleep"], script.states["awake"]
    assert isinstance(asleep.body[1], n.On) and asleep.body[1].event == n.Event("button", "wheel")
    assert isinstance(awake.body[-1], n.On) and awake.body[-1].event == n.Event("touch")
    assert script.body[-1] == n.Go("asleep")
    assert warnings(GREETER) == []


def test_each_mistake_with_states_is_named_where_it_is():
    assert errors("state awake { go asleep }\nstate asleep { go awake }\ngo awak") == [
        "t.face:3:1: error: unknown state 'awak'; did you mean 'awake'?"
    ]
    assert errors("state a { happy }\nstate a { sad }\ngo a") == [
        "t.face:2:1: error: state 'a' is already defined on line 1"
    ]
    assert errors("repeat 2 { state b { nod } }") == [
        "t.face:1:12: error: 'state' is only allowed at the top level of a script"
    ]
    assert errors("state a { happy }\ntogether { go a; nod }") == [
        "t.face:2:12: error: 'go' cannot be inside 'together', whose statements run side by side"
    ]
    assert errors("go back") == [
        "t.face:1:1: error: 'go back' returns to the state the face came from, and this script has none"
    ]
    assert errors("state back { nod }\ngo back")[0].startswith(
        "t.face:1:1: error: a state cannot be called 'back'"
    )
    assert errors("state a { repeat 2 { on touch { nod } } }\ngo a") == [
        "t.face:1:22: error: 'on' is only allowed at the top level of a script or of a state"
    ]


def test_a_state_no_go_reaches_is_warned_and_a_state_is_no_part_of_the_main_scripts_length():
    assert warnings("state lonely { happy }\nnod") == [
        "t.face:1:1: warning: state 'lonely' is never entered: no 'go lonely' in the script"
    ]
    parse("state long { wait 3000s }\nwait 3000s\ngo long")  # each within the hour
