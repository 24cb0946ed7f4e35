"""An edit of the script in the studio, over a long run of events (and commands pressed): it goes
on from the last input before the first one the edit reaches, and what it shows is what running
the edited script again over all the inputs shows (the reference: `EventRun.start`, the run from
the start)."""

from __future__ import annotations

import pytest

from baxterface_cli.language.event_line import read_event_line
from baxterface_cli.language.event_trace import Posted
from baxterface_cli.language.parser import parse
from baxterface_cli.studio.event_run import Command, EventRun
from baxterface_cli.studio.workspace import Workspace

SCRIPT = (
    "sad\n"
    "on signal poke {\n  happy\n  look left in 0.3s\n  wait 0.2s\n}\n"
    "on signal late queue {\n  angry\n  wait 0.5s\n}\n"
    "forever {\n  blink\n  wait 2s\n}\n"
)
POKES = 300  # events, 0.7 s apart: the late one comes after the 290th


def events():
    poke, late = read_event_line("signal poke"), read_event_line("signal late")
    fired = [Posted(round(0.7 * (i + 1), 3), poke, 0) for i in range(POKES)]
    fired.insert(290, Posted(round(0.7 * 290 + 0.35, 3), late, 0))
    return tuple(fired)


EDITS = {
    # The late event's handler changed, its lines kept: on from the checkpoint before it.
    "the late handler": (SCRIPT.replace("  angry\n  wait 0.5s", "  sad\n  wait 0.4s"), True),
    # A handler for an event never fired, added at the end: every checkpoint still holds.
    "a handler added": (SCRIPT + "on touch mouth {\n  wink left\n}\n", True),
    # The main script changed: from the start.
    "the main script": (SCRIPT.replace("wait 2s", "wait 1.5s"), False),
    # A line added before the handlers: every line after moved, which the timeline shows: from the start.
    "a line moved": ("# a comment\n" + SCRIPT.replace("angry", "sad"), False),
    # A handler of a signal some statement raises (its time is not an event's): from the start.
    "a raised signal's handler": (
        SCRIPT.replace("  wait 0.2s\n}", "  wait 0.2s\n  signal late\n}").replace("angry", "sad"),
        False,
    ),
}


@pytest.mark.parametrize("name", list(EDITS))
def test_an_edit_shows_what_the_edited_script_run_again_over_every_event_shows(name):
    text, goes_on = EDITS[name]
    before, after = parse(SCRIPT, "edited.face"), parse(text, "edited.face")
    run = EventRun.start(before, 7, None, events())
    edited = run.edited(after)
    again = EventRun.start(after, 7, None, events())
    assert edited.inputs == again.inputs and edited.counts == again.counts
    assert edited.timeline.duration == again.timeline.duration
    steps = int(edited.timeline.duration * 20)
    assert all(edited.timeline.sample(i / 20) == again.timeline.sample(i / 20) for i in range(steps + 1))
    assert [s.line for s in edited.timeline.spans] == [s.line for s in again.timeline.spans]
    # Gone on from a checkpoint: the timelines played before it are the ones already made.
    reused = sum(1 for (_, a), (_, b) in zip(edited.played, run.played) if a is b)
    assert (reused > 100) == goes_on, reused
    # And it goes on as the run from the start does: the next event, fired back among the others too.
    for at in (0.7 * POKES + 1.0, 100.05):
        late = Posted(at, read_event_line("signal late"), 0)
        edited, again = edited.with_input(late), again.with_input(late)
        assert edited.counts == again.counts
        assert all(edited.timeline.sample(t) == again.timeline.sample(t) for t in (at, at + 0.3, at + 1.0))


@pytest.mark.parametrize(
    "pressed, goes_on",
    [("look right in 0.3s\nhappy", True), ("angry\nsignal late", False)],  # the second raises late
)
def test_an_edit_over_commands_pressed_goes_on_as_the_script_run_again_shows(pressed, goes_on):
    """Commands pressed in the panel are the session's inputs as events are: an edit of a handler
    goes on from a checkpoint past them, unless one of them raises the edited handler's signal."""
    command = Command(50.05, parse(pressed, "panel"))
    inputs = tuple(sorted([*events(), command, command._replace(at=150.05)], key=lambda i: i.at))
    before = parse(SCRIPT, "edited.face")
    after = parse(EDITS["the late handler"][0], "edited.face")
    run = EventRun.start(before, 7, None, inputs)
    edited, again = run.edited(after), EventRun.start(after, 7, None, inputs)
    assert edited.counts == again.counts and edited.timeline.duration == again.timeline.duration
    steps = int(edited.timeline.duration * 20)
    assert all(edited.timeline.sample(i / 20) == again.timeline.sample(i / 20) for i in range(steps + 1))
    reused = sum(1 for (_, a), (_, b) in zip(edited.played, run.played) if a is b)
    assert (reused > 100) == goes_on, reused


def test_the_studio_goes_on_with_an_edit_as_the_script_run_again_shows_it(tmp_path):
    path = tmp_path / "edited.face"
    path.write_text(SCRIPT)
    workspace = Workspace(path, seed=7, idle=False, clock=lambda: 0.0)
    workspace.update(SCRIPT)
    kept = events()
    workspace.preview.inputs = kept
    workspace.update(SCRIPT + " ")  # the run over the events, as the studio keeps it
    shown_before = workspace.preview.run
    edit = EDITS["the late handler"][0]
    assert workspace.update(edit)["diagnostics"] == []
    run = workspace.preview.run
    again = EventRun.start(parse(edit, "edited.face"), 7, workspace.preview.recordings, kept)
    assert run.played[0][1] is shown_before.played[0][1]  # gone on from a checkpoint
    assert run.counts == again.counts and workspace.preview.counts == again.counts
    assert all(run.timeline.sample(i / 10) == again.timeline.sample(i / 10) for i in range(2200))
