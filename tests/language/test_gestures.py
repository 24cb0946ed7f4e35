"""The face's gestures (data/gestures.face), which every script may call, and `use`."""

from __future__ import annotations

import os

import numpy as np
import pytest

from baxterface_cli import parse
from baxterface_cli.language.diagnostics import ScriptError
from baxterface_cli.language.parser import gestures, parse_file
from conftest import baxterface

pytestmark = pytest.mark.language

ASKED = {"laugh", "giggle", "shake", "agree", "disagree", "surprise", "think", "yawn", "shrug", "greet"}
ASKED |= {"goodbye", "puzzled", "listen"}


def errors(text: str, folder=None) -> list:
    with pytest.raises(ScriptError) as raised:
        parse(text, "t.face", folder)
    return [d.message for d in raised.value.diagnostics]


def test_the_library_has_each_gesture_asked_for_each_short_and_said_in_words():
    found = gestures()
    assert set(found) >= ASKED and "nod" not in found  # `nod` is the robot's head nod, a statement
    for gesture in found.values():
        assert 0.5 < gesture.seconds < 3.0 and gesture.about, gesture.name


def test_a_script_calls_a_gesture_without_defining_it_and_its_own_define_comes_first():
    script = parse("laugh; blink", "t.face")
    assert [d.name for d in script.definitions.values()] == ["laugh"]
    assert script.definitions["laugh"] is gestures()["laugh"].define
    own = parse("define laugh { blink }\nlaugh", "t.face")
    assert own.definitions["laugh"].body == parse("blink").body
    # A gesture that calls another brings it too; nothing uncalled is borrowed.
    assert set(parse("disagree").definitions) == {"disagree", "shake"}
    assert parse("blink").definitions == {}


def test_check_offers_a_gesture_for_a_misspelled_word_and_nothing_for_a_word_near_nothing():
    assert errors("lagh") == ["unknown command 'lagh'; did you mean 'laugh'?"]
    assert errors("zzqxw") == ["unknown command 'zzqxw'"]


def test_each_gesture_compiles_renders_moves_the_face_and_ends_at_rest():
    from baxterface_cli.drawing.renderer import Renderer
    from baxterface_cli.drawing.theme import Theme
    from baxterface_cli.engine.compiler import compile_script

    renderer = Renderer(Theme.default().layers((256, 150)))
    rest_state = compile_script(parse("default; wait 3s"), seed=0).sample(2.9)
    rest = renderer.render(rest_state).copy()
    for name, gesture in gestures().items():
        timeline = compile_script(parse(name), seed=0)
        assert timeline.duration == pytest.approx(gesture.seconds, abs=0.05), name
        moved = [not np.array_equal(renderer.render(timeline.sample(t)), rest) for t in (0.3, 0.6, 0.9)]
        assert any(moved), name
        assert timeline.sample(timeline.duration + 1).expression == rest_state.expression, name


def test_the_live_session_runs_a_gesture_sent_as_a_command():
    from baxterface_cli.engine.live_session import LiveSession

    session = LiveSession(idle=False, now=0.0)
    before = session.face.state(0.5)
    session.run(parse("surprise", "<command>"), 1.0)
    assert session.face.state(1.5).expression != before.expression
    assert session.face.state(4.0).expression == before.expression


def test_use_brings_another_files_defines_relative_to_the_script(tmp_path):
    (tmp_path / "lib").mkdir()
    lib = tmp_path / "lib"
    (lib / "mine.face").write_text('use "more.face"\ndefine hop { blink; skip }\n', encoding="utf-8")
    (lib / "more.face").write_text("define skip { wink left }\ndefine jump { nod }\n", encoding="utf-8")
    script = tmp_path / "show.face"
    script.write_text('use "lib/mine.face"\nhop; laugh\n', encoding="utf-8")
    assert set(parse_file(script).definitions) == {"hop", "skip", "laugh"}
    # A used file's own `use`s serve its definitions (what they call comes along), no more.
    assert "unknown command 'jump'" in errors('use "lib/mine.face"\njump', tmp_path)[0]
    # The script's own define of a used name comes first.
    script.write_text('use "lib/mine.face"\ndefine hop { nod }\nhop\n', encoding="utf-8")
    assert parse_file(script).definitions["hop"].body == parse("nod").body


def test_use_is_refused_out_of_the_folder_in_a_circle_missing_broken_nested_or_with_no_folder(tmp_path):
    inside = tmp_path / "in"
    inside.mkdir()
    (tmp_path / "out.face").write_text("define hop { blink }\n", encoding="utf-8")
    os.symlink(tmp_path / "out.face", inside / "link.face")
    (inside / "a.face").write_text('use "b.face"\n', encoding="utf-8")
    (inside / "b.face").write_text('use "a.face"\n', encoding="utf-8")
    (inside / "bad.face").write_text("define hop { lagh }\n", encoding="utf-8")
    root = os.path.realpath(inside)
    assert errors('use "../out.face"', inside) == [
        f"cannot use '../out.face': it is outside {root}, the folder of the script"
    ]
    assert errors('use "link.face"', inside)[0].startswith("cannot use 'link.face': it is outside")
    assert errors(f'use "{tmp_path / "out.face"}"', inside)[0].endswith("not an absolute one")
    assert errors('use "a.face"', inside) == [
        "cannot use 'a.face': it has errors: a.face:1:1: cannot use 'b.face': it has errors: b.face:1:1: "
        "cannot use 'a.face': it uses this file again (a.face -> b.face -> a.face); 'use' cannot go round"
    ]
    assert errors('use "none.face"', inside) == [f"cannot use 'none.face': there is no such file in {root}"]
    assert errors('use "bad.face"', inside) == [
        "cannot use 'bad.face': it has errors: bad.face:1:14: unknown command 'lagh'; did you mean 'laugh'?"
    ]
    nested = errors('repeat 2 { use "b.face" }', inside)
    assert nested[0] == "'use' is only allowed at the top level of a script"
    assert errors('use "b.face"') == ["cannot use 'b.face': this script has no folder to read files from"]


def test_check_reports_a_use_error_on_one_line_where_the_use_is(tmp_path):
    (tmp_path / "show.face").write_text('blink\nuse "../x.face"\n', encoding="utf-8")
    run = baxterface("check", "show.face", cwd=tmp_path)
    first = run.err.splitlines()[0]
    assert run.code == 1 and first.startswith("show.face:2:1: error: cannot use '../x.face'")


def test_baxterface_gestures_lists_each_with_its_length_and_words_and_prints_one():
    run = baxterface("gestures")
    assert run.code == 0
    lines = run.out.splitlines()
    assert [line.split()[0] for line in lines] == list(gestures())
    assert lines[0].split()[1:3] == [f"{gestures()['laugh'].seconds:.1f}", "s"]
    one = baxterface("gestures", "shake")
    assert one.code == 0 and "define shake {" in one.out and parse(one.out).definitions
    unknown = baxterface("gestures", "nope")
    assert unknown.code == 1 and "no gesture 'nope'" in unknown.err
