"""`--events FILE`, `--hear FILE.wav` and `--duration T` of `render`, `play` and `explain`: a script
that reacts, run by the live session over an events file and the words heard in a recording
(engine/session_run.py)."""

from __future__ import annotations

import os
import re
from typing import Any, Callable, List, Optional, Tuple, TypeVar

import typer

from ..core.face_constants import LIMITS
from ..language.diagnostics import ScriptError
from ..language.syntax_tree import Script
from .app import fail, recordings_of
from .finite_numbers import finite

T = TypeVar("T")

EVENTS_OPT = typer.Option(
    None,
    "--events",
    metavar="FILE",
    help="Events for the script's handlers, one a line: '2.5 face seen', '4 word \"hello\"'.",
)
HEAR_OPT = typer.Option(
    None,
    "--hear",
    metavar="FILE.wav[@T]",
    help="A recording, starting T seconds in (FILE.wav@8s; 0 by default): the script's 'word' phrases "
    "heard in it are events at the times they end, each utterance a 'heard' event (with the [hear] "
    "extra); render mixes it into the sound.",
)
PLACED = re.compile(r"(?P<path>.+)@(?P<start>[0-9]+(?:\.[0-9]+)?)s?")
LISTEN_OPT = typer.Option(
    False, "--listen", help="Hear the script's 'on word' phrases from this machine's microphone."
)
BARGE_IN_OPT = typer.Option(
    False, "--barge-in", help="With --listen: hear words while the face speaks (it may hear itself)."
)
DURATION_OPT = typer.Option(
    None,
    "--duration",
    metavar="T",
    min=0.0,
    max=LIMITS.max_seconds,
    callback=finite,
    help="Seconds to run the script (default: until it rests after its end and the last event).",
)


def session_animation(
    script: Script,
    events: Optional[str],
    seed: Optional[int],
    idle: bool,
    crossfade: Optional[float],
    duration: Optional[float],
    command: str,
    hear: Optional[str] = None,
    heard: Any = None,
) -> Tuple[Any, List[Any]]:
    """The animation to show, and the session's log: the script run by the live session, as every
    live end runs it, over `events` and the words heard in `hear` (or over `heard`, the two already
    read by `events_trace`), with no events if neither is given."""
    from ..engine.animation import Animation
    from ..engine.session_run import run_over

    trace = heard if heard is not None else events_trace(script, events, hear, command)
    run = ran(command, lambda: run_over(script, trace, seed, duration, crossfade, recordings_of(script)))
    return Animation(run.timeline, idle=idle, seed=seed), run.log  # type: ignore[arg-type]


def ran(command: str, run: Callable[[], T]) -> T:
    """`run()`, a recorded run of a session: each way it fails is one line naming `command`."""
    from ..engine.session_run import NeverRests
    from ..extras import MissingTool

    try:
        return run()
    except NeverRests as e:
        raise fail(f"baxterface {command}: {e}", 2) from None
    except MissingTool as e:
        raise fail(f"baxterface: {e}") from None
    except ScriptError as e:
        raise fail(e.render()) from None


def events_trace(script: Script, events: Optional[str], hear: Optional[str], command: str) -> Any:
    """The events of `events` (a file, or "-": stdin) and the phrases heard in the recording `hear`,
    in time order (None for neither); a one-line exit for a bad file, a missing extra, or a script
    that waits for no words."""
    from ..language.event_trace import Posted, Trace, read_trace

    try:
        trace = None if events is None else read_trace("/dev/stdin" if events == "-" else events, events)
    except ScriptError as e:
        raise fail(e.render()) from None
    if hear is None:
        return trace
    heard = [Posted(at, event, 0, f"heard in {hear}") for at, event in heard_words(script, hear, command)]
    posted = sorted(list(trace.events if trace is not None else ()) + heard, key=lambda p: p.at)
    return Trace(tuple(posted), trace.filename if trace is not None else hear)


def heard_words(script: Script, path: str, command: str) -> List[Tuple[float, Any]]:
    """(when it ended, a `word` event) for each of the script's phrases heard in the recording at
    `path` (any sound file `say file` takes), and a `heard` event for each whole utterance where the
    listener tells them (in time order: an utterance's words before it)."""
    from ..extras import MissingTool
    from ..language.events import MOST_HEARD
    from ..language.syntax_tree import Event
    from ..speech.audio_files import AudioError

    words = phrases_wanted(script, command, "--hear")
    path, start = placed(path, command)
    try:
        from ..speech.listening import spot_file
        from ..speech.word_spotter import WordError

        heard = spot_file(path, words)
    except MissingTool as e:
        raise fail(f"baxterface {command}: --hear: {e}") from None
    except WordError as e:
        raise fail(f"baxterface {command}: --hear: {e}", 2) from None
    except AudioError as e:
        raise fail(f"baxterface {command}: --hear: {path}: {e}") from None
    found = [(start + h.at, Event("word", h.word)) for h in heard.words]
    found += [(start + s.at, Event("heard", s.text[:MOST_HEARD])) for s in heard.said]
    return sorted(found, key=lambda pair: pair[0])


def placed(hear: str, command: str) -> Tuple[str, float]:
    """The recording `--hear` names and when it starts: `FILE.wav@8s` (or `@8`) 8 seconds into the
    script, a bare `FILE.wav` at its start (a file whose own name ends so is taken whole)."""
    found = PLACED.fullmatch(hear)
    if found is None or os.path.exists(hear):
        return hear, 0.0
    start = float(found.group("start"))
    if start > LIMITS.max_seconds:
        raise fail(f"baxterface {command}: --hear: {hear}: starts past the one-hour limit", 2)
    return found.group("path"), start


def visitor_sound(hear: Optional[str], command: str) -> List[Tuple[float, Any, int]]:
    """The recording of `--hear`, to mix into a rendered sound: [(when it starts, int16 samples, their
    rate)], [] without one."""
    from ..speech.audio_files import AudioError, read_sound

    if hear is None:
        return []
    path, start = placed(hear, command)
    try:
        sound = read_sound(path)
    except AudioError as e:
        raise fail(f"baxterface {command}: --hear: {path}: {e}") from None
    return [(start, sound.samples, sound.rate)]


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


def phrases_wanted(script: Script, command: str, option: str) -> List[str]:
    """The phrases `script` listens for, or an exit 2: `option` (--listen, --hear) hears only those."""
    from ..language.checker import phrases_listened

    words = phrases_listened(script.body)
    if not words:
        wanted = "'on word \"hello\" { ... }'"
        raise fail(f"baxterface {command}: {option}: the script listens for no words ({wanted})", 2)
    return words
