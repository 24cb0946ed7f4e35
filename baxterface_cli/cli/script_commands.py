"""Commands on a script file: `check`, `explain` and `render`."""

from __future__ import annotations

import errno
import json
import sys
from typing import TYPE_CHECKING, List, Optional, Sequence

import typer

from ..extras import MissingTool
from ..language.diagnostics import ScriptError
from ..language.syntax_tree import to_json
from .app import (
    CROSSFADE_OPT,
    DEFAULT_SEED,
    FACE_POLICY_OPT,
    FOLLOW_FROM_OPT,
    FPS_HELP,
    INLINE_OPT,
    SCRIPT_ARG,
    SEED_HELP,
    SIZE_OPT,
    THEME_OPT,
    check_recordings,
    echo_warnings,
    fail,
    fitted_theme,
    following_from,
    load_script,
    script_from,
)
from .events_option import DURATION_OPT, EVENTS_OPT, HEAR_OPT, session_animation, visitor_sound
from .finite_numbers import finite
from .log_replay import annotated, is_log, log_animation

if TYPE_CHECKING:  # imported where used: `check` needs neither drawing nor playing
    from ..drawing.renderer import Renderer
    from ..engine.animation import Animation
    from ..robot.rehearsal import Rehearsal
    from ..speech.soundtrack import Placed


def check(
    files: List[str] = typer.Argument(
        ..., metavar="FILE...", help="Scripts to check; '-' reads standard input."
    ),
    ast: bool = typer.Option(False, "--ast", help="Print the script's syntax tree as JSON (one FILE)."),
) -> None:
    """Check scripts: silent with exit status 0 when they are fine.

    Each problem prints as FILE:LINE:COL: error: message, with the source line
    and a caret under the column; any error makes the exit status 1. Warnings
    (an eye target outside the eye ellipse, say) print the same way but keep
    the status 0.
    """
    if ast and len(files) != 1:
        typer.echo("baxterface check: --ast takes exactly one FILE", err=True)
        raise typer.Exit(2)
    failed = False
    for path in files:
        try:
            script = load_script(path)
            check_recordings(script)
        except ScriptError as e:
            typer.echo(e.render(), err=True)
            failed = True
            continue
        echo_warnings(script)
        if ast:
            typer.echo(json.dumps(to_json(script), indent=2, sort_keys=True))
    if failed:
        raise typer.Exit(1)


def explain(
    script_path: Optional[str] = SCRIPT_ARG,
    inline: Optional[str] = INLINE_OPT,
    as_json: bool = typer.Option(
        False, "--json", help="One JSON object per frame (JSON Lines): the whole face state."
    ),
    fps: float = typer.Option(
        30.0, "--fps", min=1.0, max=120.0, callback=finite, help="Frames per second for --json."
    ),
    seed: int = typer.Option(DEFAULT_SEED, "--seed", help=SEED_HELP),
    idle: bool = typer.Option(False, "--idle", help="Include idle blinks and eye darts (--json)."),
    crossfade: Optional[float] = CROSSFADE_OPT,
    grouped: bool = typer.Option(
        False, "--grouped", help="Statements first, then face changes, robot commands and words."
    ),
    events: Optional[str] = EVENTS_OPT,
    hear: Optional[str] = HEAR_OPT,
    duration: Optional[float] = DURATION_OPT,
) -> None:
    """Explain a script's timeline: what starts and ends when.

    One line per statement, face change, robot command and spoken word, in
    time order (--grouped: statements, then face, robot and words). With
    --json, print one record per frame with the whole face state (skin,
    mouth, brows, eyes, eyelids, head pan, crossfade) and the robot's status. With --events,
    the events, which handler ran when, and what each dropped or queued; with --hear, the
    script's words heard in a recording are events too.
    """
    from ..engine.explanation import explained, frame_times
    from ..engine.session_run import reactive
    from ..engine.timeline import state_record

    if is_log(script_path):  # a session's log: its scripts and events run again
        given = (inline, events, hear)
        animation, run, replay = log_animation(script_path, seed, idle, crossfade, duration, "explain", given)
        script, log = replay.script, run.log
    else:
        script = script_from(script_path, inline, "explain")
        animation, log = session_animation(script, events, seed, idle, crossfade, duration, "explain", hear)
        if events is None and hear is None and not reactive(script):
            log = []  # it says only that the script ended, as the listing's end does
    timeline = animation.timeline
    if as_json:
        for t in frame_times(timeline.duration, fps):  # the frames `render` draws
            typer.echo(json.dumps(state_record(t, animation.sample(t), timeline.status(t)), sort_keys=True))
        return
    typer.echo(f"{script.filename}: {timeline.duration:.2f} s")
    for line in explained(timeline, grouped, [(entry.at, entry.text) for entry in log]):
        typer.echo(line)


