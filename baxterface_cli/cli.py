"""The `baxterface` command line: a thin adapter over the library."""

from __future__ import annotations

import json
import os
import secrets
import signal
import sys
from pathlib import Path
from typing import List, Optional

import typer

from . import __version__
from .diagnostics import ScriptError, render_all
from .extras import MissingTool
from .nodes import Script, to_json
from .parser import parse, parse_file

DEFAULT_SEED = 0  # render and explain are reproducible unless told otherwise

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
        return parse_file(sys.stdin.buffer, "<stdin>")
    return parse_file(path)


def fail(message: str, code: int = 1) -> typer.Exit:
    typer.echo(message, err=True)
    return typer.Exit(code)


def script_from(path: Optional[str], inline: Optional[str], command: str) -> Script:
    """The script a command was given: FILE, '-', inline with -e, or piped in."""
    try:
        if inline is not None:
            if path is not None:
                raise fail(f"baxterface {command}: give a SCRIPT or -e TEXT, not both", 2)
            script = parse(inline, "<-e>")
        elif path is None and sys.stdin.isatty():
            raise fail(
                f"baxterface {command}: no script; give a FILE, '-' for standard input, or -e 'happy; blink'",
                2,
            )
        else:
            script = load_script(path or "-")
    except ScriptError as e:
        raise fail(e.render()) from None
    echo_warnings(script)
    return script


def echo_warnings(script: Script) -> None:
    if script.warnings:
        text = render_all(script.warnings, script.filename, script.source, more_warnings=script.more_warnings)
        typer.echo(text, err=True)


def fitted_theme(theme: Optional[str], size: Optional[str], command: str):
    """The theme's layers at the asked size, or a clear exit naming `command`."""
    from .theme import ThemeError, resolve

    try:
        return resolve(theme).layers(_size(size) or (1024, 600))
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
    None, "--size", metavar="WxH", help="Screen size (default 1024x600; 1920x1200 for upgraded heads)."
)
THEME_OPT = typer.Option(
    None, "--theme", metavar="DIR", help="A theme folder (see 'baxterface theme export')."
)
FPS_HELP = "Frames per second."
# Real-time commands: a new seed each run, idle life on.
RANDOM_SEED_OPT = typer.Option(None, "--seed", help=SEED_HELP + " Default: random.")
IDLE_ON_OPT = typer.Option(True, "--idle/--no-idle", help="Idle blinks and eye darts.")
CROSSFADE_OPT = typer.Option(
    None,
    "--crossfade",
    metavar="SECONDS",
    min=0.0,
    max=2.0,
    help="Blend part changes over this time; 0 cuts. Default: 0.15 s, or cuts for the old node's commands.",
)


FOLLOW_FROM_OPT = typer.Option(
    None,
    "--follow-from",
    metavar="FILE",
    help="What following sees, instead of the robot's sensors: a trace (.jsonl: sonar, hands) "
    "or camera images (a video or a picture).",
)


def following_from(path: Optional[str], animation, command: str, say):
    """The rehearsal that follows what FILE shows (`--follow-from`), or None without one.

    `say` takes a warning line; a file that cannot be used is a clear exit 1.
    """
    if path is None:
        return None
    from .effects import Follow
    from .rehearsal import FollowSourceError, Rehearsal, open_source

    try:
        source = open_source(path)
    except (MissingTool, FollowSourceError) as e:
        raise fail(f"baxterface {command}: {e}") from None
    if not any(isinstance(cue.effect, Follow) for cue in animation.timeline.cues):
        say(f"baxterface {command}: the script follows nothing, so --follow-from changes nothing")
    return Rehearsal(source, lambda message: say(f"baxterface {command}: {message}"))


def animation_for(script: Script, seed: Optional[int], idle: bool, crossfade: Optional[float]):
    from .idle import Animation
    from .timeline import compile_script

    try:
        timeline = compile_script(script, seed, crossfade=crossfade)
    except MissingTool as e:  # `say` without a speech engine
        raise fail(f"baxterface: {e}") from None
    return Animation(timeline, idle=idle, seed=seed)


