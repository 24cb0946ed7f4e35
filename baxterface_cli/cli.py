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
from .theme import Theme, ThemeError, parse_size

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


theme_app = typer.Typer(
    help="Themes: the face's layer images. Export the default one to edit, check your own.",
    no_args_is_help=True,
)
app.add_typer(theme_app, name="theme")


def _size(text: Optional[str]) -> Optional[tuple]:
    if text is None:
        return None
    try:
        return parse_size(text)
    except ValueError as e:
        raise typer.BadParameter(str(e)) from None


@theme_app.command("export")
def theme_export(
    folder: str = typer.Argument(..., metavar="DIR", help="Folder to write the layers and theme.json to."),
    size: Optional[str] = typer.Option(
        None, "--size", metavar="WxH", help="Screen size to draw the layers at (default 1024x600)."
    ),
    theme: Optional[str] = typer.Option(
        None, "--theme", metavar="DIR", help="Export this theme instead of the default."
    ),
    force: bool = typer.Option(False, "--force", help="Write into a folder that is not empty."),
) -> None:
    """Write a theme's layers (PNG) and manifest to DIR, to edit in an image editor.

    Every layer is a full-screen RGBA image; keep each file's size when you edit
    it, then use the folder with --theme DIR.
    """
    try:
        source = Theme.load(theme) if theme else Theme.default()
        written = source.export(folder, _size(size), force=force)
    except ThemeError as e:
        typer.echo(f"baxterface: {e}", err=True)
        raise typer.Exit(1) from None
    typer.echo(f"wrote {len(written)} files to {folder}")


@theme_app.command("check")
def theme_check(folder: str = typer.Argument(..., metavar="DIR", help="A theme folder.")) -> None:
    """Check that a theme folder has every layer, readable and of the right size."""
    try:
        theme = Theme.load(folder)
        theme.layers(theme.size)
    except ThemeError as e:
        typer.echo(f"baxterface: {e}", err=True)
        raise typer.Exit(1) from None


def main(argv: Optional[List[str]] = None) -> None:
    """Entry point: run the app, never showing a user a Python traceback."""
    try:
        app(args=argv, prog_name="baxterface")
    except Exception as e:  # a bug of ours: say so in one line
        if os.environ.get("BAXTERFACE_DEBUG"):
            raise
        typer.echo(f"baxterface: internal error: {e!r} (BAXTERFACE_DEBUG=1 shows where)", err=True)
        sys.exit(2)
