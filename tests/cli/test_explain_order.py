"""`explain --events` reads lines at one time in the order things happened: a handler's statement
that takes no time comes after the handler runs and before it ends, and the main script's next
one after the main script goes on."""

from __future__ import annotations

from conftest import baxterface


def at(lines, time: str):
    """The lines at `time` (as explain writes it, "2.00"), without the time."""
    return [line.split(None, 2)[2] for line in lines if line.split()[:2] == [time, "s"]]


def test_a_zero_length_last_statement_reads_before_its_handler_ends(tmp_path):
    (tmp_path / "z.face").write_text(
        "on signal poke { look left in 0s }\nwait until signal poke\nlook right in 0s\n"
    )
    (tmp_path / "z.events").write_text("2 signal poke\n")
    run = baxterface("explain", "z.face", "--events", "z.events", cwd=tmp_path)
    assert run.code == 0, run.err
    assert at(run.out.splitlines(), "2.00") == [
        "react event signal poke (z.events:1)",
        "react line 1 'on signal poke' runs",
        "line 1    look 65 0 in 0s",
        "react line 1 'on signal poke' ends",
        "react main script goes on",
        "line 3    look -65 0 in 0s",
        "react main script ends",
    ]


def test_the_face_a_handler_arrives_at_reads_before_the_handler_ends(tmp_path):
    (tmp_path / "h.face").write_text("on signal poke { happy }\n")
    (tmp_path / "h.events").write_text("2 signal poke\n")
    run = baxterface("explain", "h.face", "--events", "h.events", cwd=tmp_path)
    assert run.code == 0, run.err
    assert at(run.out.splitlines(), "2.30") == [
        "face  skin 2, mouth teeth, brows raised",
        "react line 1 'on signal poke' ends",
    ]
    grouped = baxterface("explain", "h.face", "--events", "h.events", "--grouped", cwd=tmp_path).out
    assert grouped.splitlines()[1].split()[-3:] == ["line", "1", "happy"]  # --grouped: statements first


def test_the_face_a_step_leaves_and_the_next_begins_from_is_said_once(tmp_path):
    # A newcomer saw `2.80 s face skin 3, ...` twice: once as `wake up` left it, once as `happy`
    # began from it.
    (tmp_path / "w.face").write_text("on touch { wake up; happy }\n")
    (tmp_path / "w.events").write_text("2 touch\n")
    run = baxterface("explain", "w.face", "--events", "w.events", cwd=tmp_path)
    assert run.code == 0, run.err
    faces = [line for line in at(run.out.splitlines(), "2.80") if line.startswith("face")]
    assert faces == ["face  skin 3, mouth smile, brows normal"]