@app.command()
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
    fps: float = typer.Option(30.0, "--fps", min=1.0, max=120.0, help=FPS_HELP),
    size: Optional[str] = SIZE_OPT,
    seed: int = typer.Option(DEFAULT_SEED, "--seed", help=SEED_HELP),
    at: Optional[float] = typer.Option(
        None, "--at", metavar="T", min=0.0, help="For a .png: the time to show (default: the end)."
    ),
    theme: Optional[str] = THEME_OPT,
    idle: bool = typer.Option(False, "--idle", help="Add idle blinks and eye darts."),
    crossfade: Optional[float] = CROSSFADE_OPT,
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress bar."),
    robot: str = typer.Option(
        "baxter", "--robot", metavar="NAME", help="For a .bag: baxter (/robot/xdisplay) or sawyer."
    ),
    follow_from: Optional[str] = FOLLOW_FROM_OPT,
) -> None:
    """Render a script to a video, an animation, a ROS bag or image files.

    The extension picks the format: .mp4 (H.264) and .webm (VP9) videos, with
    the speech; .gif, .webp and .apng looping animations; a .bag that `rosbag
    play` replays on the robot; .wav the speech alone; a .png gets one frame,
    the last or the one at --at; PATH ending
    in '/' (or an existing folder) gets frame_00000.png, ... Files appear only
    once complete. A script that follows someone follows them in FILE with
    --follow-from, as `play` shows it.
    """
    from .formats import FormatError, format_for
    from .renderer import Renderer
    from .rendering import render as render_to
    from .ros.robot_link import DISPLAY_TOPICS

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
    animation = animation_for(script_from(script_path, inline, "render"), seed, idle, crossfade)
    follow = following_from(follow_from, animation, "render", lambda line: typer.echo(line, err=True))
    if at is not None and at > animation.duration:
        typer.echo(
            f"baxterface render: --at {at:g} is past the script's end ({animation.duration:.2f} s); "
            "showing the last frame",
            err=True,
        )
    renderer = Renderer(fitted_theme(theme, size, "render"))
    show_progress = not quiet and sys.stderr.isatty()
    try:
        if show_progress:
            from rich.progress import Progress

            with Progress(transient=True) as bar:
                task = bar.add_task("rendering", total=None)
                count = render_to(
                    animation,
                    renderer,
                    out,
                    fps,
                    at,
                    lambda done, total: bar.update(task, completed=done, total=total),
                    robot,
                    follow,
                )
        else:
            count = render_to(animation, renderer, out, fps, at, robot=robot, follow=follow)
    except MissingTool as e:
        raise fail(f"baxterface render: {e}") from None
    except FormatError as e:
        raise fail(f"baxterface render: {e}", 2) from None
    except OSError as e:
        raise fail(f"baxterface render: cannot write {out}: {e.strerror or e}") from None
    if not quiet and sys.stderr.isatty():
        frames = f"{count} frame{'s' if count != 1 else ''}, " if fmt.frames else ""
        typer.echo(f"wrote {out} ({frames}{animation.duration:.2f} s)", err=True)


