"""`baxterface play`: a script in real time, in a window or this terminal.

Every script plays on a live session (play/live_player.py), with a window's clicks, a
microphone's words (`--listen`) and an events file's lines; `--loop` and `--watch` start a fresh
session of the script, `--follow-from` stands in for the robot's sensors and `--log` keeps the
session's record."""

from __future__ import annotations

import contextlib
import os
import sys
from typing import Any, Callable, List, NamedTuple, Optional

import typer

from ..language import syntax_tree as n
from ..language.checker import walk
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
    recordings_of,
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
    phrases_wanted,
)
from .finite_numbers import finite
from .log_option import LOG_OPT, LOG_SIZE_OPT, LogFile, log_file, logged_seed, open_log


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
    if watch and (hear is not None or listen):  # they hear the phrases of the version they began with
        raise fail("baxterface play: --watch goes without --hear and --listen", 2)
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
    _play(
        script,
        events if heard is None else heard,
        Showing(window, fps, size, theme, follow_from, face_policy),
        Running(seed, idle, crossfade, duration, loop, script_path if watch else None),
        Live(listen, barge_in, window and reactive(script), logged),
    )


class Showing(NamedTuple):
    """Where and how the face is shown."""

    window: bool
    fps: float
    size: Optional[str]
    theme: Optional[str]
    follow_from: Optional[str]
    face_policy: Optional[str]


class Running(NamedTuple):
    """How the session runs, and starts again: `--loop`, and the file `--watch` reloads."""

    seed: Optional[int]
    idle: bool
    crossfade: Optional[float]
    duration: Optional[float]
    loop: bool
    watched: Optional[str]


class Live(NamedTuple):
    """What may come at any time: the microphone's words, a window's clicks; and the record."""

    listen: bool
    barge_in: bool
    clicked: bool  # a script that reacts, in a window: it plays until the window closes
    logged: Optional[LogFile]


def holds(script: n.Script, *kinds: type) -> bool:
    """Does `script` hold a statement of `kinds`, in its body, handlers, states or definitions?
    (`play` knows before it starts whether to open the sound, or warn that nothing follows.)"""
    bodies = [script.body] + [d.body for d in script.definitions.values()]
    return any(isinstance(s, kinds) for body in bodies for s in walk(body))


