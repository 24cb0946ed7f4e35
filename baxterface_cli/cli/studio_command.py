"""`baxterface studio`: write, preview and perform the face from a web page."""

from __future__ import annotations

import contextlib
import secrets
import time
from pathlib import Path
from typing import Optional

import typer

from ..extras import MissingTool
from ..language.diagnostics import ScriptError
from .app import (
    IDLE_ON_OPT,
    RANDOM_SEED_OPT,
    THEME_OPT,
    fail,
    fitted_theme,
)
from .finite_numbers import finite
from .log_option import LOG_OPT, LOG_SIZE_OPT, log_file, logged_seed, open_log


def studio(
    script_path: Optional[str] = typer.Argument(
        None, metavar="[SCRIPT]", help="The script to write; made on first save. Default: studio.face here."
    ),
    port: int = typer.Option(8080, "--port", min=0, max=65535, help="Port to serve on; 0 takes a free one."),
    host: str = typer.Option(
        "127.0.0.1", "--host", help="Address to serve on. Anything but loopback needs the printed token."
    ),
    no_browser: bool = typer.Option(False, "--no-browser", help="Do not open a web browser."),
    panel: Optional[str] = typer.Option(
        None, "--buttons", metavar="FILE", help="Your own button panel (JSON; see docs/studio.md)."
    ),
    size: str = typer.Option("512x300", "--size", metavar="WxH", help="The preview's size."),
    fps: float = typer.Option(
        30.0, "--fps", min=1.0, max=60.0, callback=finite, help="The preview's most frames a second."
    ),
    seed: Optional[int] = RANDOM_SEED_OPT,
    theme: Optional[str] = THEME_OPT,
    idle: bool = IDLE_ON_OPT,
    topic: str = typer.Option(
        "display_chatter", "--topic", help="The face node's command topic, for presses sent to the robot."
    ),
    log: Optional[str] = LOG_OPT,
    log_size: float = LOG_SIZE_OPT,
) -> None:
    """Write, preview and perform the face from a web page.

    An editor with check's diagnostics as you type, a live preview drawn by
    the face's own renderer, and a button panel for live sessions whose
    presses take over at once (and on the robot, when switched on) and export
    as a log that render replays. Serves on 127.0.0.1:8080 until Ctrl-C.
    """
    from ..extras import need
    from ..studio.panel import PanelError

    try:
        need("starlette", "studio", "the studio")
        need("uvicorn", "studio", "the studio")
    except MissingTool as e:
        raise fail(f"baxterface studio: {e}") from None
    from ..drawing.renderer import Renderer
    from ..speech.warm_start import start_in_background
    from ..studio.api import create_app
    from ..studio.api import log as server_log
    from ..studio.workspace import Workspace
    from ..web.request_guard import is_loopback
    from ..web.server import bind, serve, url_for

    path = Path(script_path or "studio.face")
    if path.is_dir():
        raise fail(f"baxterface studio: {path} is a folder; give a script file", 2)
    if not path.parent.resolve().is_dir():
        raise fail(f"baxterface studio: no folder {path.parent} to keep {path.name} in", 2)
    seed = logged_seed(log, seed)
    logged = log_file(log, log_size, "studio", seed=seed)
    start_in_background()  # the speech process starts as the theme is fitted: no `say` waits for it
    renderer = Renderer(fitted_theme(theme, size, "studio"))
    renderer.prepare_in_background()
    said = lambda text: typer.echo(f"baxterface studio: {text}", err=True)  # noqa: E731 - the log's warnings
    # The session's log, closed however the studio ends: a script it refuses, a port taken, Ctrl-C.
    with open_log(logged, time.monotonic(), said) or contextlib.nullcontext() as record:
        try:
            buttons = Path(panel) if panel else None
            workspace = Workspace(path, buttons, seed, idle, topic=topic, record=record)
        except PanelError as e:
            raise fail(f"baxterface studio: {e}") from None
        except ScriptError as e:
            raise fail(e.render()) from None
        token = None if is_loopback(host) else secrets.token_urlsafe(18)
        try:
            sock = bind(host, port)
        except OSError as e:
            raise fail(f"baxterface studio: cannot serve on {host}:{port}: {e.strerror or e}") from None
        url = url_for(host, sock.getsockname()[1], token)
        made = "" if path.exists() else f" ({path.name} is made on first save)"
        served = create_app(workspace, renderer, fps, token).serving("studio", host, sock.getsockname()[1])

        def ready() -> None:
            typer.echo(f"baxterface studio: {url}  editing {path}{made}; Ctrl-C stops", err=True)
            if not no_browser:
                import webbrowser

                webbrowser.open(url)

        stopped_by = serve(served, sock, ready, log=server_log)
    if workspace.text != workspace.saved:
        typer.echo(
            f"baxterface studio: stopped; the editor's last changes to {path.name} were not saved", err=True
        )
    else:
        typer.echo("baxterface studio: stopped", err=True)
    if stopped_by is not None:  # the shell's convention: 128 + the signal (130 for Ctrl-C)
        raise typer.Exit(128 + stopped_by)