def render(
    script_path: Optional[str] = SCRIPT_ARG,
    out: str = typer.Option(
        ...,
        "--out",
        "-o",
        metavar="PATH",
        help="FILE.mp4, .webm, .gif, .webp, .apng, .bag, .png (one frame), .wav (the speech alone), "
        "or DIR/ for numbered PNGs.",
    ),
    inline: Optional[str] = INLINE_OPT,
    fps: float = typer.Option(30.0, "--fps", min=1.0, max=120.0, callback=finite, help=FPS_HELP),
    size: Optional[str] = SIZE_OPT,
    seed: int = typer.Option(DEFAULT_SEED, "--seed", help=SEED_HELP),
    at: Optional[float] = typer.Option(
        None,
        "--at",
        metavar="T",
        min=0.0,
        callback=finite,
        help="For a .png: the time to show (default: the end).",
    ),
    theme: Optional[str] = THEME_OPT,
    idle: bool = typer.Option(False, "--idle", help="Add idle blinks and eye darts."),
    crossfade: Optional[float] = CROSSFADE_OPT,
    quiet: bool = typer.Option(
        False, "--quiet", "-q", help="No progress bar, and no line saying what was written."
    ),
    robot: str = typer.Option(
        "baxter", "--robot", metavar="NAME", help="For a .bag: baxter (/robot/xdisplay) or sawyer."
    ),
    follow_from: Optional[str] = FOLLOW_FROM_OPT,
    face_policy: Optional[str] = FACE_POLICY_OPT,
    events: Optional[str] = EVENTS_OPT,
    hear: Optional[str] = HEAR_OPT,
    duration: Optional[float] = DURATION_OPT,
) -> None:
    """Render a script to a video, an animation, a ROS bag or image files.

    The extension picks the format: .mp4 (H.264) and .webm (VP9) videos, with
    the speech; .gif, .webp and .apng looping animations; a .bag that `rosbag
    play` replays on the robot; .wav the speech alone; a .png gets one frame,
    the last or the one at --at; PATH ending
    in '/' (or an existing folder) gets frame_00000.png, ... Files appear only
    once complete. A script that follows someone follows them in FILE with
    --follow-from, as `play` shows it. A script that reacts (`on face seen { ... }`) meets the
    events of --events FILE at their times, and the words it waits for heard in --hear FILE.wav:
    the same script, events and seed make the same frames.
    """
    from ..drawing.renderer import Renderer
    from ..engine.effects import SetFollowing
    from ..export.annotations import annotation_kind
    from ..export.registry import format_for
    from ..export.sink import FormatError
    from ..ros.effect_messages import DISPLAY_TOPICS

    if annotation_kind(out):  # ELAN's or Praat's tiers of a session's log
        annotated(script_path, out, seed, duration, (inline, events, hear))
        return
    try:
        fmt = format_for(out)
    except FormatError as e:
        raise typer.BadParameter(str(e), param_hint="--out") from None
    if at is not None and not fmt.one_frame:
        raise typer.BadParameter(
            "picks the frame of a .png; videos, animations, bags and folders get every frame",
            param_hint="--at",
        )
    if robot not in DISPLAY_TOPICS:
        raise typer.BadParameter(
            f"must be {' or '.join(DISPLAY_TOPICS)}, not {robot!r}", param_hint="--robot"
        )
    drawn = [0, 0]  # frames drawn, frames in all: what Ctrl-C reports
    try:
        if is_log(script_path):  # a session's log: its scripts and events run again
            given = (inline, events, hear)
            animation, _, _ = log_animation(script_path, seed, idle, crossfade, duration, "render", given)
        else:
            script = script_from(script_path, inline, "render")
            animation, _ = session_animation(script, events, seed, idle, crossfade, duration, "render", hear)
        say = lambda line: typer.echo(line, err=True)  # noqa: E731
        follows = any(isinstance(cue.effect, SetFollowing) for cue in animation.timeline.cues)
        follow = following_from(follow_from, follows, "render", say, face_policy)
        if at is not None and at > animation.duration:
            say(
                f"baxterface render: --at {at:g} is past the script's end ({animation.duration:.2f} s); "
                "showing the last frame"
            )
        renderer = Renderer(fitted_theme(theme, size, "render"))
        # The visitor's voice beside the face's, in the formats with a sound (the others leave it).
        visitor = [] if is_log(script_path) else visitor_sound(hear, "render")
        count = _written(animation, renderer, out, fps, at, robot, follow, quiet, drawn, visitor)
    except KeyboardInterrupt:  # a partial file is gone already: the sink aborted on the way out
        done = f" after {drawn[0]} of {drawn[1]} frames" if drawn[1] else ""
        raise fail(f"baxterface render: stopped{done}; {out} not written", 130) from None
    if not quiet:  # a log or a pipe hears of it too, as a terminal does
        frames = f"{count} frame{'s' if count != 1 else ''}, " if fmt.frames else ""
        if fmt.one_frame:  # a still says which moment it is, of how long a script
            from ..export.render_to_file import frame_times as sampled

            (still,) = sampled(fmt, animation, fps, at)
            typer.echo(f"wrote {out} (1 frame, at {still:.2f} s of {animation.duration:.2f} s)", err=True)
        else:
            typer.echo(f"wrote {out} ({frames}{animation.duration:.2f} s)", err=True)


