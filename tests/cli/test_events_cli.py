"""`render`, `explain` and `play` with `--events FILE`, as a user runs them: the same script,
events and seed make the same frames, explain says which handler ran and what it dropped, and
what cannot run is refused in one line."""

from __future__ import annotations

import pytest

from baxterface_cli.core.face_state import FaceState
from baxterface_cli.engine.live_face import LiveFace
from baxterface_cli.language.diagnostics import ScriptError
from baxterface_cli.language.parser import parse
from conftest import baxterface

SCRIPT = """\
sleep
wait until button ok
wake up
on face seen { happy; one of { wink left | wink right | nod } }
on touch interrupt { look left in 0.5s; look right in 0.5s }
forever { look 20 0 in 1s; look -20 0 in 1s }
"""
EVENTS = """\
# someone comes and goes
1 button ok
2.5 face seen
2.8 face seen
3 touch mouth
"""


@pytest.fixture
def files(tmp_path):
    (tmp_path / "s.face").write_text(SCRIPT)
    (tmp_path / "s.events").write_text(EVENTS)
    return tmp_path


def test_the_same_script_events_and_seed_render_the_same_frames_to_the_bit(files):
    outs = []
    for name in ("a.gif", "b.gif"):
        args = ("render", "s.face", "--events", "s.events", "--seed", "7", "--size", "128x75", "--fps", "10")
        run = baxterface(*args, "--out", name, "-q", cwd=files)
        assert run.code == 0, run.err
        outs.append((files / name).read_bytes())
    assert outs[0] == outs[1]
    assert len(outs[0]) > 1000


def test_explain_shows_each_event_which_handler_ran_and_what_it_dropped(files):
    run = baxterface("explain", "s.face", "--events", "s.events", cwd=files)
    assert run.code == 0, run.err
    lines = run.out.splitlines()
    assert lines[0].startswith("s.face: ")
    react = [line.split(None, 3)[-1] for line in lines if " react " in line]
    assert react[:8] == [
        "event button ok (s.events:2)",
        "event face seen (s.events:3)",
        "line 4 'on face seen' runs",
        "event face seen (s.events:4)",
        "dropped face seen: line 4 'on face seen' is running",
        "event touch mouth (s.events:5)",
        "line 4 'on face seen' interrupted",
        "line 5 'on touch' runs",
    ]
    assert react[8:] == ["line 5 'on touch' ends", "main script goes on"]  # in its forever: at rest


def test_a_bad_events_file_is_told_where_like_a_script(files):
    (files / "bad.events").write_text("1 face seen\n2 fase seen\n")
    run = baxterface("render", "s.face", "--events", "bad.events", "--out", "x.gif", cwd=files)
    assert run.code == 1
    assert run.err.splitlines()[0] == "bad.events:2:3: error: unknown event 'fase'; did you mean 'face'?"
    assert not (files / "x.gif").exists()


def test_forever_without_events_needs_a_duration(files):
    (files / "f.face").write_text("forever { look left in 1s; look right in 1s }\n")
    run = baxterface("explain", "f.face", cwd=files)
    assert run.code == 2
    assert "'forever' on line 1 never ends and no events come to end it; give --duration" in run.err
    run = baxterface("explain", "f.face", "--duration", "3", cwd=files)
    assert run.code == 0 and run.out.startswith("f.face: 3.00 s"), run.err


def test_play_refuses_handlers_without_events(files):
    run = baxterface("play", "s.face", "--terminal", cwd=files)
    assert run.code == 2
    assert run.err.strip() == (
        "baxterface play: s.face:4: the script has handlers; "
        "give --events FILE or --listen, or play it in a window"
    )


def test_a_live_face_alone_refuses_a_script_that_reacts_in_one_line():
    face = LiveFace()  # its session runs handlers (engine/live_session.py); alone, it compiles as render does
    with pytest.raises(ScriptError) as caught:
        face.prepare(parse("blink\non face seen { nod }", "display_chatter"), FaceState())
    assert caught.value.summary() == (
        "display_chatter:2:1: error: 'on face seen' runs in render, play and explain (with --events FILE); "
        "a timeline compiled alone (compile_script) does not run handlers, waits, signals, "
        "'forever' or 'one of' yet"
    )
    face.begin(face.prepare(parse("blink", "display_chatter"), FaceState()), 1.0)  # and goes on