@app.command()
def explain(
    script_path: Optional[str] = SCRIPT_ARG,
    inline: Optional[str] = INLINE_OPT,
    as_json: bool = typer.Option(
        False, "--json", help="One JSON object per frame (JSON Lines): the whole face state."
    ),
    fps: float = typer.Option(30.0, "--fps", min=1.0, max=120.0, help="Frames per second for --json."),
    seed: int = typer.Option(DEFAULT_SEED, "--seed", help=SEED_HELP),
    idle: bool = typer.Option(False, "--idle", help="Include idle blinks and eye darts (--json)."),
    crossfade: Optional[float] = CROSSFADE_OPT,
    grouped: bool = typer.Option(
        False, "--grouped", help="Statements first, then face changes, robot commands and words."
    ),
) -> None:
    """Explain a script's timeline: what starts and ends when.

    One line per statement, face change, robot command and spoken word, in
    time order (--grouped: statements, then face, robot and words). With
    --json, print one record per frame with the whole face state (skin,
    mouth, brows, eyes, eyelids, head pan, crossfade) and the robot's status.
    """
    from .explanation import explained
    from .timeline import state_record

    script = script_from(script_path, inline, "explain")
    animation = animation_for(script, seed, idle, crossfade)
    timeline = animation.timeline
    if as_json:
        for t in timeline.frame_times(fps):
            typer.echo(json.dumps(state_record(t, animation.sample(t), timeline.status(t)), sort_keys=True))
        return
    typer.echo(f"{script.filename}: {timeline.duration:.2f} s")
    for line in explained(timeline, grouped):
        typer.echo(line)


@app.command()
def play(
    script_path: Optional[str] = typer.Argument(
        None, metavar="SCRIPT", help="Script file ('-' reads standard input)."
    ),
    inline: Optional[str] = INLINE_OPT,
    loop: bool = typer.Option(False, "--loop", help="Start again at the end, until interrupted."),
    watch: bool = typer.Option(
        False, "--watch", help="Reload SCRIPT when it changes; keep the last good version on errors."
    ),
    window: Optional[bool] = typer.Option(
        None, "--window/--terminal", help="Where to play (default: a window if there is a display)."
    ),
    fps: float = typer.Option(30.0, "--fps", min=1.0, max=120.0, help=FPS_HELP),
    size: Optional[str] = SIZE_OPT,
    seed: Optional[int] = RANDOM_SEED_OPT,
    theme: Optional[str] = THEME_OPT,
    idle: bool = IDLE_ON_OPT,
    crossfade: Optional[float] = CROSSFADE_OPT,
    follow_from: Optional[str] = FOLLOW_FROM_OPT,
) -> None:
    """Play a script in real time: in a window, or in this terminal.

    The status line shows what only the robot could: head pan, enable,
    following. A script that says something speaks through this machine's
    sound device, in step with the picture. A script that follows someone
    follows them in FILE with --follow-from. Ctrl-C stops.
    """
    from .playback import Player, TerminalScreen, WindowScreen, window_available
    from .renderer import Renderer

    if watch and (script_path in (None, "-") or inline is not None):
        raise fail("baxterface play: --watch needs a SCRIPT file", 2)
    script = script_from(script_path, inline, "play")
    why_not = window_available()
    if window is None:
        window = why_not is None
    if window and why_not:
        raise fail(f"baxterface play: cannot open a window: {why_not}")
    if not window and not sys.stdout.isatty():
        raise fail(
            "baxterface play: no display and no terminal to play in; "
            "use 'baxterface render SCRIPT --out show.gif' to make a file instead"
        )
    renderer = Renderer(fitted_theme(theme, size, "play"))
    animation = animation_for(script, seed, idle, crossfade)
    held: List[str] = []  # a terminal's face would cover the line; it is said when the face is gone

    def say(line: str) -> None:
        if window:
            typer.echo(line, err=True)
        else:
            held.append(line)

    def open_sound():  # only once a script that speaks starts: the others never touch the device
        from .audio import open_sound as open_device

        return open_device(lambda message: say(f"baxterface play: {message}"))

    follow = following_from(follow_from, animation, "play", say)
    screen = WindowScreen() if window else TerminalScreen()
    player = Player(animation, renderer, screen, fps, sound=open_sound, follow=follow)
    poll = _watcher(script_path, seed, idle, crossfade, player) if watch else None
    interrupted = False
    try:
        player.run(loop=loop, hold=watch, poll=poll)
    except KeyboardInterrupt:
        interrupted = True
    finally:
        screen.close()
        if player.sound is not None:
            player.sound.close()
        for line in held:
            typer.echo(line, err=True)
    shown = f"{player.frames_shown} frames ({screen.name})"
    length = player.animation.duration
    if interrupted:  # the shell's convention: 128 + SIGINT
        where = f"{player.position:.2f} s of {length:.2f} s of script"
        typer.echo(f"interrupted at {where}, after {player.elapsed():.2f} s: {shown}", err=True)
        raise typer.Exit(130)
    typer.echo(f"played {length:.2f} s of script in {player.elapsed():.2f} s: {shown}", err=True)


