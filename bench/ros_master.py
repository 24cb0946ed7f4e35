"""A roscore of a benchmark's own, on a free loopback port."""

from __future__ import annotations

import os
import socket
import subprocess
import time
from typing import Dict, Optional, Tuple


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start_roscore(home: Optional[str] = None) -> Tuple[subprocess.Popen, Dict[str, str]]:
    """A roscore that answers, and the environment that reaches it; SIGINT it when done."""
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI=f"http://127.0.0.1:{port}", ROS_IP="127.0.0.1")
    env.pop("ROS_HOSTNAME", None)
    if home is not None:
        env["ROS_HOME"] = home
    core = subprocess.Popen(
        ["roscore", "-p", str(port)], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
    )
    while subprocess.run(["rosnode", "list"], env=env, capture_output=True).returncode != 0:
        if core.poll() is not None:
            raise RuntimeError("roscore did not start")
        time.sleep(0.2)
    return core, env
