"""The `baxterface` command line: a thin adapter over the library."""

from __future__ import annotations

import json
import os
import sys
from typing import List, Optional

import typer

from . import __version__
from .diagnostics import ScriptError
from .nodes import Script, to_json
from .parser import decode, parse, read_bounded

app = typer.Typer(
    name="baxterface",
    help="A face for the Baxter robot's head screen, written as a script.\n\n"
    "Scripts mix the old face node's commands (happy, look_40_-20_0.5, wobble_0.3) "
    "with the script language (happy; look 40 -20 in 0.5s; wobble 0.3). "
    "See docs/language.md.",
    no_args_is_help=True,
    pretty_exceptions_enable=False,
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
        name = "<stdin>"
        data = read_bounded(sys.stdin.buffer, name)
    else:
        name = path
        data = read_bounded(path, name)
    return parse(decode(data, name), name)


@app.command()
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
        except ScriptError as e:
            typer.echo(e.render(), err=True)
            failed = True
            continue
        for warning in script.warnings:
            typer.echo(warning.render(script.filename, script.source), err=True)
        if ast:
            typer.echo(json.dumps(to_json(script), indent=2, sort_keys=True))
    if failed:
        raise typer.Exit(1)


def main(argv: Optional[List[str]] = None) -> None:
    """Entry point: run the app, never showing a user a Python traceback."""
    try:
        app(args=argv, prog_name="baxterface")
    except Exception as e:  # a bug of ours: say so in one line
        if os.environ.get("BAXTERFACE_DEBUG"):
            raise
        typer.echo(f"baxterface: internal error: {e!r} (BAXTERFACE_DEBUG=1 shows where)", err=True)
        sys.exit(2)
