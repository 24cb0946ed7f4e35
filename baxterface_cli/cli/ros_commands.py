"""The commands that talk to ROS: `node`, `buttons`, `send` and `stream`."""

from __future__ import annotations

import sys
from typing import List, Optional

import typer

from ..language.diagnostics import ScriptError
from ..language.parser import parse
from .app import (
    CROSSFADE_OPT,
    FPS_HELP,
    IDLE_ON_OPT,
    INLINE_OPT,
    RANDOM_SEED_OPT,
    SCRIPT_ARG,
    SIZE_OPT,
    THEME_OPT,
    animation_for,
    fail,
    fitted_theme,
    script_from,
)


def _ros_ready(command: str, images: bool = True) -> None:
    """ROS importable and its master reachable, or a clear exit 1."""
    from ..ros.connect import RosUnavailable, require_master, require_ros

    try:
        require_ros(images)
        require_master()
    except RosUnavailable as e:
        raise fail(f"baxterface {command}: {e}") from None


def _split_ros_args(words: List[str]) -> tuple:
    """ROS remappings and private parameters (name:=value) apart from the rest."""
    ros = [w for w in words if ":=" in w]
    return [w for w in words if ":=" not in w], ros


def node(ctx: typer.Context) -> None:
    """Run the face node on ROS: the replacement for the old screen_listener.py.

    Takes ROS remappings and private parameters as arguments:
    display_chatter:=/other, _fps:=30, _size:=1920x1200, _theme:=DIR,
    _idle:=false, _selftest:=true, _display_topic:=/robot/head_display,
    _audio:=soundplay|local|none, _camera:=/cameras/head_camera/image,
    _camera_hfov:=76 (degrees; by default the camera's camera_info says),
    _face_policy:=nearest|central|longest. Commands (old or new) arrive on
    display_chatter and take over at once; scripts sent to ~queue wait for
    what is playing. Frames go to /robot/xdisplay (bgr8), speech to
    sound_play on /robotsound, what the face is doing to ~state (JSON).
    """
    _ros_ready("node")
    from ..ros.face_node import run_node
    from ..ros.node_settings import SettingError

    try:
        code = run_node(["baxterface_node", *ctx.args])
    except SettingError as e:
        raise fail(f"baxterface node: {e}", 2) from None
    raise typer.Exit(code)


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
    from ..robot.navigator_buttons import ButtonMap, MappingError

    try:
        button_map = ButtonMap.load(mapping)
    except MappingError as e:
        raise fail(f"baxterface buttons: {e}") from None
    _ros_ready("buttons", images=False)
    from ..ros.buttons import run_buttons

    raise typer.Exit(run_buttons(button_map, ["baxterface_buttons", *ctx.args]))


def send(
    ctx: typer.Context,
    words: Optional[List[str]] = typer.Argument(
        None, metavar="COMMAND...", help="The command: happy, or look 40 -20 in 1s."
    ),
    file: Optional[str] = typer.Option(
        None, "-f", "--file", metavar="FILE", help="Send a script file instead."
    ),
    stdin: bool = typer.Option(
        False, "--stdin", help="Send each line of standard input as it comes, over one connection."
    ),
    topic: str = typer.Option("display_chatter", "--topic", help="The face node's command topic."),
    queue: bool = typer.Option(
        False, "--queue", help="Play after what is playing (the node's ~queue topic)."
    ),
    timeout: float = typer.Option(5.0, "--timeout", min=0.1, help="Seconds to wait for the face node."),
) -> None:
    """Send a command or script to a running face node, checked first.

    A bad script gets the same diagnostics as 'check' and is not sent. With
    no face node listening within --timeout, it says so (exit 1). With
    --stdin, each line is a command of its own: bad lines are reported with
    their line number and skipped, and the exit status is 1 if there were any.
    """
    text_words, ros_args = _split_ros_args(list(words or []) + list(ctx.args))
    if sum([file is not None, bool(text_words), stdin]) > 1:
        raise fail("baxterface send: give one of COMMAND, -f FILE or --stdin", 2)
    if file is None and not text_words and not stdin:
        raise fail("baxterface send: nothing to send; give a COMMAND, -f FILE or --stdin", 2)
    what = ""
    if file is not None:
        script = script_from(file, None, "send")
        text = script.source
        what = f"{script.filename} ({len(text.splitlines())} lines)"
    elif text_words:
        text = " ".join(text_words)
        try:
            parse(text, "<command>")
        except ScriptError as e:
            raise fail(e.render()) from None
        what = repr(text)
    _ros_ready("send", images=False)
    from ..ros.send import NoSubscriber, Sender, listeners

    try:
        with Sender("baxter_face/queue" if queue else topic, timeout, ["baxterface_send", *ros_args]) as out:
            if stdin:
                bad = _send_lines(out, sys.stdin)
                if bad:
                    raise fail(f"baxterface send: {bad} line{'s' if bad > 1 else ''} not sent")
                return
            typer.echo(f"sent {what} to {out.topic} ({listeners(out.send(text))})", err=True)
    except NoSubscriber as e:
        raise fail(f"baxterface send: {e}") from None


def _send_lines(out, lines) -> int:
    """Check and send each line as it comes; how many were bad (reported, not sent)."""
    from ..ros.send import listeners

    bad = 0
    for number, line in enumerate(lines, 1):
        command = line.strip()
        if not command or command.startswith("#"):
            continue
        try:  # parsed where it stands, so that errors carry the line's number
            parse("\n" * (number - 1) + line.rstrip("\n"), "<stdin>")
        except ScriptError as e:
            typer.echo(e.render(), err=True)
            bad += 1
            continue
        typer.echo(f"sent {command!r} to {out.topic} ({listeners(out.send(command))})", err=True)
    return bad


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
    from ..ros.speakers import AUDIO_CHOICES, SPEAKERS
    from ..ros.wire import DISPLAY_TOPICS

    if robot not in DISPLAY_TOPICS:
        raise fail(f"baxterface stream: --robot must be {' or '.join(DISPLAY_TOPICS)}, not {robot!r}", 2)
    if audio not in SPEAKERS:
        raise fail(f"baxterface stream: --audio must be {AUDIO_CHOICES}, not {audio!r}", 2)
    script = script_from(script_path, inline, "stream")
    renderer_layers = fitted_theme(theme, size, "stream")
    _ros_ready("stream")
    from ..drawing.renderer import Renderer
    from ..ros.send import stream as stream_to

    animation = animation_for(script, seed, idle, crossfade)
    played = stream_to(
        animation, Renderer(renderer_layers), robot, fps, ["baxterface_stream", *ctx.args], audio=audio
    )
    typer.echo(f"streamed {animation.duration:.2f} s of script in {played:.2f} s", err=True)
