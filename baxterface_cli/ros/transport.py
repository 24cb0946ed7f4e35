"""How ROS 2 moves the face's frames: Fast DDS's shared memory sized for a frame, unless the user chose.

rmw_fastrtps's own set-up gives shared memory 512 KB segments, so a 1.8 MB
frame crosses in pieces (15 ms at the median on a quiet machine, 28 ms
loaded); with 8 MB segments it crosses whole (5 ms). `shm` loads a Fast DDS
profile shipped here (fastdds_shm.xml) that keeps UDP beside the larger
shared memory, so peers with nothing set, peers with
ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST and peers on other hosts still meet
the process (at UDP's speed for the last). Under LOCALHOST the profile is
fastdds_shm_localhost.xml, which does what rmw_fastrtps does for LOCALHOST
(UDP on 127.0.0.1 only), and the process itself runs with SUBNET: with
LOCALHOST, rmw_fastrtps would add its own transports beside the profile's.

The choice is made once a process: Fast DDS reads its profile when the
process's first participant is made. What the user set wins: their own
profile or transports (FASTDDS_DEFAULT_PROFILES_FILE,
FASTRTPS_DEFAULT_PROFILES_FILE, FASTDDS_BUILTIN_TRANSPORTS, a
DEFAULT_FASTDDS_PROFILES.xml here) or another middleware (RMW_IMPLEMENTATION)
leave everything as it is. The environment is set only while the link joins,
then given back, so programs this process starts make their own choice.
"""

from __future__ import annotations

import contextlib
import os
from pathlib import Path
from typing import Dict, Iterator, List, Optional, Sequence

TRANSPORTS = ("shm", "default")
DEFAULT = "shm"
CHOICE_ENV = "BAXTERFACE_ROS_TRANSPORT"  # for programs of ours without a --ros-transport option
PARAMETER = "transport"  # the face node's parameter
HERE = Path(__file__).resolve().parent
PROFILES = {False: HERE / "fastdds_shm.xml", True: HERE / "fastdds_shm_localhost.xml"}
THEIRS = ("FASTDDS_DEFAULT_PROFILES_FILE", "FASTRTPS_DEFAULT_PROFILES_FILE", "FASTDDS_BUILTIN_TRANSPORTS")
FAST_DDS = ("rmw_fastrtps_cpp", "rmw_fastrtps_dynamic_cpp")
CHOICES = "shm or default"

_asked: Optional[str] = None  # the command line's --ros-transport
_chosen: Optional[Dict[str, str]] = None  # what this process's first link set up, and its words


class TransportError(ValueError):
    """A transport that is neither `shm` nor `default`; `where` it was given, and the `problem`."""

    def __init__(self, where: str, problem: str) -> None:
        super().__init__(f"{where} {problem}")
        self.where, self.problem = where, problem


def check(mode: str, where: str) -> str:
    if mode not in TRANSPORTS:
        raise TransportError(where, f"must be {CHOICES}, not {mode[:40]!r}")
    return mode


def ask(mode: Optional[str]) -> None:
    """The command line's choice (--ros-transport), for every ROS 2 link this process opens."""
    global _asked
    _asked = None if mode is None else check(mode, "--ros-transport")


def from_ros_args(argv: Sequence[str]) -> Optional[str]:
    """The node's `transport` parameter, given as `-p transport:=...` or in a `--params-file`, read
    before ROS starts: Fast DDS takes its transports when the node's participant is made."""
    found = None
    words = list(argv)
    for i, word in enumerate(words[:-1]):
        following = words[i + 1]
        if word in ("-p", "--param") and following.startswith(PARAMETER + ":="):
            found = following.split(":=", 1)[1]
        elif word == "--params-file":
            found = _from_params_file(following) or found
    return None if found is None else check(found.strip("'\""), f"parameter {PARAMETER}")


def _from_params_file(path: str) -> Optional[str]:
    try:
        import yaml  # rclpy's own dependency
    except ImportError:
        return None
    try:
        with open(path, encoding="utf-8") as f:
            tree = yaml.safe_load(f)
    except (OSError, UnicodeDecodeError, yaml.YAMLError):  # rclpy says what is wrong with it
        return None
    for params in (tree or {}).values() if isinstance(tree, dict) else ():
        values = params.get("ros__parameters") if isinstance(params, dict) else None
        if isinstance(values, dict) and PARAMETER in values:
            return str(values[PARAMETER])
    return None


def requested(argv: Sequence[str] = ()) -> str:
    """The transport asked for: --ros-transport, else the node's parameter, else
    BAXTERFACE_ROS_TRANSPORT, else shm. TransportError for anything else."""
    if _asked is not None:
        return _asked
    given = from_ros_args(argv)
    if given is not None:
        return given
    env = os.environ.get(CHOICE_ENV, "").strip()
    return check(env, CHOICE_ENV) if env else DEFAULT


def _theirs(env: Dict[str, str], cwd: str) -> Optional[str]:
    """What the user set that decides the transport, in words; None if nothing."""
    rmw = env.get("RMW_IMPLEMENTATION", "").strip()
    if rmw and rmw not in FAST_DDS:
        return f"RMW_IMPLEMENTATION is {rmw}"
    for name in THEIRS:
        if env.get(name, "").strip():
            return f"{name} is set"
    skip = env.get("SKIP_DEFAULT_XML_FILE", "") == "1"
    if not skip and os.path.isfile(os.path.join(cwd, "DEFAULT_FASTDDS_PROFILES.xml")):
        return "DEFAULT_FASTDDS_PROFILES.xml is in the working folder"
    return None


def plan(mode: str, env: Dict[str, str], cwd: str) -> Dict[str, str]:
    """The variables to set for `mode` in environment `env`, and under "" what to log."""
    if mode == "default":
        return {"": "default (ROS's own Fast DDS set-up)"}
    theirs = _theirs(env, cwd)
    if theirs is not None:
        return {"": f"default: yours ({theirs})"}
    scope = env.get("ROS_AUTOMATIC_DISCOVERY_RANGE", "").strip().upper()
    if not scope and env.get("ROS_LOCALHOST_ONLY", "").strip() == "1":
        scope = "LOCALHOST"
    local = scope == "LOCALHOST"
    out = {"FASTDDS_DEFAULT_PROFILES_FILE": str(PROFILES[local])}
    if local:  # the profile keeps the process on this host, as LOCALHOST would
        out["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "SUBNET"
        out["ROS_LOCALHOST_ONLY"] = ""
    reach = "this host only" if local else "UDP beside it"
    out[""] = f"shm (Fast DDS shared memory, 8 MB segments; {reach})"
    return out


@contextlib.contextmanager
def environment(argv: Sequence[str] = ()) -> Iterator[str]:
    """Set the transport's variables while a ROS 2 link joins, and give them back after; yields
    the words for the log. The first link of a process decides for all of them."""
    global _chosen
    if _chosen is None:
        _chosen = plan(requested(argv), dict(os.environ), os.getcwd())
    saved: List[tuple] = [(name, os.environ.get(name)) for name in _chosen if name]
    try:
        for name, value in _chosen.items():
            if not name:
                continue
            if value:
                os.environ[name] = value
            else:
                os.environ.pop(name, None)
        yield _chosen[""]
    finally:
        for name, value in saved:
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value
