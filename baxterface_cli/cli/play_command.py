"""`baxterface play`: a script in real time, in a window or this terminal."""

from __future__ import annotations

import os
import sys
from typing import List, Optional

import typer

from ..language.diagnostics import ScriptError
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
    check_recordings,
    fail,
    fitted_theme,
    following_from,
    load_script,
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
    session_animation,
)
from .finite_numbers import finite
from .log_option import LOG_OPT, LOG_SIZE_OPT, log_file, logged_seed


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
    from ..drawing.renderer import Renderer
    from ..engine.session_run import reactive
    from ..play.player import Player, TerminalScreen, WindowScreen, window_available
    from ..speech.warm_start import start_in_background

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
    if watch and log is not None:
        raise fail("baxterface play: --log keeps a live session's record, which --watch is not", 2)
    seed = logged_seed(log, seed)
    logged = log_file(log, log_size, "play", seed=seed, events=events, duration=duration)
    if listen or (window and reactive(script)) or logged is not None:
        from .play_live import play_live

        given = events if heard is None else heard
        play_live(
            script, given, window, fps, size, seed, theme, idle, crossfade, duration, listen, barge_in, logged
        )
        return
    handlers_need_events(script, events or hear, "play")
    if not window and not sys.stdout.isatty():
        raise fail(
            "baxterface play: no display and no terminal to play in; "
            "use 'baxterface render SCRIPT --out show.gif' to make a file instead"
        )
    start_in_background()  # the speech process starts as the theme is fitted: no `say` waits for it
    renderer = Renderer(fitted_theme(theme, size, "play"))
    animation, _ = session_animation(script, events, seed, idle, crossfade, duration, "play", hear, heard)
    held: List[str] = []  # a terminal's face would cover the line; it is said when the face is gone

    def say(line: str) -> None:
        if window:
            typer.echo(line, err=True)
        else:
            held.append(line)

    def open_sound():  # only once a script that speaks starts: the others never touch the device
        from ..speech.sound_device import open_sound as open_device

        return open_device(lambda message: say(f"baxterface play: {message}"))

    follow = following_from(follow_from, animation, "play", say, face_policy)
    screen = WindowScreen() if window else TerminalScreen()
    player = Player(animation, renderer, screen, fps, sound=open_sound, follow=follow)
    poll = _watcher(script_path, seed, idle, crossfade, player) if watch else None
    interrupted = False
    try:
        player.run(loop=loop, hold=watch, poll=poll)
    except KeyboardInterrupt:
        interrupted = True
    finally:
        screen.close()
        if player.sound is not None:
            player.sound.close()
        for line in held:
            typer.echo(line, err=True)
    shown = f"{player.frames_shown} frames ({screen.name})"
    length = player.animation.duration
    if interrupted:  # the shell's convention: 128 + SIGINT
        where = f"{player.position:.2f} s of {length:.2f} s of script"
        typer.echo(f"interrupted at {where}, after {player.elapsed():.2f} s: {shown}", err=True)
        raise typer.Exit(130)
    typer.echo(f"played {length:.2f} s of script in {player.elapsed():.2f} s: {shown}", err=True)


def _watcher(path: str, seed: Optional[int], idle: bool, crossfade: Optional[float], player):
    """A poll function: a new animation when the file changed and parses, else None."""
    state = {"mtime": os.stat(path).st_mtime_ns}

    def poll():
        try:
            mtime = os.stat(path).st_mtime_ns
        except OSError:
            return None
        if mtime == state["mtime"]:
            return None
        state["mtime"] = mtime
        try:
            script = load_script(path)
            check_recordings(script)
        except ScriptError as e:
            first = e.diagnostics[0]
            player.note = f"kept the last good version: line {first.line}: {first.message}"
            return None
        player.note = ""
        return session_animation(script, None, seed, idle, crossfade, None, "play")[0]

    return poll