def reactions(tmp_path, script: str, events: str):
    """What `explain --events` says the handlers did, each line without its time."""
    (tmp_path / "r.face").write_text(script)
    (tmp_path / "r.events").write_text(events)
    run = baxterface("explain", "r.face", "--events", "r.events", cwd=tmp_path)
    assert run.code == 0 and "internal error" not in run.err, run.err
    return [line.split(None, 3)[-1] for line in run.out.splitlines() if " react " in line]


def test_an_interrupt_raised_by_a_running_handler_stops_it_and_runs(tmp_path):
    script = "on touch { happy; signal poke; sad }\non signal poke interrupt { bored }\n"
    said = reactions(tmp_path, script, "1 touch\n")
    assert said[0] == "main script ends"  # it has only handlers
    assert said[1:7] == [
        "event touch (r.events:1)",
        "line 1 'on touch' runs",
        "event signal poke (line 1)",
        "line 1 'on touch' interrupted",
        "line 2 'on signal poke' runs",
        "line 2 'on signal poke' ends",
    ]


@pytest.mark.parametrize("policy", ["queue", "interrupt"])
def test_handlers_that_raise_their_own_signal_in_no_time_are_stopped_and_the_script_goes_on(tmp_path, policy):
    said = reactions(tmp_path, f"on signal poke {policy} {{ signal poke }}\nsignal poke\nhappy\n", "")
    stopped = [line for line in said if "not run" in line]
    assert stopped == [
        "line 1 'on signal poke' not run: 100 handler runs began without time passing "
        "(handlers that raise each other's signals?)"
    ]
    assert said[-1] == "main script ends"  # `happy`, after the loop was stopped


def test_two_handlers_of_one_event_in_a_script_are_both_kept_the_second_by_its_policy(tmp_path):
    script = "on touch { happy }\non touch queue { sad }\non touch { bored }\nwait 3s\n"
    said = reactions(tmp_path, script, "1 touch\n")
    assert "its handler replaced" not in " ".join(said)
    assert said[:5] == [
        "event touch (r.events:1)",
        "line 1 'on touch' runs",
        "queued touch for line 2 'on touch'",
        "dropped touch for line 3 'on touch': line 1 'on touch' is running",
        "line 1 'on touch' ends",
    ]
    assert said[5] == "line 2 'on touch' runs"


def test_explain_with_events_shows_the_face_each_step_leaves_as_without(tmp_path):
    (tmp_path / "plain.face").write_text("wake up\nhappy\n")
    plain = baxterface("explain", "plain.face", cwd=tmp_path)
    woken = [line.strip() for line in plain.out.splitlines() if line.strip().startswith("0.80 s")]
    assert woken and "face  skin" in woken[0], plain.out
    (tmp_path / "r.face").write_text("wake up\nhappy\nwait 3s\non touch { sad }\n")
    (tmp_path / "r.events").write_text("1 touch\n")
    run = baxterface("explain", "r.face", "--events", "r.events", cwd=tmp_path)
    faces = [line.strip() for line in run.out.splitlines() if " face " in line]
    assert faces[0] == woken[0], run.out  # `wake up`'s face, at the very moment `happy` begins
    # `sad` ends at 1.30, then `happy` starts over and ends at 1.60: each leaves a face.
    assert [line.split(" s ")[0] for line in faces[-2:]] == ["1.30", "1.60"], run.out


def test_a_script_of_only_a_clock_handler_asks_for_a_duration_and_runs_by_it(tmp_path):
    (tmp_path / "tick.face").write_text("on every 2s { blink }\n")
    run = baxterface("explain", "tick.face", cwd=tmp_path)
    assert (run.code, run.err) == (
        2,
        "baxterface explain: 'on every 2s' on line 1 runs by the clock, and nothing else happens; "
        "give --duration\n",
    )
    run = baxterface("explain", "tick.face", "--duration", "5", cwd=tmp_path)
    assert run.code == 0, run.err
    ran = [line.split()[0] for line in run.out.splitlines() if "'on every 2s' runs" in line]
    assert ran == ["2.00", "4.00"], run.out


def test_a_run_ends_where_the_face_exits_though_events_come_after(tmp_path):
    (tmp_path / "ex.face").write_text("on touch { exit }\nforever { wait 1s }\n")
    (tmp_path / "ex.events").write_text("1 touch\n10 face seen\n")
    for more in ([], ["--duration", "20"]):
        run = baxterface("explain", "ex.face", "--events", "ex.events", *more, cwd=tmp_path)
        assert run.code == 0, run.err
        lines = run.out.splitlines()
        exits = [line.split()[0] for line in lines if line.endswith("react the face exits")]
        assert exits and lines[0] == f"ex.face: {exits[0]} s", run.out
