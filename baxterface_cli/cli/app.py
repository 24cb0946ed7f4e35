"""The `baxterface` app: its options and helpers that every command shares, and its entry point."""

from __future__ import annotations

import os
import signal
import sys
from typing import List, Optional

import typer

from .. import __version__
from ..extras import MissingTool
from ..language.diagnostics import ScriptError, render_all
from ..language.parser import parse, parse_file
from ..language.syntax_tree import Script
from .finite_numbers import finite

DEFAULT_SEED = 0  # render and explain are reproducible unless told otherwise

app = typer.Typer(
    name="baxterface",
    help="A face for the Baxter robot's head screen, written as a script.\n\n"
    "Scripts mix the old face node's commands (happy, look_40_-20_0.5, wobble_0.3) "
    "with the script language (happy; look 40 -20 in 0.5s; wobble 0.3). "
    "See docs/language.md.",
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    # Plain help and errors: an error is one line that names its option, and help shows each
    # argument by its name, not its Python type (<str>) in a box drawn around it.
    rich_markup_mode=None,
    context_settings={"help_option_names": ["-h", "--help"]},
)


def _version(value: bool) -> None:
    if value:
        typer.echo(f"baxterface {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: bool = typer.Option(
        False, "--version", callback=_version, is_eager=True, help="Print the version and exit."
    ),
) -> None:
    """Root options; the work is in the subcommands."""


def load_script(path: str) -> Script:
    """Read and parse FILE, or standard input for '-'."""
    if path == "-":
        return parse_file(sys.stdin.buffer, "<stdin>")
    return parse_file(path)


def fail(message: str, code: int = 1) -> typer.Exit:
    typer.echo(message, err=True)
    return typer.Exit(code)


def script_from(path: Optional[str], inline: Optional[str], command: str, recordings: bool = True) -> Script:
    """The script a command was given: FILE, '-', inline with -e, or piped in.

    With `recordings`, the files its `say file`s name are checked too (see `check_recordings`).
    """
    try:
        if inline is not None:
            if path is not None:
                raise fail(f"baxterface {command}: give a SCRIPT or -e TEXT, not both", 2)
            script = parse(inline, "<-e>", ".")  # its `use`s from the current folder
        elif path is None and sys.stdin.isatty():
            raise fail(
                f"baxterface {command}: no script; give a FILE, '-' for standard input, or -e 'happy; blink'",
                2,
            )
        else:
            script = load_script(path or "-")
        if recordings:
            check_recordings(script)
    except ScriptError as e:
        raise fail(e.render()) from None
    echo_warnings(script)
    return script


def recordings_of(script: Script):
    """Where a script's `say file`s are read: its folder, or the current one for '-' and -e."""
    from ..speech.recordings import Recordings

    return Recordings.for_script(
        script.filename, warn=lambda line: typer.echo(f"baxterface: {line}", err=True)
    )


def check_recordings(script: Script) -> None:
    """ScriptError, at each `say file`, for a recording that is missing or cannot be read."""
    problems = recordings_of(script).check(script) if "file" in script.source.lower() else []
    if problems:
        raise ScriptError(problems, script.filename, script.source)


def echo_warnings(script: Script) -> None:
    if script.warnings:
        text = render_all(script.warnings, script.filename, script.source, more_warnings=script.more_warnings)
        typer.echo(text, err=True)


def fitted_theme(theme: Optional[str], size: Optional[str], command: str):
    """The theme's layers at the asked size, or a clear exit naming `command`."""
    from ..drawing.theme import ThemeError, resolve

    try:
        return resolve(theme).layers(parse_size_option(size) or (1024, 600))
    except ThemeError as e:
        raise fail(f"baxterface {command}: {e}") from None


SCRIPT_ARG = typer.Argument(
    None, metavar="[SCRIPT]", help="Script file; '-' or nothing reads standard input."
)
INLINE_OPT = typer.Option(
    None, "-e", "--eval", metavar="TEXT", help="The script itself: -e 'happy; look 40 -20'."
)
SEED_HELP = "Seed for emotions' random mouths and brows, and idle blinks."
SIZE_OPT = typer.Option(
    None,
    "--size",
    metavar="WIDTHxHEIGHT",
    help="Screen size in pixels. Default: 1024x600; upgraded heads have 1920x1200.",
)
THEME_OPT = typer.Option(
    None, "--theme", metavar="DIR", help="A theme folder (see 'baxterface theme export')."
)
FPS_HELP = "Frames per second."
# Real-time commands: a new seed each run, idle life on.
RANDOM_SEED_OPT = typer.Option(None, "--seed", metavar="N", help=SEED_HELP + " Default: random.")
IDLE_ON_OPT = typer.Option(True, "--idle/--no-idle", help="Idle blinks and eye darts.")
CROSSFADE_OPT = typer.Option(
    None,
    "--crossfade",
    metavar="SECONDS",
    min=0.0,
    max=2.0,
    callback=finite,
    help="Blend part changes over this time; 0 cuts. Default: 0.15 s, or cuts for the old node's commands.",
)


