"""`baxterface play` run: every script on a live session (play/live_player.py), in a window or the
terminal, with a window's clicks, a microphone's words (`--listen`) and an events file's lines;
`--loop` and `--watch` start a fresh session of the script, `--follow-from` stands in for the
robot's sensors and `--log` keeps the session's record."""

from __future__ import annotations

import contextlib
import os
import sys
from typing import Any, Callable, List, NamedTuple, Optional

import typer

from ..language import syntax_tree as n
from ..language.checker import walk
from ..language.diagnostics import ScriptError
from .app import check_recordings, fail, fitted_theme, following_from, load_script, recordings_of
from .events_option import phrases_wanted
from .log_option import LogFile, open_log


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


def play_live(script: n.Script, events: Any, shown: Showing, running: Running, live: Live) -> None:
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
