"""`baxterface play`: a script in real time, in a window or this terminal."""

from __future__ import annotations

from typing import Optional

import typer

from .app import (
    CROSSFADE_OPT,
    FACE_POLICY_OPT,
    FOLLOW_FROM_OPT,
    FPS_HELP,
    IDLE_ON_OPT,
    INLINE_OPT,
    RANDOM_SEED_OPT,
    SIZE_OPT,
    THEME_OPT,
    fail,
    script_from,
)
from .events_option import (
    BARGE_IN_OPT,
    DURATION_OPT,
    EVENTS_OPT,
    HEAR_OPT,
    LISTEN_OPT,
    events_trace,
    handlers_need_events,
)
from .finite_numbers import finite
from .log_option import LOG_OPT, LOG_SIZE_OPT, log_file, logged_seed
from .play_live import Live, Running, Showing, play_live


def play(
    script_path: Optional[str] = typer.Argument(
        None, metavar="SCRIPT", help="Script file ('-' reads standard input)."
    ),
    inline: Optional[str] = INLINE_OPT,
    loop: bool = typer.Option(False, "--loop", help="Start again at the end, until interrupted."),
    watch: bool = typer.Option(
        False, "--watch", help="Reload SCRIPT when it changes; keep the last good version on errors."
    ),
    window: Optional[bool] = typer.Option(
        None, "--window/--terminal", help="Where to play (default: a window if there is a display)."
    ),
    fps: float = typer.Option(30.0, "--fps", min=1.0, max=120.0, callback=finite, help=FPS_HELP),
    size: Optional[str] = SIZE_OPT,
    seed: Optional[int] = RANDOM_SEED_OPT,
    theme: Optional[str] = THEME_OPT,
    idle: bool = IDLE_ON_OPT,
    crossfade: Optional[float] = CROSSFADE_OPT,
    follow_from: Optional[str] = FOLLOW_FROM_OPT,
    face_policy: Optional[str] = FACE_POLICY_OPT,
    events: Optional[str] = EVENTS_OPT,
    hear: Optional[str] = HEAR_OPT,
    duration: Optional[float] = DURATION_OPT,
    listen: bool = LISTEN_OPT,
    barge_in: bool = BARGE_IN_OPT,
    log: Optional[str] = LOG_OPT,
    log_size: float = LOG_SIZE_OPT,
) -> None:
    """Play a script in real time: in a window, or in this terminal.

    The status line shows what only the robot could: head pan, enable,
    following. A script that says something speaks through this machine's
    sound device, in step with the picture. A script that follows someone
    follows them in FILE with --follow-from. A script with handlers meets the events of
    --events FILE at their times, and the words it waits for heard in --hear FILE.wav; in a
    window, and with --listen, it runs live: a click on the
    face is a `touch` (with its place), a phrase heard from the microphone a `word`, until the
    window closes, --duration passes or the face exits; --log FILE keeps its record. Ctrl-C stops.
    """
    from ..engine.session_run import reactive
    from ..play.screens import window_available

    if watch and (script_path in (None, "-") or inline is not None):
        raise fail("baxterface play: --watch needs a SCRIPT file", 2)
    script = script_from(script_path, inline, "play")
    if watch and (events is not None or hear is not None or reactive(script) or listen):
        raise fail("baxterface play: --watch plays scripts that do not react, for now", 2)
    if barge_in and not listen:
        raise fail("baxterface play: --barge-in goes with --listen", 2)
    # the words heard first: a recording it cannot read is the error, wherever it would play
    heard = None if hear is None else events_trace(script, events, hear, "play")
    why_not = window_available()
    if window is None:
        window = why_not is None
    if window and why_not:
        raise fail(f"baxterface play: cannot open a window: {why_not}")
    if (watch or loop) and log is not None:
        again = "--watch" if watch else "--loop"
        raise fail(f"baxterface play: --log keeps one live session's record, and {again} starts new ones", 2)
    if not (window or listen):
        handlers_need_events(script, events or hear, "play")
    seed = logged_seed(log, seed)
    logged = log_file(log, log_size, "play", seed=seed, events=events, duration=duration)
    play_live(
        script,
        events if heard is None else heard,
        Showing(window, fps, size, theme, follow_from, face_policy),
        Running(seed, idle, crossfade, duration, loop, script_path if watch else None),
        Live(listen, barge_in, window and reactive(script), logged),
    )
