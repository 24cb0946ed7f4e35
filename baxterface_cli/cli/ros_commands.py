"""The commands that talk to ROS: `node`, `buttons`, `send` and `stream` (`--ros 1` or `--ros 2`)."""

from __future__ import annotations

import os
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
    fail,
    fitted_theme,
    recordings_of,
    script_from,
)
from .events_option import BARGE_IN_OPT, DURATION_OPT, LISTEN_OPT, phrases_wanted
from .finite_numbers import finite
from .log_option import LOG_OPT, LOG_SIZE_OPT, log_file
from .web_client import TOKEN_OPT, url_option

ROS_OPT = typer.Option(
    None,
    "--ros",
    metavar="1|2",
    help="The ROS version: 1 (rospy) or 2 (rclpy). Default: the ROS_VERSION of a sourced ROS, else the "
    "one this Python can import (1 if both or neither).",
)

TRANSPORT_OPT = typer.Option(
    None,
    "--ros-transport",
    metavar="shm|default",
    help="ROS 2 only: how frames travel. shm (the default): Fast DDS's shared memory sized for a "
    "frame, beside UDP; default: ROS's own set-up. A Fast DDS profile or transports of your own "
    "(FASTDDS_DEFAULT_PROFILES_FILE, FASTDDS_BUILTIN_TRANSPORTS) always win. See docs/ros.md.",
)


def check_transport(command: str, version: int, given: Optional[str], ros_args: List[str] = ()) -> None:
    """The ROS 2 transport for this process's links, or a clear exit 2 for a bad one."""
    from ..ros import transport

    try:
        transport.ask(given)
        if version == 2:
            transport.requested(ros_args if command == "node" else ())
    except transport.TransportError as e:
        raise fail(f"baxterface {command}: {e}", 2) from None


def chosen_ros_version(command: str, given: Optional[int]) -> int:
    from ..ros.connect import importable_ros
    from ..ros.link import RosVersionError, ros_version

    if given is None and not os.environ.get("ROS_VERSION", "").strip() and importable_ros() == [2]:
        return 2  # a virtual environment with the ros2 extra and no ROS 1
    try:
        return ros_version(given)
    except RosVersionError as e:
        raise fail(f"baxterface {command}: {e}", 2) from None


def ros_ready(command: str, version: int = 1) -> None:
    """ROS importable and (ROS 1) its master reachable, or a clear exit 1."""
    from ..ros.connect import RosUnavailable, require_master, require_ros

    try:
        require_ros(version)
        if version == 1:
            require_master()
    except RosUnavailable as e:
        raise fail(f"baxterface {command}: {e}") from None


def split_ros_args(words: List[str], version: int = 1, command: str = "send") -> tuple:
    """The command's own words apart from its ROS arguments: on ROS 1 each `name:=value`
    (remappings, `_private` parameters), on ROS 2 everything from `--ros-args` on."""
    if version == 1:
        return [w for w in words if ":=" not in w], [w for w in words if ":=" in w]
    cut = words.index("--ros-args") if "--ros-args" in words else len(words)
    own, ros = words[:cut], words[cut:]
    for word in own:
        if ":=" in word:  # ROS 1's spelling, which ROS 2 would silently ignore
            name, value = word.split(":=", 1)
            flag = "-p" if name.startswith("_") else "-r"
            raise fail(
                f"baxterface {command}: on ROS 2, ROS arguments come after --ros-args: "
                f"--ros-args {flag} {name.lstrip('_') if flag == '-p' else name}:={value}",
                2,
            )
    return own, ros


