"""The studio's events: fired by hand (the events bar, `POST /api/event`) at the script the editor
plays, which reacts to them as `render --events` would.

A script that reacts (a handler, a wait, a signal, `forever`, `one of`) is previewed as a live
session run over the events fired so far (engine/session_run.py), each at the transport's position
when it was fired; firing one runs the script again with it, and the preview plays on from there.
A run that would never rest by itself (a `forever`, an `idle` timer) is shown for `WINDOW` seconds
past its last event. The events belong to the session: cleared with it, and exported beside it as
the script plus its events file, which `play`, `render` and `explain` take with `--events`.
"""

from __future__ import annotations

import bisect
import threading
from pathlib import Path
from typing import Any, Dict, List, Tuple

from ..core.partial_files import write_atomic
from ..engine.animation import Animation
from ..engine.session_run import NeverRests, reactive, run_over
from ..language import syntax_tree as n
from ..language.event_trace import Posted, Trace
from ..language.events import in_words

WINDOW = 30.0  # seconds a run that never rests is shown past its last event
MOST_EVENTS = 200  # events a session holds: each one fired runs the script again over all of them


class TooManyEvents(Exception):
    """The session holds as many events as it takes."""


def listens(script: n.Script) -> List[str]:
    """The events the script's handlers wait for, as the events bar offers them."""
    found = [in_words(s.event) for s in script.body if isinstance(s, n.On)]
    return sorted(set(found), key=found.index)


def animation(preview: Any, script: n.Script, events: List[Posted]) -> Tuple[Animation, Dict[str, Any]]:
    """`script` played as the `preview` (preview.py's, which imports this) plays it: over `events`
    when it reacts. And what its handlers did: runs, dropped and queued in all (zeros for a script
    that does not react)."""
    if not reactive(script):
        return preview.compiled(script), {"runs": 0, "dropped": 0, "queued": 0}
    trace = Trace(tuple(events), "events")
    try:
        run = run_over(script, trace, preview.seed, recordings=preview.recordings)
    except NeverRests:
        run = run_over(script, trace, preview.seed, trace.end + WINDOW, recordings=preview.recordings)
    counts = run.session.counts().values()
    totals = {key: sum(c[key] for c in counts) for key in ("runs", "dropped", "queued")}
    return Animation(run.timeline, preview.idle, preview.seed), totals


def events_text(events: List[Posted]) -> str:
    return "".join(f"{e.at:.3f}".rstrip("0").rstrip(".") + f" {in_words(e.event)}\n" for e in events)


class Reacting:
    """The workspace's half that takes events (a mixin: `self.preview`, `self.lock`, `self.clock`)."""

    preview: Any  # preview.py's Preview
    lock: Any
    clock: Any
    name: str

    def _start_reacting(self) -> None:
        # A fired event and an edit each run the script again: one at a time, so neither loses the other.
        self.firing = threading.Lock()

    def event(self, event: n.Event) -> Dict[str, Any]:
        """Fire `event` at the preview's position: what the script's handlers did with it.
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
                script, before = preview.script, preview.counts
            events, at = list(preview.events), round(t, 3)
            # After any fired at the same time or before (a seek back fires between them).
            events.insert(bisect.bisect_right([e.at for e in events], at), Posted(at, event, 0))
            shown, counts = animation(preview, script, events)
            with self.lock:
                preview.events = events
                preview.show(script, shown, counts)
                preview.fired(t, self.clock())
        moved = {k: counts[k] - before[k] for k in counts}
        return {"event": in_words(event), "at": round(t, 3), "events": len(events), **moved}

    def _replay(self, script: n.Script) -> Tuple[Animation, Dict[str, Any]]:
        """The slow half of showing `script`, over the session's events."""
        return animation(self.preview, script, list(self.preview.events))

    def clear_events(self) -> None:
        with self.firing:
            with self.lock:
                had, script = bool(self.preview.events), self.preview.script
                self.preview.events = []
            if had:  # show the script without them
                shown, counts = self._replay(script)
                with self.lock:
                    self.preview.show(script, shown, counts)

    def export_events(self, target: Path) -> Dict[str, Any]:
        """The script the events were fired at and the events, beside `target` (the session's file);
        nothing when no event was fired."""
        with self.lock:
            events, source, seed = list(self.preview.events), self.preview.script.source, self.preview.seed
        if not events:
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