ROS_ARGS = {"allow_extra_args": True, "ignore_unknown_options": True}


def _ros_ready(command: str) -> None:
    """ROS importable and its master reachable, or a clear exit 1."""
    from .ros.connect import RosUnavailable, require_master, require_ros

    try:
        require_ros()
        require_master()
    except RosUnavailable as e:
        raise fail(f"baxterface {command}: {e}") from None


def _split_ros_args(words: List[str]) -> tuple:
    """ROS remappings and private parameters (name:=value) apart from the rest."""
    ros = [w for w in words if ":=" in w]
    return [w for w in words if ":=" not in w], ros


@app.command(context_settings=ROS_ARGS)
def node(ctx: typer.Context) -> None:
    """Run the face node on ROS: the replacement for the old screen_listener.py.

    Takes ROS remappings and private parameters as arguments:
    display_chatter:=/other, _fps:=30, _size:=1920x1200, _theme:=DIR,
    _idle:=false, _selftest:=true, _display_topic:=/robot/head_display,
    _audio:=soundplay|local|none, _camera:=/cameras/head_camera/image,
    _camera_hfov:=76 (degrees). Commands (old or new) arrive on
    display_chatter and take over at once; scripts sent to ~queue wait for
    what is playing. Frames go to /robot/xdisplay (bgr8), speech to
    sound_play on /robotsound, what the face is doing to ~state (JSON).
    """
    _ros_ready("node")
    from .ros.node import run_node
    from .theme import ThemeError

    try:
        code = run_node(["baxterface_node", *ctx.args])
    except ThemeError as e:
        raise fail(f"baxterface node: {e}") from None
    except ValueError as e:
        raise fail(f"baxterface node: {e}") from None
    raise typer.Exit(code)


@app.command(context_settings=ROS_ARGS)
def buttons(
    ctx: typer.Context,
    mapping: Optional[str] = typer.Option(None, "--mapping", metavar="FILE", help="Your own mapping (JSON)."),
) -> None:
    """Turn Baxter's navigator buttons into face commands on display_chatter.

    By default: torso OK toggles enable/disable; the left arm's button above
    the wheel wakes the face, below puts it to sleep; the right arm's buttons
    toggle dynamic left/right arm following; the left wheel scrolls through the
    emotions while awake. The mapping is a small JSON file (see docs/ros.md).
    """
    from .buttons import ButtonMap, MappingError

    try:
        button_map = ButtonMap.load(mapping)
    except MappingError as e:
        raise fail(f"baxterface buttons: {e}") from None
    _ros_ready("buttons")
    from .ros.buttons import run_buttons

    raise typer.Exit(run_buttons(button_map, ["baxterface_buttons", *ctx.args]))


@app.command(context_settings=ROS_ARGS)
def send(
    ctx: typer.Context,
    words: Optional[List[str]] = typer.Argument(
        None, metavar="COMMAND...", help="The command: happy, or look 40 -20 in 1s."
    ),
    file: Optional[str] = typer.Option(
        None, "-f", "--file", metavar="FILE", help="Send a script file instead."
    ),
    topic: str = typer.Option("display_chatter", "--topic", help="The face node's command topic."),
    queue: bool = typer.Option(
        False, "--queue", help="Play after what is playing (the node's ~queue topic)."
    ),
    timeout: float = typer.Option(5.0, "--timeout", min=0.1, help="Seconds to wait for the face node."),
) -> None:
    """Send a command or script to a running face node, checked first.

    A bad script gets the same diagnostics as 'check' and is not sent. With
    no face node listening within --timeout, it says so (exit 1).
    """
    text_words, ros_args = _split_ros_args(list(words or []) + list(ctx.args))
    if file is not None and text_words:
        raise fail("baxterface send: give a COMMAND or -f FILE, not both", 2)
    if file is None and not text_words:
        raise fail("baxterface send: nothing to send; give a COMMAND or -f FILE", 2)
    script = script_from(file, None, "send") if file is not None else None
    text = script.source if script is not None else " ".join(text_words)
    if script is None:
        try:
            parse(text, "<command>")
        except ScriptError as e:
            raise fail(e.render()) from None
    _ros_ready("send")
    from .ros.send import NoSubscriber
    from .ros.send import send as send_text

    try:
        send_text(text, "baxter_face/queue" if queue else topic, timeout, ["baxterface_send", *ros_args])
    except NoSubscriber as e:
        raise fail(f"baxterface send: {e}") from None


