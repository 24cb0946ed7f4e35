"""The face's assets: `voices`, `gestures` and `theme export` / `theme check`."""

from __future__ import annotations

from typing import Optional

import typer

from .app import (
    fail,
    parse_size_option,
)


def voices(
    query: Optional[str] = typer.Argument(
        None,
        metavar="[LANGUAGE]",
        help="Only these: a voice name and those under it (en), or a language (spanish).",
    ),
) -> None:
    """List the voices `say ... voice NAME` takes (espeak-ng's), with the language each speaks."""
    from ..core.voices import listed_voices, matching_voices

    found = matching_voices(query) if query else list(listed_voices().items())
    if not found:
        raise fail(f"baxterface voices: no voice speaks {query!r}; 'baxterface voices' lists them all")
    width = max(len(name) for name, _ in found)
    for name, language in found:
        typer.echo(f"{name:<{width}}  {language}")


def gestures(
    name: Optional[str] = typer.Argument(
        None, metavar="[NAME]", help="Print this gesture's definition, to copy and change."
    ),
) -> None:
    """List the gestures every script may call by name (laugh, shake, ...): length, what each does."""
    from ..language.parser import gestures as library

    found = library()
    if name is None:
        width = max(len(g) for g in found)
        for gesture in found.values():
            typer.echo(f"{gesture.name:<{width}}  {gesture.seconds:4.1f} s  {gesture.about}")
        return
    gesture = found.get(name.lower())
    if gesture is None:
        raise fail(f"baxterface gestures: no gesture {name!r}; 'baxterface gestures' lists them")
    typer.echo(f"# {gesture.about}")
    typer.echo(gesture.text)


def theme_export(
    folder: str = typer.Argument(..., metavar="DIR", help="Folder to write the layers and theme.json to."),
    size: Optional[str] = typer.Option(
        None, "--size", metavar="WIDTHxHEIGHT", help="Screen size to draw the layers at (default 1024x600)."
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
    if not folder:  # Path("") is the current folder
        raise typer.BadParameter("is empty; give a folder (./ for this one)", param_hint="DIR")
    from ..drawing.theme import Theme, ThemeError

    try:
        source = Theme.load(theme) if theme else Theme.default()
        written = source.export(folder, parse_size_option(size), force=force)
    except ThemeError as e:
        typer.echo(f"baxterface: {e}", err=True)
        raise typer.Exit(1) from None
    typer.echo(f"wrote {len(written)} files to {folder}")


def theme_check(folder: str = typer.Argument(..., metavar="DIR", help="A theme folder.")) -> None:
    """Check that a theme folder has every layer, readable and of the right size."""
    from ..drawing.theme import Theme, ThemeError

    try:
        theme = Theme.load(folder)
        theme.layers(theme.size)
    except ThemeError as e:
        typer.echo(f"baxterface: {e}", err=True)
        raise typer.Exit(1) from None
