"""`--events FILE` and `--duration T` of `render`, `play` and `explain`: a script that reacts, run
by the live session over an events file (engine/session_run.py)."""

from __future__ import annotations

from typing import Any, List, Optional, Tuple

import typer

from ..core.face_constants import LIMITS
from ..language.diagnostics import ScriptError
from ..language.syntax_tree import Script
from .app import animation_for, fail, recordings_of

EVENTS_OPT = typer.Option(
    None,
    "--events",
    metavar="FILE",
    help="Events for the script's handlers, one a line: '2.5 face seen', '4 word \"hello\"'.",
)
DURATION_OPT = typer.Option(
    None,
    "--duration",
    metavar="T",
    min=0.0,
    max=LIMITS.max_seconds,
    help="Seconds to run a script that reacts (default: until it rests after the last event).",
)


def reacting_animation(
    script: Script,
    events: Optional[str],
    seed: Optional[int],
    idle: bool,
    crossfade: Optional[float],
    duration: Optional[float],
    command: str,
) -> Tuple[Any, List[Any]]:
    """The animation to show, and the session's log ([] for a script that does not react and has
    no events): the script compiled as always, or run by the session over `events`."""
    from ..engine.animation import Animation
    from ..engine.session_run import NeverRests, reactive, run_over
    from ..extras import MissingTool
    from ..language.event_trace import read_trace

    if events is None and not reactive(script):
        if duration is not None:
            raise fail(
                f"baxterface {command}: --duration is for a script that reacts (with 'on', 'forever' ...)", 2
            )
        return animation_for(script, seed, idle, crossfade), []
    try:
        trace = None if events is None else read_trace("/dev/stdin" if events == "-" else events, events)
    except ScriptError as e:
        raise fail(e.render()) from None
    try:
        run = run_over(script, trace, seed, duration, crossfade, recordings_of(script))
    except NeverRests as e:
        raise fail(f"baxterface {command}: {e}", 2) from None
    except MissingTool as e:
        raise fail(f"baxterface: {e}") from None
    except ScriptError as e:
        raise fail(e.render()) from None
    return Animation(run.timeline, idle=idle, seed=seed), run.log  # type: ignore[arg-type]


def handlers_need_events(script: Script, events: Optional[str], command: str) -> None:
    """`play` in a terminal, without --events or --listen, refuses a script with handlers: nothing
    there raises events (a window raises touch, --listen words)."""
    from ..language.syntax_tree import On

    handler = next((s for s in script.body if isinstance(s, On)), None)
    if events is None and handler is not None:
        raise fail(
            f"baxterface {command}: {script.filename}:{handler.pos.line}: the script has handlers; "
            "give --events FILE or --listen, or play it in a window",
            2,
        )
