"""The studio's events: fired by hand (the events bar, `POST /api/event`, a tap on the preview)
at the script the editor plays, which reacts to them as `render --events` would; and presses in
the panel that react, taken as the face node takes them.

A script that reacts (a handler, a wait, a signal, `forever`, `one of`) is previewed as a live
session run over the events fired so far, each at the transport's position when it was fired.
The run is kept (event_run.py): an event fired continues it from the last one, so the 2,000th
costs what the first did. A run that would never rest by itself (a `forever`, an `idle` timer)
is shown for `WINDOW` seconds past its last event. The events belong to the session: cleared with
it, and exported beside it as the script plus its events file, which `play`, `render` and
`explain` take with `--events`.

A press in the panel that reacts: `signal NAME` is fired as the events bar fires it; a handler
(`on ... { }`) installs itself in the script the preview runs, after the editor's text (one for
an event already handled replaces it, and says so, as the node logs it), and is exported with
it, so the export plays what the preview played. Other statements that react (`wait until`,
`forever`, `one of`) would take over the run at a moment, which no script plus events file can
replay: they are refused, with the reason.
"""

from __future__ import annotations

import bisect
import threading
from pathlib import Path
from typing import Any, Dict, List, NamedTuple, Optional, Tuple

from ..core.face_constants import LIMITS
from ..core.partial_files import write_atomic
from ..engine.animation import Animation
from ..engine.session_handlers import ons_of
from ..engine.session_program import first_reacting
from ..language import syntax_tree as n
from ..language.diagnostics import Diagnostic, ScriptError
from ..language.event_trace import Posted
from ..language.events import in_words
from ..language.parser import parse
from ..language.script_length import in_words as time_in_words
from ..language.statements import describe
from .event_run import WINDOW, EventRun

__all__ = ["WINDOW", "MOST_EVENTS", "Reacting", "TooManyEvents", "listens"]

# Events a session holds. Not for time (an event fired at the end costs the same at any count):
# for memory, which the run kept for the preview takes: about 16 KB an event (docs/studio.md).
MOST_EVENTS = 10_000
PRESSED = "# pressed in the studio's panel"  # the line between the editor's text and the handlers