def node(
    ctx: typer.Context, ros: Optional[int] = ROS_OPT, ros_transport: Optional[str] = TRANSPORT_OPT
) -> None:
    """Run the face node on ROS 1 or ROS 2: the replacement for the old screen_listener.py.

    A SCRIPT given first plays once the node is up (its `script` parameter), as
    a script sent to ~queue does. Takes ROS remappings and the node's parameters
    as arguments. For example
    (these are not the defaults): on ROS 1, display_chatter:=/other _fps:=20;
    on ROS 2, --ros-args -r display_chatter:=/other -p fps:=20.

    \b
    Parameters (on ROS 1 with a leading _), and their defaults:
      fps            the most frames a second: 30
      size           WIDTHxHEIGHT of the screen: 1024x600 (upgraded heads: 1920x1200)
      theme          a theme folder (DIR): the built-in theme
      idle           true|false, idle blinks and eye darts: true
      selftest       true|false, flash every layer at start: false
      display_topic  where frames go: /robot/xdisplay (Sawyer: /robot/head_display)
      audio          soundplay|local|none: soundplay on ROS 1, local on ROS 2
      camera         the image topic 'follow face' uses: /cameras/head_camera/image
      camera_hfov    its field of view in DEGREES: its camera_info's, else 76
      face_policy    nearest|central|longest: nearest
      recordings     the FOLDER 'say file' may read: none (no recording is read)
      listen         words for 'on word': default (the microphone) or a WAV file: none
      barge_in       true|false, hear words while the face speaks: false
      script         a FILE to play once the node is up: none
      transport      ROS 2: shm|default, as --ros-transport: shm

    Commands (old or new) arrive on display_chatter and take over at once;
    scripts sent to ~queue wait for what is playing. Frames go to
    /robot/xdisplay (bgr8), speech to sound_play on /robotsound (ROS 1) or
    this machine's sound device (ROS 2), what the face is doing to ~state
    (JSON; 'baxterface state' reads it). See docs/ros.md.
    """
    version = chosen_ros_version("node", ros)
    words, ros_args = split_ros_args(list(ctx.args), version, "node")
    if len(words) > 1:
        raise fail(f"baxterface node: unexpected {words[1]!r}; give one SCRIPT at most", 2)
    if words:  # the node's `script` parameter, checked here first: its mistakes where they are
        script_from(words[0], None, "node")
        path = os.path.abspath(words[0])
        ros_args += [f"_script:={path}"] if version == 1 else _ros2_parameter(ros_args, f"script:={path}")
    check_transport("node", version, ros_transport, ros_args)
    ros_ready("node", version)
    from ..ros.connect import RosUnavailable
    from ..ros.face_node import run_node
    from ..ros.node_settings import SettingError

    try:
        code = run_node(ros_args, version)
    except SettingError as e:
        said = str(e) if version == 1 else f"parameter {e.name} {e.problem}"
        raise fail(f"baxterface node: {said}", 2) from None
    except RosUnavailable as e:
        raise fail(f"baxterface node: {e}") from None
    raise typer.Exit(code)


def _ros2_parameter(ros_args: List[str], setting: str) -> List[str]:
    """`-p NAME:=VALUE` after ROS 2's `--ros-args`, which `ros_args` may have already."""
    return (["--ros-args"] if "--ros-args" not in ros_args else []) + ["-p", setting]


