"""Serving a face page, the studio's or the screen's: a listening socket, uvicorn until Ctrl-C or
SIGTERM, the address, and the lines it logs.

The application is a `FaceApi`'s (face_api.py; studio/api.py and screen/screen_api.py extend it);
the frame pump is frame_pump.py's. Connections are kept from using up the process's files (connections.py).
"""

from __future__ import annotations

import sys
import threading
from typing import Any, Callable, Optional

from .connections import Connections
from .pages import page_protocol

_WRITING = threading.Lock()


def _stderr(message: str) -> None:
    """`message` and its newline in one write: the frame pump, the ROS listener and the server's
    threads log side by side, and print's two writes (the text, then the newline) once joined two
    lines into one."""
    stream = sys.stderr
    if stream is None:  # no standard error at all (pythonw): nowhere to log
        return
    with _WRITING:
        stream.write(message + "\n")
        stream.flush()


def logger(command: str) -> Callable[[str], None]:
    """One line on standard error, named after the command that serves: `baxterface studio: ...`."""

    def log(message: str) -> None:
        _stderr(f"baxterface {command}: {message}")

    return log


def serve(
    app: Any,
    sock: Any,
    ready: Callable[[], None],
    stopping: Callable[[], None] = lambda: None,
    log: Callable[[str], None] = _stderr,
) -> Optional[int]:
    """Run `app` on the bound socket until Ctrl-C or SIGTERM; returns the signal that stopped it.

    `ready` is called once the server answers, `stopping` as it begins to stop. A signal never
    interrupts the set-up (under Python 3.8, Ctrl-C inside logging's set-up broke a lock): one
    that comes before uvicorn takes the signals over is kept, and stops the
    server as soon as it is up; uvicorn hands back the ones it caught the same way.
    `log` takes the server's own lines (connections refused or out of files, once a second).
    """
    import asyncio
    import signal

    import uvicorn

    # The frame pump waits for the GIL behind threads that parse scripts; each wait may last a
    # whole switch interval (5 ms by default), several times a frame. As the face node does.
    sys.setswitchinterval(0.001)

    stops: list = []

    def keep(signum: int, frame: Any) -> None:
        stops.append(signum)

    handled = (signal.SIGINT, signal.SIGTERM)
    before = {signum: signal.signal(signum, keep) for signum in handled}

    connections = Connections(log)

    class Server(uvicorn.Server):
        async def startup(self, sockets: Any = None) -> None:
            asyncio.get_running_loop().set_exception_handler(connections.loop_exception)
            await super().startup(sockets=sockets)
            if stops:
                self.should_exit = True
            elif not self.should_exit:
                ready()

        async def shutdown(self, sockets: Any = None) -> None:
            stopping()
            await super().shutdown(sockets=sockets)

    try:
        config = uvicorn.Config(
            app,
            log_level="warning",
            lifespan="off",
            ws_max_size=4 * 1024 * 1024,
            # The frames are JPEG, which deflate does not shrink; and they are written to the pages
            # as they are, framed once for all (pages.py).
            ws_per_message_deflate=False,
            http=connections.protocol(),
            ws=page_protocol(),
        )
        Server(config).run(sockets=[sock])
    finally:
        for signum, handler in before.items():
            signal.signal(signum, handler)
    return stops[0] if stops else None


def bind(host: str, port: int) -> Any:
    """A listening socket on host:port (port 0: any free one); OSError when it is taken."""
    import socket

    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    # Frames go out at once, not held back for the page's acknowledgement (Nagle's delay);
    # the connections accepted inherit it.
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    try:
        sock.bind((host, port))
    except OSError:
        sock.close()
        raise
    sock.set_inheritable(True)
    return sock


def this_machine() -> str:
    """This machine's address on its network (where its default route leaves), else its name."""
    import socket

    try:
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
            probe.connect(("192.0.2.1", 9))  # a documentation address: connecting UDP sends nothing
            address = probe.getsockname()[0]
    except OSError:  # no route at all
        address = ""
    return address if address and not address.startswith(("127.", "0.")) else socket.gethostname()


def url_for(host: str, port: int, token: Optional[str]) -> str:
    """The address to open; serving on every address, the one the lab's other machines reach."""
    if host in ("0.0.0.0", "::", ""):
        host = this_machine()
    shown = f"[{host}]" if ":" in host else host
    return f"http://{shown}:{port}/" + (f"?token={token}" if token else "")