def _written(
    animation: Animation,
    renderer: Renderer,
    out: str,
    fps: float,
    at: Optional[float],
    robot: str,
    follow: Optional[Rehearsal],
    quiet: bool,
    drawn: List[int],
    heard: Sequence[Placed] = (),
) -> int:
    """Render to `out`, with a progress bar on a terminal; the frames written, or a one-line failure."""
    from ..export.render_to_file import render as render_to
    from ..export.sink import FormatError

    def counted(done: int, total: int) -> None:
        drawn[:] = [done, total]

    try:
        if quiet or not sys.stderr.isatty():
            return render_to(animation, renderer, out, fps, at, counted, robot, follow, heard)
        from rich.progress import Progress

        with Progress(transient=True) as bar:
            task = bar.add_task("rendering", total=None)

            def shown(done: int, total: int) -> None:
                counted(done, total)
                bar.update(task, completed=done, total=total)

            return render_to(animation, renderer, out, fps, at, shown, robot, follow, heard)
    except MissingTool as e:
        raise fail(f"baxterface render: {e}") from None
    except FormatError as e:
        raise fail(f"baxterface render: {e}", 2) from None
    except OSError as e:
        raise fail(f"baxterface render: cannot write {out}: {_reason(e, out)}") from None


_NAMED_ERRORS = (errno.EACCES, errno.EPERM, errno.EROFS, errno.ENOTDIR, errno.EISDIR, errno.ENOENT)


def _reason(error: OSError, out: str) -> str:
    """Why writing failed, naming the path at fault where it is not `out` itself."""
    reason = error.strerror or str(error)
    named = str(error.filename or "")
    # A folder made read-only mid-render, say; never the hidden partial's own name.
    ours = named.rstrip("/") == out.rstrip("/") or ".baxterface-partial" in named
    if error.errno in _NAMED_ERRORS and named and not ours:
        return f"{named}: {reason}"
    return reason