FOLLOW_FROM_OPT = typer.Option(
    None,
    "--follow-from",
    metavar="FILE",
    help="What following sees, instead of the robot's sensors: a trace (.jsonl: sonar, hands) "
    "or camera images (a video or a picture).",
)


FACE_POLICY_OPT = typer.Option(
    None,
    "--face-policy",
    metavar="NAME",
    help="Which face --follow-from's camera images have followed among several: nearest (the "
    "largest, the default), central (nearest the middle) or longest (seen the longest).",
)


def following_from(path: Optional[str], follows: bool, command: str, say, face_policy: Optional[str] = None):
    """The rehearsal that follows what FILE shows (`--follow-from`), or None without one.

    `say` takes a warning line; a file that cannot be used is a clear exit 1.
    """
    if face_policy is not None:
        from ..robot.person_choice import FACE_POLICIES, FACE_POLICY_CHOICES

        if face_policy not in FACE_POLICIES:
            raise typer.BadParameter(
                f"must be {FACE_POLICY_CHOICES}, not {face_policy[:40]!r}", param_hint="--face-policy"
            )
        if path is None:
            raise typer.BadParameter(
                "chooses among the faces in --follow-from FILE", param_hint="--face-policy"
            )
    if path is None:
        return None
    from ..robot.rehearsal import FollowSourceError, Rehearsal, open_source

    try:
        source = open_source(path)
    except (MissingTool, FollowSourceError) as e:
        raise fail(f"baxterface {command}: {e}") from None
    if not follows:
        say(f"baxterface {command}: the script follows nothing, so --follow-from changes nothing")
    warn = lambda message: say(f"baxterface {command}: {message}")  # noqa: E731
    return Rehearsal(source, warn) if face_policy is None else Rehearsal(source, warn, face_policy)


def parse_size_option(text: Optional[str]) -> Optional[tuple]:
    from ..drawing.theme_manifest import parse_size

    if text is None:
        return None
    try:
        return parse_size(text)
    except ValueError as e:  # "size 10x10 is too small": the option names it
        raise typer.BadParameter(str(e).replace("size ", "", 1), param_hint="'--size'") from None


ROS_ARGS = {"allow_extra_args": True, "ignore_unknown_options": True}

# What an option's value is, by its name, for the options declared without a metavar: help would
# otherwise show click's name of its type (<float range>, <int>, TEXT).
METAVARS = {
    "--fps": "FPS",
    "--seed": "N",
    "--port": "PORT",
    "--host": "ADDRESS",
    "--topic": "TOPIC",
    "--timeout": "SECONDS",
    "--robot": "NAME",
    "--audio": "MODE",
    "--url": "URL",
    "--token": "TOKEN",
    "--at": "SECONDS",
    "--size": "WIDTHxHEIGHT",
}


def named_metavars(command) -> None:
    """Give every option of `command` and its subcommands without a metavar its METAVARS one."""
    for sub in getattr(command, "commands", {}).values():
        named_metavars(sub)
    for param in command.params:
        if getattr(param, "is_flag", False) or getattr(param, "count", False):
            continue
        names = [o for o in param.opts if o in METAVARS]
        if names and (param.metavar is None or param.metavar in ("T", "WxH")):
            param.metavar = METAVARS[names[0]]


def _terminate(signum: int, frame: object) -> None:
    # Unwind like Ctrl-C, so half-written output is removed on the way out.
    raise SystemExit(128 + signum)


def _check_default_voice() -> None:
    """A $BAXTERFACE_VOICE that names no voice is one line at the start, whatever the command."""
    from ..core.voices import VOICE_VARIABLE, default_voice, say_voice_names

    try:
        default_voice()
    except ValueError as e:
        from ..language.diagnostics import did_you_mean

        name = os.environ.get(VOICE_VARIABLE, "").strip().lower()
        hint = did_you_mean(name, say_voice_names()) or "; 'baxterface voices' lists them"
        typer.echo(f"baxterface: {e}{hint}", err=True)
        sys.exit(1)


def main(argv: Optional[List[str]] = None) -> None:
    """Entry point: run the app, never showing a user a Python traceback."""
    signal.signal(signal.SIGTERM, _terminate)
    _check_default_voice()
    try:
        command = typer.main.get_command(app)
        named_metavars(command)
        command(args=argv, prog_name="baxterface")
    except Exception as e:  # a bug of ours: say so in one line
        if os.environ.get("BAXTERFACE_DEBUG"):
            raise
        typer.echo(f"baxterface: internal error: {e!r} (BAXTERFACE_DEBUG=1 shows where)", err=True)
        sys.exit(2)
