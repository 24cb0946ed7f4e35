"""`baxterface screen`: the face alone, for any screen with a browser."""

from __future__ import annotations

import contextlib
import os
import re
import secrets
from typing import Optional

import typer

from ..extras import MissingTool
from ..language.diagnostics import ScriptError
from .app import IDLE_ON_OPT, RANDOM_SEED_OPT, THEME_OPT, echo_warnings, fail, fitted_theme, load_script
from .finite_numbers import finite
from .log_option import LOG_OPT, LOG_SIZE_OPT, log_file, logged_seed
from .web_client import TOKEN_VARIABLE

SHORTEST_TOKEN = 16
TOKEN = re.compile(r"[A-Za-z0-9_.~-]{16,}")  # goes into an address as it is


def screen(
    script_path: Optional[str] = typer.Argument(
        None, metavar="[SCRIPT]", help="A script to play first, when the first screen opens; '-' reads it in."
    ),
    port: int = typer.Option(8081, "--port", min=0, max=65535, help="Port to serve on; 0 takes a free one."),
    host: str = typer.Option(
        "127.0.0.1", "--host", help="Address to serve on. Anything but loopback needs the printed token."
    ),
    ros: Optional[int] = typer.Option(
        None, "--ros", metavar="1|2", min=1, max=2, help="Commands from display_chatter too, on ROS 1 or 2."
    ),
    topic: str = typer.Option("display_chatter", "--topic", help="The command topic, with --ros."),
    no_browser: bool = typer.Option(False, "--no-browser", help="Do not open a web browser here."),
    size: str = typer.Option("1024x600", "--size", metavar="WxH", help="The frames' size."),
    fps: float = typer.Option(
        30.0, "--fps", min=1.0, max=60.0, callback=finite, help="The most frames a second."
    ),
    seed: Optional[int] = RANDOM_SEED_OPT,
    theme: Optional[str] = THEME_OPT,
    idle: bool = IDLE_ON_OPT,
    log: Optional[str] = LOG_OPT,
    log_size: float = LOG_SIZE_OPT,
) -> None:
    """Show the face alone on any screen with a browser: a tablet, a monitor, a kiosk.

    The page fills the window with the face, keeps the screen awake, comes
    back by itself when this server restarts, and plays what the face says.
    Commands come as in the studio (POST /api/command) and, with --ros, on
    display_chatter as the face node takes them. Serves on 127.0.0.1:8081
    until Ctrl-C; another --host needs the printed token (or BAXTERFACE_TOKEN).
    """
    from ..extras import need

    try:
        need("starlette", "studio", "the screen")
        need("uvicorn", "studio", "the screen")
    except MissingTool as e:
        raise fail(f"baxterface screen: {e}") from None
    seed = logged_seed(log, seed)
    logged = log_file(log, log_size, "screen", seed=seed)
    script = None
    if script_path is not None:
        try:
            script = load_script(script_path)
        except ScriptError as e:
            raise fail(e.render()) from None
        echo_warnings(script)
    from ..drawing.renderer import Renderer
    from ..screen.screen_api import ScreenApi
    from ..screen.screen_face import ScreenFace
    from ..speech.warm_start import start_in_background
    from ..web.request_guard import is_loopback
    from ..web.server import bind, logger, serve, url_for

    start_in_background()  # the speech process starts as the theme is fitted: no `say` waits for it
    renderer = Renderer(fitted_theme(theme, size, "screen"))
    renderer.prepare_in_background()
    try:
        face = ScreenFace(script, seed, idle, log_file=logged)
    except MissingTool as e:  # `say` without a speech engine
        raise fail(f"baxterface screen: {e}") from None
    api = ScreenApi(face, renderer, fps, logger("screen"))
    listening = _listen(ros, topic, api) if ros is not None else contextlib.nullcontext()
    token = None if is_loopback(host) else _token()
    try:
        sock = bind(host, port)
    except OSError as e:
        raise fail(f"baxterface screen: cannot serve on {host}:{port}: {e.strerror or e}") from None
    url = url_for(host, sock.getsockname()[1], token)
    showing = f"playing {script_path} first" if script_path else "the face"
    heard = f", and commands on {topic} (ROS {ros})" if ros is not None else ""

    def ready() -> None:
        api.start()  # in the server's loop: commands heard on ROS are taken from now
        typer.echo(f"baxterface screen: {url}  {showing}{heard}; Ctrl-C stops", err=True)
        if not no_browser:
            import webbrowser

            webbrowser.open(url)

    with listening:  # commands heard on ROS until the server stops
        served = api.app(token).serving("screen", host, sock.getsockname()[1])
        stopped_by = serve(served, sock, ready, stopping=api.stop_taking, log=api.log)
    face.close()  # the session's log file, if any, ends with the shutdown
    typer.echo("baxterface screen: stopped", err=True)
    if stopped_by is not None:  # the shell's convention: 128 + the signal (130 for Ctrl-C)
        raise typer.Exit(128 + stopped_by)


def _listen(version: int, topic: str, api):
    """Commands heard on ROS `version`'s `topic`, taken as POST /api/command takes them."""
    from ..ros.connect import RosUnavailable
    from ..screen.chatter_feed import listen

    try:
        return listen(version, topic, lambda text: api.hand_over(text, topic))
    except RosUnavailable as e:
        raise fail(f"baxterface screen: {e}") from None


def _token() -> str:
    """The token other machines need: BAXTERFACE_TOKEN's, which outlives a restart, else a new one."""
    given = os.environ.get(TOKEN_VARIABLE)
    if given is None:
        return secrets.token_urlsafe(18)
    if not TOKEN.fullmatch(given):
        raise fail(
            f"baxterface screen: {TOKEN_VARIABLE} must be at least {SHORTEST_TOKEN} letters, digits, "
            "'-', '_', '.' or '~'; python3 -c 'import secrets; print(secrets.token_urlsafe(18))' makes one"
        )
    return given
