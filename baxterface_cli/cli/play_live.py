"""`baxterface play` live: a script that reacts, on a live session, with a window's clicks, a
microphone's words (`--listen`) and an events file's lines (play/live_player.py)."""

from __future__ import annotations

import contextlib
import sys
from typing import Any, List, Optional

import typer

from ..language import syntax_tree as n
from ..language.diagnostics import ScriptError
from .app import fail, fitted_theme, recordings_of
from .events_option import phrases_wanted
from .log_option import LogFile, open_log


def play_live(
    script: n.Script,
    events: Any,  # a path, or the events already read (a Trace: `play --hear`)
    window: bool,
    fps: float,
    size: Optional[str],
    seed: Optional[int],
    theme: Optional[str],
    idle: bool,
    crossfade: Optional[float],
    duration: Optional[float],
    listen: bool,
    barge_in: bool,
    logged: Optional[LogFile] = None,
) -> None:
    from ..drawing.renderer import Renderer
    from ..engine.live_session import LiveSession
    from ..extras import MissingTool
    from ..language.event_trace import read_trace
    from ..play.live_player import LivePlayer
    from ..play.player import TerminalScreen, WindowScreen
    from ..speech.warm_start import start_in_background

    words = phrases_wanted(script, "play", "--listen") if listen else []
    try:
        trace = events
        if isinstance(events, str):
            trace = read_trace("/dev/stdin" if events == "-" else events, events)
    except ScriptError as e:
        raise fail(e.render()) from None
    start_in_background()  # the speech process starts as the theme is fitted: no `say` waits for it
    renderer = Renderer(fitted_theme(theme, size, "play"))
    held: List[str] = []

    def say(line: str) -> None:
        if window:
            typer.echo(line, err=True)
        else:
            held.append(line)

    def open_sound():
        from ..speech.sound_device import open_sound as open_device

        return open_device(lambda message: say(f"baxterface play: {message}"))

    with contextlib.ExitStack() as stack:
        record = open_log(logged, 0.0, say)  # on the player's clock: the show starts at 0
        players: List[Any] = []
        if record is not None:  # the shutdown's record, at where the show came to
            stack.callback(lambda: record.close(players[0].position if players else 0.0))
        try:
            session = LiveSession(
                None,
                seed=seed,
                idle=idle,
                recordings=recordings_of(script),
                crossfade=crossfade,
                keep_up=True,
            )
            if record is not None:  # the script as it starts, and what its first step says
                record.watch(session.face)
                record.script(0.0, script.source, script.filename)
            session.run(script, 0.0)
        except MissingTool as e:
            raise fail(f"baxterface: {e}") from None
        except ScriptError as e:
            raise fail(e.render()) from None
        if not window and not sys.stdout.isatty():
            raise fail(
                "baxterface play: no display and no terminal to play in; "
                "use 'baxterface render SCRIPT --events FILE --out show.gif' to make a file instead"
            )
        screen = WindowScreen() if window else TerminalScreen()
        stack.callback(screen.close)
        player = LivePlayer(session, renderer, screen, fps, trace, duration, sound=open_sound, record=record)
        players.append(player)
        if listen:
            _listen(stack, player, words, barge_in)
        interrupted = False
        try:
            player.run()
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
    shown = f"{player.frames_shown} frames ({screen.name})"
    if interrupted:
        typer.echo(f"interrupted after {player.position:.2f} s: {shown}", err=True)
        raise typer.Exit(130)
    typer.echo(f"played {player.position:.2f} s live: {shown}", err=True)


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
