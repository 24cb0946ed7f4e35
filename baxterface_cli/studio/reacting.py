"""What comes to the studio's one live session (event_run.py): events fired by hand (the events
bar, `POST /api/event`, a tap on the preview) and presses in the panel, each at the preview's
position, on the run of the editor's script, as the face node takes events and commands.

A script (reacting or not) is previewed as a live session run over what came to it so far. The
run is kept (event_run.py): an input continues it from the last one, so the 10,000th costs what
the first did. A run that would never rest by itself (a `forever`, an `idle` timer) is shown for
`WINDOW` seconds past its last input. What came belongs to the session: cleared with it, and
exported with it as a log that `render` and `explain` replay (studio_log.py).

A press in the panel is taken as the node takes a command: `signal NAME` is fired as the events
bar fires it; a handler (`on ... { }`) installs itself in the script the preview runs, after the
editor's text (one for an event already handled replaces it, and says so, as the node logs it);
anything else is a command, a new main script that takes over at the preview's position from
the face as it is there (`Command`), whatever it says: moves, `wait until`, `forever`, `one of`.
A handler beside other statements is refused: the run is made again from the start at an edit,
and keeps handlers only as part of the script.
"""

from __future__ import annotations

import threading
from pathlib import Path
from typing import Any, Callable, Dict, List, NamedTuple, Optional, Tuple

from ..core.face_constants import LIMITS
from ..core.partial_files import write_atomic
from ..engine.animation import Animation
from ..engine.session_handlers import ons_of
from ..language import syntax_tree as n
from ..language.diagnostics import Diagnostic, ScriptError
from ..language.event_trace import Posted
from ..language.events import in_words
from ..language.parser import parse
from ..language.script_length import in_words as time_in_words
from ..language.statements import describe
from ..speech.recordings import RecordingError
from .event_run import WINDOW, Command, EventRun, Input

__all__ = ["WINDOW", "MOST_EVENTS", "Reacting", "TooManyEvents", "listens"]

# Events and presses a session holds. Not for time (one at the end costs the same at any count):
# for memory, which the run kept for the preview takes: about 16 KB an input (docs/studio.md).
MOST_EVENTS = 10_000
PRESSED = "# pressed in the studio's panel"  # the line between the editor's text and the handlers


class TooManyEvents(Exception):
    """The session holds as many inputs as it takes, or the input falls past a run's limit."""


class Pressed(NamedTuple):
    """Handlers pressed in the panel: their text, and the events they are for."""

    text: str
    keys: Tuple[Tuple[str, str, float], ...]


def _key(event: n.Event) -> Tuple[str, str, float]:
    return (event.kind, event.arg, event.seconds)  # as the live session tells one handler's event


def listens(script: n.Script) -> List[str]:
    """The events the script's handlers wait for (its states' too), as the events bar offers them."""
    found = [in_words(on.event) for on, _ in ons_of(script)]
    return sorted(set(found), key=found.index)


def animation(
    preview: Any, script: n.Script, inputs: Tuple[Input, ...]
) -> Tuple[Animation, Dict[str, Any], Optional[EventRun]]:
    """`script` played as the `preview` (preview.py's, which imports this) plays it: the live
    session's run over `inputs`, as `render` makes it of the session's log, kept to be continued.
    And what its handlers did: runs, dropped and queued in all."""
    kept: Optional[EventRun] = preview.run  # the run shown: an edit goes on from where it reaches it
    if kept is not None and kept.inputs == inputs and kept.seed == preview.seed:
        run = kept.edited(script)
    else:
        run = EventRun.start(script, preview.seed, preview.recordings, inputs)
    return Animation(run.timeline, preview.idle, preview.seed), run.counts, run  # type: ignore[arg-type]


def with_pressed(script: n.Script, pressed: List[Pressed]) -> n.Script:
    """The editor's `script` with the handlers pressed in the panel after it (ScriptError if they
    no longer fit it: a call of a definition it dropped)."""
    if not pressed:
        return script
    text = (
        script.source.rstrip("\n") + f"\n\n{PRESSED}\n" + "".join(p.text.strip("\n") + "\n" for p in pressed)
    )
    try:
        return parse(text, script.filename)
    except ScriptError as e:  # its lines are not the editor's: said without a place there
        why = "a handler pressed in the panel does not fit the script: {}; Clear drops what was pressed"
        errors = [d._replace(line=0, column=0, message=why.format(d.message)) for d in e.errors]
        raise ScriptError(errors, script.filename) from None