class TooManyEvents(Exception):
    """The session holds as many events as it takes, or the event falls past a run's limit."""


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
    preview: Any, script: n.Script, events: List[Posted]
) -> Tuple[Animation, Dict[str, Any], Optional[EventRun]]:
    """`script` played as the `preview` (preview.py's, which imports this) plays it: the live
    session's run over `events`, as `render --events` makes it, kept to be continued. And what its
    handlers did: runs, dropped and queued in all."""
    kept: Optional[EventRun] = preview.run  # the run shown: an edit goes on from where it reaches it
    if kept is not None and list(kept.events) == events and kept.seed == preview.seed:
        run = kept.edited(script)
    else:
        run = EventRun.start(script, preview.seed, preview.recordings, tuple(events))
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
    """The workspace's half that takes events (a mixin: `self.preview`, `self.lock`, `self.clock`)."""

    preview: Any  # preview.py's Preview
    lock: Any
    clock: Any
    name: str
    record: Any  # studio_log.py's StudioRecord

    def _start_reacting(self) -> None:
        # A fired event and an edit each change the run: one at a time, so neither loses the other.
        self.firing = threading.Lock()
        self.pressed: List[Pressed] = []
        self.editor: Optional[n.Script] = None  # the editor's script the preview plays, without them

    def event(self, event: n.Event, source: str = "") -> Dict[str, Any]:
        """Fire `event` (from `source`, for the session's log) at the preview's position: what the
        script's handlers did with it.
        TooManyEvents past `MOST_EVENTS`; ScriptError (or MissingTool) for a handler that cannot play."""
        with self.firing:
            with self.lock:
                preview = self.preview
                if len(preview.events) >= MOST_EVENTS:
                    raise TooManyEvents(
                        f"the session holds {MOST_EVENTS} events, the most it takes; export it and clear it"
                    )
                now = self.clock()
                t = preview.transport.position(now, preview.duration)
                script, before, run = preview.script, preview.counts, preview.run
            at = round(t, 3)
            if at > LIMITS.max_seconds:  # as an events file's, and render's run, end there
                raise TooManyEvents(
                    f"{at:g} s is past {time_in_words(LIMITS.max_seconds)}, the longest a run is"
                )
            posted = Posted(at, event, 0)
            if run is None:  # a script that reacts to nothing: kept for the export, nothing runs
                events = list(preview.events)
                events.insert(bisect.bisect_right([e.at for e in events], at), posted)
                shown, counts = preview.animation, before
            else:
                run = run.with_event(posted)
                events = list(run.events)
                shown, counts = Animation(run.timeline, preview.idle, preview.seed), run.counts
            with self.lock:
                preview.events = events
                preview.show(script, shown, counts, run)
                preview.fired(t, self.clock())
                self.record.fired(now, posted, source, shown, run)
        moved = {k: counts[k] - before[k] for k in counts}
        return {"event": in_words(event), "at": at, "events": len(events), **moved}

    def press(self, text: str) -> Dict[str, Any]:
        """A press in the panel: played in the session (`at`, its time there), or, when it reacts,
        taken by the script's run (see `react`); sent to the robot when that is on, as the node
        takes either. ScriptError if it is bad."""
        script = parse(text, "<command>")
        if first_reacting(script) is None:
            return {"at": self.command(text)}  # type: ignore[attr-defined]
        answer = self.react(script)
        self.robot.send(text)  # type: ignore[attr-defined]
        return answer

    def react(self, script: n.Script) -> Dict[str, Any]:
        """A press in the panel that reacts (see the module's docstring): what it did."""
        body = [s for s in script.body if not isinstance(s, n.Define)]
        if body and all(isinstance(s, n.Signal) for s in body):
            fired = [self.event(n.Event("signal", s.name)) for s in body]
            return {"reacting": True, "fired": fired}
        if body and all(isinstance(s, n.On) for s in body):
            return self._install(script)
        others = [s for s in body if not isinstance(s, (n.On, n.Signal))]
        taking = [s for s in others if first_reacting(n.Script((s,), "<command>", (), "")) is not None]
        if not body:  # definitions alone, which wait or choose: nothing calls them here
            message = "a definition alone does nothing in the panel: press it with the handler that calls it"
            others = list(script.body)
        elif taking:
            message = (
                f"'{describe(taking[0])}' in the panel would take over the run at this moment, which the "
                "export (the script and its events file) cannot replay: write it in the editor's script; "
                "the panel takes handlers ('on ... { }') and 'signal NAME', each as a press of its own"
            )
        else:  # a plain statement beside a handler or a signal: they go to two places
            message = (
                f"'{describe(others[0])}' beside a handler or a signal: press them one at a time (a handler "
                "goes into the script's run, a signal is fired at it, the rest plays in the session)"
            )
        where = (taking or others)[0].pos
        raise ScriptError([Diagnostic(where.line, where.column, message)], "<command>", script.source)

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
        """The slow half of showing `script`, over the session's events."""
        return animation(self.preview, script, list(self.preview.events))

    def clear_events(self) -> None:
        with self.firing:
            with self.lock:
                had = bool(self.preview.events) or bool(self.pressed)
                script = self.editor or self.preview.script
                self.preview.events, self.pressed = [], []
                self.record.cleared(self.clock())
            if had:  # show the editor's script without them
                prepared = self._replay(script)
                with self.lock:
                    self.preview.show(script, *prepared)
                    self.record.script(self.clock(), script, self.name, prepared[0], prepared[2])

    def export_events(self, target: Path) -> Dict[str, Any]:
        """The script the events were fired at (with the handlers pressed) and the events, beside
        `target` (the session's file); nothing when neither was."""
        with self.lock:
            events, source, seed = list(self.preview.events), self.preview.script.source, self.preview.seed
            pressed = len(self.pressed)
        if not events and not pressed:
            return {}
        script_path = target.with_name(target.stem + "-script.face")
        events_path = script_path.with_suffix(".events")
        header = (
            f"# baxterface studio session: {self.name} with {len(events)} event"
            + ("" if len(events) == 1 else "s")
            + f" fired by hand\n# replays exactly with: baxterface play {script_path.name} "
            f"--events {events_path.name} --seed {seed}\n"
        )
        written = events_text(events)
        write_atomic(script_path, (header + source).encode("utf-8", "surrogatepass"))
        write_atomic(events_path, written.encode("utf-8"))
        return {"script_path": script_path.name, "events_path": events_path.name, "events_text": written}