def buttons(
    ctx: typer.Context,
    mapping: Optional[str] = typer.Option(None, "--mapping", metavar="FILE", help="Your own mapping (JSON)."),
) -> None:
    """Turn Baxter's navigator buttons into face commands on display_chatter.

    By default: torso OK toggles enable/disable; the left arm's button above
    the wheel wakes the face, below puts it to sleep; the right arm's buttons
    toggle dynamic left/right arm following; the left wheel scrolls through the
    emotions while awake. The mapping is a small JSON file: see "The navigator
    buttons" in docs/following.md.
    """
    from ..robot.navigator_buttons import ButtonMap, MappingError

    try:
        button_map = ButtonMap.load(mapping)
    except MappingError as e:
        raise fail(f"baxterface buttons: {e}") from None
    ros_ready("buttons")
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
    topic: str = typer.Option(
        "display_chatter", "--topic", metavar="TOPIC", help="The face node's command topic."
    ),
    queue: bool = typer.Option(
        False, "--queue", help="Play after what is playing (the node's ~queue topic)."
    ),
    timeout: float = typer.Option(
        5.0,
        "--timeout",
        metavar="SECONDS",
        min=0.1,
        callback=finite,
        help="How long to wait for the face node.",
    ),
    event: Optional[str] = typer.Option(
        None,
        "--event",
        metavar="EVENT",
        help="Raise an event instead, as an events file writes it without its time: 'button ok', "
        "'word \"hello\"', 'touch left eye'.",
    ),
    url: Optional[str] = url_option("With --event: a running screen or studio, as it printed its address."),
    token: Optional[str] = TOKEN_OPT,
    ros: Optional[int] = ROS_OPT,
    ros_transport: Optional[str] = TRANSPORT_OPT,
) -> None:
    """Send a command or script to a running face node, checked first.

    A bad script gets the same diagnostics as 'check' and is not sent. With
    no face node listening within --timeout, it says so (exit 1). With
    --stdin, each line is a command of its own: bad lines are reported with
    their line number and skipped, and the exit status is 1 if there were any.
    With --event, an event reaches the node's handlers (its ~event topic), or
    with --url a screen's or studio's, as the robot's or a tap would.
    What was sent is printed on standard output, problems on standard error.
    """
    if event is not None or url is not None:
        _send_event(event, url, token, timeout, words or [], file, stdin, queue, ctx.args, ros, ros_transport)
        return
    version = chosen_ros_version("send", ros)
    text_words, ros_args = split_ros_args(list(words or []) + list(ctx.args), version)
    if sum([file is not None, bool(text_words), stdin]) > 1:
        raise fail("baxterface send: give one of COMMAND, -f FILE or --stdin", 2)
    if file is None and not text_words and not stdin:
        raise fail("baxterface send: nothing to send; give a COMMAND, -f FILE or --stdin", 2)
    what = ""
    if file is not None:
        script = script_from(file, None, "send", recordings=False)  # the node reads its own
        text = script.source
        what = f"{script.filename} ({len(text.splitlines())} lines)"
    elif text_words:
        text = " ".join(text_words)
        try:
            parse(text, "<command>")
        except ScriptError as e:
            raise fail(e.render()) from None
        what = repr(text)
    check_transport("send", version, ros_transport)
    ros_ready("send", version)
    from ..ros.connect import RosUnavailable
    from ..ros.send import NoSubscriber, Sender, listeners

    try:
        with Sender("baxter_face/queue" if queue else topic, timeout, ros_args, version) as out:
            if stdin:
                bad = _send_lines(out, sys.stdin)
                if bad:
                    raise fail(f"baxterface send: {bad} line{'s' if bad > 1 else ''} not sent")
                return
            typer.echo(f"sent {what} to {out.topic} ({listeners(out.send(text))})")
    except (NoSubscriber, RosUnavailable) as e:
        raise fail(f"baxterface send: {e}") from None


def _send_event(event, url, token, timeout, words, file, stdin, queue, args, ros, ros_transport) -> None:
    """`send --event LINE`: to the node's ~event topic, or `--url`'s POST /api/event."""
    from ..language.event_line import read_event_line

    if event is None:
        raise fail("baxterface send: --url goes with --event", 2)
    if words or file is not None or stdin or queue:
        raise fail("baxterface send: give --event or a command, not both", 2)
    try:
        read_event_line(event, "<event>")
    except ScriptError as e:
        raise fail(e.render()) from None
    if url is not None:
        from .web_client import call

        done = call("send", url, token, "/api/event", timeout, body=event)
        counts = ", ".join(f"{done.get(k, 0)} {k}" for k in ("runs", "dropped", "queued"))
        typer.echo(f"raised {done.get('event', event)!r} at {url} ({counts})")
        return
    version = chosen_ros_version("send", ros)
    _, ros_args = split_ros_args(list(args), version)
    check_transport("send", version, ros_transport)
    ros_ready("send", version)
    from ..ros.connect import RosUnavailable
    from ..ros.link import NODE_NAME
    from ..ros.send import NoSubscriber, Sender, listeners

    try:
        with Sender(f"{NODE_NAME}/event", timeout, ros_args, version) as out:
            typer.echo(f"sent event {event!r} to {out.topic} ({listeners(out.send(event))})")
    except (NoSubscriber, RosUnavailable) as e:
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
        typer.echo(f"sent {command!r} to {out.topic} ({listeners(out.send(command))})")
    return bad