def events_text(events: List[Posted]) -> str:
    return "".join(f"{e.at:.3f}".rstrip("0").rstrip(".") + f" {in_words(e.event)}\n" for e in events)


class Reacting:
    """The workspace's half that takes events and presses (a mixin: `self.preview`, `self.lock`,
    `self.clock`)."""

    preview: Any  # preview.py's Preview
    lock: Any
    clock: Any
    name: str
    record: Any  # studio_log.py's StudioRecord
    robot: Any  # robot_switch.py's RobotSwitch

    def _start_reacting(self) -> None:
        # A fired event, a press and an edit each change the run: one at a time, so none loses another.
        self.firing = threading.Lock()
        self.pressed: List[Pressed] = []
        self.editor: Optional[n.Script] = None  # the editor's script the preview plays, without them

    def event(self, event: n.Event, source: str = "") -> Dict[str, Any]:
        """Fire `event` (from `source`, for the session's log) at the preview's position: what the
        script's handlers did with it.
        TooManyEvents past `MOST_EVENTS`; ScriptError (or MissingTool) for a handler that cannot play."""
        at, moved = self._take(lambda at: Posted(at, event, 0), source)
        with self.lock:
            fired = len(self.preview.inputs) - self.preview.commands
        return {"event": in_words(event), "at": at, "events": fired, **moved}

    def _command(self, script: n.Script) -> float:
        """A command pressed: it takes over the session at the preview's position, as a command sent
        to the face node takes over from the face as it is; its time on the run. ScriptError (or
        MissingTool) if it cannot play."""
        return self._take(lambda at: Command(at, script), "panel")[0]

    def _take(self, made: Callable[[float], Input], source: str) -> Tuple[float, Dict[str, int]]:
        """The input `made` at the preview's position, taken by the session's run, which the preview
        plays on from there: its time, and what the handlers did."""
        with self.firing:
            with self.lock:
                preview = self.preview
                if len(preview.inputs) >= MOST_EVENTS:
                    raise TooManyEvents(
                        f"the session holds {MOST_EVENTS} events and presses, the most it takes; export "
                        "it and clear it"
                    )
                now = self.clock()
                t = preview.position(now)
                script, before, run = preview.script, preview.counts, preview.run
            at = round(t, 3)
            if at > LIMITS.max_seconds:  # as an events file's, and render's run, end there
                raise TooManyEvents(
                    f"{at:g} s is past {time_in_words(LIMITS.max_seconds)}, the longest a run is"
                )
            item = made(at)
            if run is None:  # the editor's script never played: the session starts with the empty one
                run = EventRun.start(script, preview.seed, preview.recordings, (item,))
            else:
                run = run.with_input(item)
            shown, counts = Animation(run.timeline, preview.idle, preview.seed), run.counts
            with self.lock:
                preview.inputs = run.inputs
                preview.commands += isinstance(item, Command)
                preview.show(script, shown, counts, run)
                preview.took(t, self.clock(), live=isinstance(item, Command))
                self.record.took(now, item, source, shown, run)
        return at, {k: counts[k] - before.get(k, 0) for k in counts}

    def press(self, text: str) -> Dict[str, Any]:
        """A press in the panel, as the face node takes a command (see the module's docstring); sent
        to the robot when that is on. ScriptError if it is bad."""
        script = parse(text, "panel")
        body = [s for s in script.body if not isinstance(s, n.Define)]
        if body and all(isinstance(s, n.Signal) for s in body):
            answer: Dict[str, Any] = {
                "reacting": True,
                "fired": [self.event(n.Event("signal", s.name), "panel") for s in body],
            }
        elif body and all(isinstance(s, n.On) for s in body):
            answer = self._install(script)
        else:
            self._refuse(script, body)
            try:
                answer = {"at": self._command(script)}
            except RecordingError as e:  # a press that says a recording it cannot
                raise ScriptError([e.diagnostic()], script.filename, script.source) from None
        self.robot.send(text)
        return answer

    @staticmethod
    def _refuse(script: n.Script, body: List[Any]) -> None:
        """ScriptError for a press the session cannot take as a command: definitions alone, or a
        handler beside other statements (it would be installed at a moment, which the run, made
        again from the start at each edit, does not keep)."""
        handlers = [s for s in body if isinstance(s, n.On)]
        if body and not handlers:
            return
        if not body:
            message = "a definition alone does nothing in the panel: press it with what calls it"
            where = script.body[0].pos
        else:
            message = (
                f"'{describe(handlers[0])}' beside other statements: press a handler alone (it goes into "
                "the script's run from its start), and the rest as a press of its own"
            )
            where = handlers[0].pos
        raise ScriptError([Diagnostic(where.line, where.column, message)], script.filename, script.source)

    def _install(self, script: n.Script) -> Dict[str, Any]:
        """Handlers pressed: in the script the preview runs from now on, replacing any for their events."""
        keys = tuple(_key(s.event) for s in script.body if isinstance(s, n.On))
        with self.firing:
            with self.lock:
                editor, shown = self.editor, self.preview.script
            if editor is None:
                raise ScriptError(
                    [Diagnostic(0, 0, "the editor's script does not play yet: fix it first")], "<command>"
                )
            handled = {_key(s.event) for s in shown.body if isinstance(s, n.On)}
            # A press all of whose handlers are replaced is dropped; the script's own stay in its
            # text, before the new one, which the run installs after them (the last one wins).
            pressed = [p for p in self.pressed if not set(p.keys) <= set(keys)]
            pressed.append(Pressed(script.source, keys))
            combined = with_pressed(editor, pressed)
            prepared = self.preview.prepare(combined)
            with self.lock:
                self.pressed = pressed
                self.preview.show(combined, *prepared)
                self.record.script(self.clock(), combined, "panel", prepared[0], prepared[2])
        installed = [in_words(s.event) for s in script.body if isinstance(s, n.On)]
        replaced = [f"{in_words(s.event)}: its handler replaced" for s in script.body
                    if isinstance(s, n.On) and _key(s.event) in handled]  # fmt: skip
        return {"reacting": True, "installed": installed, "replaced": replaced}

    def _replay(self, script: n.Script) -> Tuple[Animation, Dict[str, Any], Optional[EventRun]]:
        """The slow half of showing `script`, over the session's inputs."""
        return animation(self.preview, script, self.preview.inputs)

    def clear_events(self) -> None:
        """The session's events, commands and pressed handlers let go: the editor's script alone."""
        with self.firing:
            with self.lock:
                had = bool(self.preview.inputs) or bool(self.pressed)
                script = self.editor or self.preview.script
                self.preview.inputs, self.preview.commands, self.pressed = (), 0, []
                self.record.cleared(self.clock())
            if had:  # show the editor's script without them
                prepared = self._replay(script)
                with self.lock:
                    self.preview.show(script, *prepared)
                    self.record.script(self.clock(), script, self.name, prepared[0], prepared[2])

    def export_events(self, target: Path) -> Dict[str, Any]:
        """The script the events were fired at (with the handlers pressed) and the events, beside
        `target` (the session's file), for `play --events`; nothing when neither was, or when a
        command was pressed, which no events file holds (the session's file replays it)."""
        with self.lock:
            inputs, source, seed = self.preview.inputs, self.preview.script.source, self.preview.seed
            pressed, commands = len(self.pressed), self.preview.commands
        if (not inputs and not pressed) or commands:
            return {}
        events: List[Posted] = list(inputs)  # type: ignore[arg-type]
        script_path = target.with_name(target.stem + "-script.face")
        events_path = script_path.with_suffix(".events")
        header = (
            f"# baxterface studio session: {self.name} with {len(events)} event"
            + ("" if len(events) == 1 else "s")
            + f" fired by hand\n# replays exactly with: baxterface render {script_path.name} "
            f"--events {events_path.name} --seed {seed} --out {script_path.stem}.mp4\n"
        )
        written = events_text(events)
        write_atomic(script_path, (header + source).encode("utf-8", "surrogatepass"))
        write_atomic(events_path, written.encode("utf-8"))
        return {"script_path": script_path.name, "events_path": events_path.name, "events_text": written}