@app.command(context_settings=ROS_ARGS)
def stream(
    ctx: typer.Context,
    script_path: Optional[str] = SCRIPT_ARG,
    inline: Optional[str] = INLINE_OPT,
    robot: str = typer.Option(
        "baxter", "--robot", help="baxter (/robot/xdisplay) or sawyer (/robot/head_display)."
    ),
    fps: float = typer.Option(30.0, "--fps", min=1.0, max=60.0, help=FPS_HELP),
    size: Optional[str] = SIZE_OPT,
    seed: Optional[int] = RANDOM_SEED_OPT,
    theme: Optional[str] = THEME_OPT,
    idle: bool = IDLE_ON_OPT,
    crossfade: Optional[float] = CROSSFADE_OPT,
    audio: str = typer.Option(
        "soundplay",
        "--audio",
        help="Where speech goes: soundplay (sound_play on /robotsound, on this machine), "
        "local (this machine's sound device) or none.",
    ),
) -> None:
    """Stream a script to the robot's screen in real time, no face node needed.

    Frames are drawn here and published as bgr8, with the script's head, nod
    and enable commands and its speech at their times.
    """
    from .ros.robot_link import AUDIO_CHOICES, DISPLAY_TOPICS, SPEAKERS

    if robot not in DISPLAY_TOPICS:
        raise fail(f"baxterface stream: --robot must be {' or '.join(DISPLAY_TOPICS)}, not {robot!r}", 2)
    if audio not in SPEAKERS:
        raise fail(f"baxterface stream: --audio must be {AUDIO_CHOICES}, not {audio!r}", 2)
    script = script_from(script_path, inline, "stream")
    renderer_layers = fitted_theme(theme, size, "stream")
    _ros_ready("stream")
    from .renderer import Renderer
    from .ros.send import stream as stream_to

    animation = animation_for(script, seed, idle, crossfade)
    played = stream_to(
        animation, Renderer(renderer_layers), robot, fps, ["baxterface_stream", *ctx.args], audio=audio
    )
    typer.echo(f"streamed {animation.duration:.2f} s of script in {played:.2f} s", err=True)


def _watcher(path: str, seed: Optional[int], idle: bool, crossfade: Optional[float], player):
    """A poll function: a new animation when the file changed and parses, else None."""
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
        except ScriptError as e:
            first = e.diagnostics[0]
            player.note = f"kept the last good version: line {first.line}: {first.message}"
            return None
        player.note = ""
        return animation_for(script, seed, idle, crossfade)

    return poll


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
        echo_warnings(script)
        if ast:
            typer.echo(json.dumps(to_json(script), indent=2, sort_keys=True))
    if failed:
        raise typer.Exit(1)