def _play(script: n.Script, events: Any, shown: Showing, running: Running, live: Live) -> None:
    """Play `script` over `events` (a path, or a Trace already read: `play --hear`) until it ends,
    the window closes, --duration passes, the face exits or Ctrl-C; then say how far it got."""
    from ..drawing.renderer import Renderer
    from ..engine.live_session import LiveSession
    from ..extras import MissingTool
    from ..language.event_trace import read_trace
    from ..play.live_player import LivePlayer
    from ..play.screens import TerminalScreen, WindowScreen
    from ..speech.warm_start import start_in_background

    words = phrases_wanted(script, "play", "--listen") if live.listen else []
    try:
        trace = events
        if isinstance(events, str):
            trace = read_trace("/dev/stdin" if events == "-" else events, events)
    except ScriptError as e:
        raise fail(e.render()) from None
    if not shown.window and not sys.stdout.isatty():
        render = "baxterface render SCRIPT" + (" --events FILE" if trace is not None else "")
        raise fail(
            "baxterface play: no display and no terminal to play in; "
            f"use '{render} --out show.gif' to make a file instead"
        )
    start_in_background()  # the speech process starts as the theme is fitted: no `say` waits for it
    renderer = Renderer(fitted_theme(shown.theme, shown.size, "play"))
    held: List[str] = []  # a terminal's face would cover the line; it is said when the face is gone

    def say(line: str) -> None:
        if shown.window:
            typer.echo(line, err=True)
        else:
            held.append(line)

    def open_sound():  # only for a script that speaks: the others never touch the device
        from ..speech.sound_device import open_sound as open_device

        return open_device(lambda message: say(f"baxterface play: {message}"))

    scripts = [script]  # the one playing: the last good version, with --watch

    def session_of(played: n.Script) -> LiveSession:
        session = LiveSession(
            None,
            seed=running.seed,
            idle=running.idle,
            recordings=recordings_of(played),
            crossfade=running.crossfade,
            keep_up=True,
        )
        if record is not None:  # the script as it starts, and what its first step says
            record.watch(session.face)
            record.script(0.0, played.source, played.filename)
        session.run(played, 0.0)
        return session

    follow = following_from(shown.follow_from, holds(script, n.Follow), "play", say, shown.face_policy)
    with contextlib.ExitStack() as stack:
        record = open_log(live.logged, 0.0, say)  # on the player's clock: the show starts at 0
        players: List[Any] = []
        if record is not None:  # the shutdown's record, at where the show came to
            stack.callback(lambda: record.close(players[0].position if players else 0.0))
        try:
            session = session_of(script)
        except MissingTool as e:
            raise fail(f"baxterface: {e}") from None
        except ScriptError as e:
            raise fail(e.render()) from None
        screen = WindowScreen() if shown.window else TerminalScreen()
        stack.callback(screen.close)
        player = LivePlayer(
            session,
            renderer,
            screen,
            shown.fps,
            trace,
            running.duration,
            sound=open_sound,
            record=record,
            follow=follow,
            live=live.listen or live.clicked,
            speaks=holds(script, n.Say, n.Ask),
            fresh=lambda: session_of(scripts[-1]),
        )
        players.append(player)
        if live.listen:
            _listen(stack, player, words, live.barge_in)
        poll = None
        if running.watched is not None:

            def reloaded(fresh: n.Script) -> LiveSession:
                scripts.append(fresh)
                return session_of(fresh)

            poll = _watcher(running.watched, player, reloaded)
        interrupted = False
        try:
            player.run(loop=running.loop, hold=poll is not None, poll=poll)
        except KeyboardInterrupt:
            interrupted = True
        except (ScriptError, MissingTool) as e:  # found only in saying it: a text espeak-ng crashed on
            stack.close()
            raise fail(e.render() if isinstance(e, ScriptError) else f"baxterface: {e}") from None
        finally:
            if player.sound is not None:
                player.sound.close()
    for line in held:
        typer.echo(line, err=True)
    shown_frames = f"{player.frames_shown} frames ({screen.name})"
    length = player.length()
    if interrupted:  # the shell's convention: 128 + SIGINT
        where = f"{player.position:.2f} s of {length:.2f} s of script"
        typer.echo(f"interrupted at {where}, after {player.elapsed():.2f} s: {shown_frames}", err=True)
        raise typer.Exit(130)
    typer.echo(f"played {length:.2f} s of script in {player.elapsed():.2f} s: {shown_frames}", err=True)


def _watcher(path: str, player, started: Callable[[n.Script], Any]):
    """A poll function: a session of the file's script when the file changed and the script in
    it is good, else None; the player's note says what was wrong with one that is not."""
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
        return started(script)

    return poll


def _listen(stack: contextlib.ExitStack, player, words: List[str], barge_in: bool) -> None:
    """The microphone, its words heard by a spotter and posted to the player; a one-line exit if
    either is missing."""
    from ..extras import MissingTool
    from ..speech.listening import listener
    from ..speech.sound_device import Microphone, MicrophoneError
    from ..speech.word_spotter import WordError

    try:
        spotter = listener(
            words,
            player.hear,
            clock=player.now,
            speaking=player.speaking,
            barge_in=barge_in,
            on_heard=player.hear_said,
            saying=player.saying,
        )
    except (MissingTool, WordError) as e:
        raise fail(f"baxterface play: --listen: {e}", 2) from None
    stack.callback(spotter.close)
    try:
        stack.enter_context(Microphone(spotter.feed))
    except MicrophoneError as e:
        raise fail(f"baxterface play: --listen: {e}") from None