def stream(
    ctx: typer.Context,
    script_path: Optional[str] = SCRIPT_ARG,
    inline: Optional[str] = INLINE_OPT,
    robot: str = typer.Option(
        "baxter", "--robot", help="baxter (/robot/xdisplay) or sawyer (/robot/head_display)."
    ),
    fps: float = typer.Option(30.0, "--fps", min=1.0, max=60.0, callback=finite, help=FPS_HELP),
    size: Optional[str] = SIZE_OPT,
    seed: Optional[int] = RANDOM_SEED_OPT,
    theme: Optional[str] = THEME_OPT,
    idle: bool = IDLE_ON_OPT,
    crossfade: Optional[float] = CROSSFADE_OPT,
    audio: Optional[str] = typer.Option(
        None,
        "--audio",
        help="Where speech goes: soundplay (sound_play on /robotsound, on this machine; the default "
        "on ROS 1), local (this machine's sound device; the default on ROS 2) or none.",
    ),
    duration: Optional[float] = DURATION_OPT,
    listen: bool = LISTEN_OPT,
    barge_in: bool = BARGE_IN_OPT,
    ros: Optional[int] = ROS_OPT,
    ros_transport: Optional[str] = TRANSPORT_OPT,
    log: Optional[str] = LOG_OPT,
    log_size: float = LOG_SIZE_OPT,
) -> None:
    """Stream a script to the robot's screen in real time, no face node needed.

    Frames are drawn here and published as bgr8, with the script's head, nod
    and enable commands and its speech at their times. It runs as the face node
    runs a script, on the same live session, with the robot's events (navigators,
    cuffs, sonar, camera, 'signal NAME' on display_chatter, words with --listen),
    until it has nothing left to do and no handlers, --duration T seconds, or Ctrl-C.
    """
    from ..ros.effect_messages import DISPLAY_TOPICS
    from ..ros.speakers import AUDIO_CHOICES, SPEAKERS
    from ..speech.warm_start import start_in_background

    version = chosen_ros_version("stream", ros)
    _, ros_args = split_ros_args(list(ctx.args), version, "stream")

    if robot not in DISPLAY_TOPICS:
        raise fail(f"baxterface stream: --robot must be {' or '.join(DISPLAY_TOPICS)}, not {robot!r}", 2)
    if audio is not None and audio not in SPEAKERS:
        raise fail(f"baxterface stream: --audio must be {AUDIO_CHOICES}, not {audio!r}", 2)
    log_file(log, log_size, "stream")  # a bad size said before ROS starts
    script = script_from(script_path, inline, "stream")
    start_in_background()  # the speech process starts as the theme is fitted: no `say` waits for it
    renderer_layers = fitted_theme(theme, size, "stream")
    if listen:
        phrases_wanted(script, "stream", "--listen")
    check_transport("stream", version, ros_transport)
    ros_ready("stream", version)
    from ..drawing.renderer import Renderer

    options = dict(seed=seed, idle=idle, recordings=recordings_of(script), crossfade=crossfade)
    renderer = Renderer(renderer_layers)
    logged = dict(log=os.path.abspath(log) if log else None, log_size=log_size)
    _stream_live(
        script, renderer, robot, fps, ros_args, audio, version, duration, listen, barge_in, options, logged
    )


def _stream_live(
    script, renderer, robot, fps, ros_args, audio, version, duration, listen, barge_in, options, logged
):
    from ..extras import MissingTool
    from ..ros.connect import RosUnavailable
    from ..ros.live_stream import Deaf, stream_live
    from ..ros.speakers import UnknownAudio

    try:
        ran = stream_live(
            script,
            renderer,
            robot,
            fps,
            ros_args,
            audio,
            version,
            duration,
            listen,
            barge_in,
            options,
            **logged,
        )
    except UnknownAudio as e:
        raise fail(f"baxterface stream: {e}", 2) from None
    except Deaf as e:
        raise fail(f"baxterface stream: --listen: {e}") from None
    except (RosUnavailable, MissingTool) as e:
        raise fail(f"baxterface stream: {e}") from None
    except ScriptError as e:
        raise fail(e.render()) from None
    if duration is not None:  # it stops at the first frame at or past the duration: it ran that long
        ran = min(ran, duration)
    typer.echo(f"streamed {ran:.2f} s", err=True)
