"""`baxterface state`: what the face is doing, from a face node on ROS or a running screen or studio."""

from __future__ import annotations

import json
import threading
from typing import Any, Dict, List, Optional

import typer

from .app import fail
from .finite_numbers import finite
from .ros_commands import (
    ROS_OPT,
    TRANSPORT_OPT,
    check_transport,
    chosen_ros_version,
    ros_ready,
    split_ros_args,
)
from .web_client import TOKEN_OPT, call, url_option

STATE_TOPIC = "/baxter_face/state"  # the face node's ~state


def state(
    ctx: typer.Context,
    url: Optional[str] = url_option(
        "A running screen or studio, as it printed its address (http://127.0.0.1:8081/, with "
        "its ?token= if it has one), instead of a face node on ROS."
    ),
    token: Optional[str] = TOKEN_OPT,
    as_json: bool = typer.Option(False, "--json", help="Print the state as JSON, as it came."),
    topic: str = typer.Option(
        STATE_TOPIC, "--topic", metavar="TOPIC", help="The face node's state topic, on ROS."
    ),
    timeout: float = typer.Option(
        10.0, "--timeout", metavar="SECONDS", min=0.1, callback=finite, help="How long to wait for an answer."
    ),
    ros: Optional[int] = ROS_OPT,
    ros_transport: Optional[str] = TRANSPORT_OPT,
) -> None:
    """Print what the face is doing: its emotion, eyes, whether it plays and what it says.

    By default it reads the face node's state on ROS (~state, which the node
    keeps for late readers); with --url, a screen's or a studio's GET
    /api/state. One readable line, or the JSON itself with --json. Exit
    status 1 when there is no answer within --timeout.
    """
    if url is not None:
        found = _from_web(url, token, timeout)
    else:
        version = chosen_ros_version("state", ros)
        _, ros_args = split_ros_args(list(ctx.args), version, "state")
        check_transport("state", version, ros_transport)
        ros_ready("state", version)
        found = _from_ros(version, topic, timeout, ros_args)
    typer.echo(json.dumps(found, sort_keys=True) if as_json else readable(found))


def _from_web(url: str, token: Optional[str], timeout: float) -> Dict[str, Any]:
    found = call("state", url, token, "/api/state", timeout)
    if "script" in found and isinstance(found.get("status"), dict):  # a studio: its preview's status
        return found["status"]
    return found


def _from_ros(version: int, topic: str, timeout: float, ros_args: List[str]) -> Dict[str, Any]:
    from ..ros.connect import RosUnavailable, open_link

    heard: List[str] = []
    came = threading.Event()

    def take(message: Any) -> None:
        if not came.is_set():
            heard.append(message.data)
            came.set()

    try:
        link = open_link(version, "baxterface_state", ros_args, anonymous=True, leaving="read")
    except RosUnavailable as e:
        raise fail(f"baxterface state: {e}") from None
    with link:
        subscription = link.subscribe(topic, "std_msgs/String", take, queue=1, latched=True)
        came.wait(timeout)
        subscription.close()
        where = link.resolve(topic)
    if not heard:
        raise fail(f"baxterface state: nothing on {where} within {timeout:g} s: is the face node running?")
    try:
        found = json.loads(heard[0])
        if not isinstance(found, dict):
            raise ValueError("not a JSON object")
    except ValueError as e:
        raise fail(f"baxterface state: {where} did not carry a face's state: {e}") from None
    return found


def readable(found: Dict[str, Any]) -> str:
    """One line a person reads: `happy (skin 2, mouth teeth, brows normal); eyes 4.5 -4.4; ...`.

    The face node's state has the face's fields at its top; a screen's and a studio's under `face`.
    """
    face = found.get("face") if isinstance(found.get("face"), dict) else found
    robot = found.get("robot") if isinstance(found.get("robot"), dict) else {}
    parts = [
        f"{face.get('emotion') or 'no emotion'} (skin {face.get('skin')}, mouth {face.get('mouth')}, "
        f"brows {face.get('brows')})",
        f"eyes {_number(face.get('eye_x'))} {_number(face.get('eye_y'))}, "
        f"lids {_number(face.get('eyelids'))}",
        "playing" if found.get("playing") else "still",
    ]
    saying = found.get("saying") or robot.get("saying")
    if saying:
        parts.append(f"saying {str(saying)[:80]!r}")
    following = found.get("following") or robot.get("following")
    if following:
        parts.append(f"following {following}")
    if found.get("queued"):
        parts.append(f"{found['queued']} queued")
    if found.get("state"):
        parts.append(f"in state {found['state']}")
    if found.get("running"):
        parts.append(f"running {found['running']}")
    return "; ".join(parts)


def _number(value: Any) -> str:
    return f"{value:g}" if isinstance(value, (int, float)) else "?"