@app.command()
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
    fps: float = typer.Option(30.0, "--fps", min=1.0, max=60.0, help="The preview's most frames a second."),
    seed: Optional[int] = RANDOM_SEED_OPT,
    theme: Optional[str] = THEME_OPT,
    idle: bool = IDLE_ON_OPT,
    topic: str = typer.Option(
        "display_chatter", "--topic", help="The face node's command topic, for presses sent to the robot."
    ),
) -> None:
    """Write, preview and perform the face from a web page.

    An editor with check's diagnostics as you type, a live preview drawn by
    the face's own renderer, and a button panel for live sessions whose
    presses play at once (and on the robot, when switched on) and export as
    a script that replays them. Serves on 127.0.0.1:8080 until Ctrl-C.
    """
    from .extras import need
    from .studio.panel import PanelError

    try:
        need("starlette", "studio", "the studio")
        need("uvicorn", "studio", "the studio")
    except MissingTool as e:
        raise fail(f"baxterface studio: {e}") from None
    from .renderer import Renderer
    from .studio.guard import is_loopback
    from .studio.server import bind, create_app, serve, url_for
    from .studio.workspace import Workspace

    path = Path(script_path or "studio.face")
    if path.is_dir():
        raise fail(f"baxterface studio: {path} is a folder; give a script file", 2)
    if not path.parent.resolve().is_dir():
        raise fail(f"baxterface studio: no folder {path.parent} to keep {path.name} in", 2)
    renderer = Renderer(fitted_theme(theme, size, "studio"))
    try:
        workspace = Workspace(path, Path(panel) if panel else None, seed, idle, topic=topic)
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
    served = create_app(workspace, renderer, fps, token)

    def ready() -> None:
        typer.echo(f"baxterface studio: {url}  editing {path}{made}; Ctrl-C stops", err=True)
        if not no_browser:
            import webbrowser

            webbrowser.open(url)

    stopped_by = serve(served, sock, ready)
    if workspace.text != workspace.saved:
        typer.echo(
            f"baxterface studio: stopped; the editor's last changes to {path.name} were not saved", err=True
        )
    else:
        typer.echo("baxterface studio: stopped", err=True)
    if stopped_by is not None:  # the shell's convention: 128 + the signal (130 for Ctrl-C)
        raise typer.Exit(128 + stopped_by)


@app.command()
def voices(
    query: Optional[str] = typer.Argument(
        None,
        metavar="[LANGUAGE]",
        help="Only these: a voice name and those under it (en), or a language (spanish).",
    ),
) -> None:
    """List the voices `say ... voice NAME` takes (espeak-ng's), with the language each speaks."""
    from .voices import matching_voices, voice_languages

    found = matching_voices(query) if query else list(voice_languages().items())
    if not found:
        raise fail(f"baxterface voices: no voice speaks {query!r}; 'baxterface voices' lists them all")
    width = max(len(name) for name, _ in found)
    for name, language in found:
        typer.echo(f"{name:<{width}}  {language}")


theme_app = typer.Typer(
    help="Themes: the face's layer images. Export the default one to edit, check your own.",
    no_args_is_help=True,
)
app.add_typer(theme_app, name="theme")


def _size(text: Optional[str]) -> Optional[tuple]:
    from .theme import parse_size

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
    if not folder:  # Path("") is the current folder
        raise typer.BadParameter("is empty; give a folder (./ for this one)", param_hint="DIR")
    from .theme import Theme, ThemeError

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
    from .theme import Theme, ThemeError

    try:
        theme = Theme.load(folder)
        theme.layers(theme.size)
    except ThemeError as e:
        typer.echo(f"baxterface: {e}", err=True)
        raise typer.Exit(1) from None


def _terminate(signum: int, frame: object) -> None:
    # Unwind like Ctrl-C, so half-written output is removed on the way out.
    raise SystemExit(128 + signum)


def main(argv: Optional[List[str]] = None) -> None:
    """Entry point: run the app, never showing a user a Python traceback."""
    signal.signal(signal.SIGTERM, _terminate)
    try:
        app(args=argv, prog_name="baxterface")
    except Exception as e:  # a bug of ours: say so in one line
        if os.environ.get("BAXTERFACE_DEBUG"):
            raise
        typer.echo(f"baxterface: internal error: {e!r} (BAXTERFACE_DEBUG=1 shows where)", err=True)
        sys.exit(2)
