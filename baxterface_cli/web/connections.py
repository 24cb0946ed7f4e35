"""Connections that cannot use up the server: a deadline for a request's head, a cap, a quiet log.

A connection that never sends its request's head (a half-open one, or one
that sends a byte now and then) is closed HEAD_TIMEOUT seconds after it
opened, or after its last answer. The server holds at most `most()`
connections, fewer than the files the process may open: past that, a new
connection closes the oldest one still waiting for its head (so a flood of
silent connections crowds out only itself, and whoever sends a request is
answered), or, when every one is busy (pages, requests being answered), is
closed itself. Running out of files all the same is logged once a second,
not once a try (asyncio's accept loop tries thousands of times a second).
"""

from __future__ import annotations

import errno
import time
from collections import OrderedDict
from typing import Any, Callable, Dict

HEAD_TIMEOUT = 10.0  # seconds a connection has to send a request's head
MOST_CONNECTIONS = 1000
FILES_KEPT = 128  # the process's own files (modules, fonts, sounds, worker threads), beside connections
LOG_EVERY = 1.0  # seconds between two lines about the same trouble
OUT_OF_FILES = (errno.EMFILE, errno.ENFILE, errno.ENOBUFS, errno.ENOMEM)


def most() -> int:
    """The most connections to hold: MOST_CONNECTIONS, or fewer when the process may open fewer files."""
    try:
        import resource
    except ImportError:  # not a Unix: no limit to read
        return MOST_CONNECTIONS
    soft, _ = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft == resource.RLIM_INFINITY:
        return MOST_CONNECTIONS
    return max(8, min(MOST_CONNECTIONS, soft - FILES_KEPT))


class EverySecond:
    """A log that writes a line of one kind at most once a second, with how many it left out."""

    def __init__(self, log: Callable[[str], None], every: float = LOG_EVERY) -> None:
        self.log, self.every = log, every
        self.last: Dict[str, float] = {}
        self.left_out: Dict[str, int] = {}

    def __call__(self, kind: str, message: str) -> None:
        now = time.monotonic()
        if now - self.last.get(kind, float("-inf")) < self.every:
            self.left_out[kind] = self.left_out.get(kind, 0) + 1
            return
        left_out = self.left_out.pop(kind, 0)
        self.last[kind] = now
        self.log(message + (f" ({left_out} more times since the last such line)" if left_out else ""))


class Connections:
    """The server's connections: `protocol()` is uvicorn's HTTP protocol with the rules above."""

    def __init__(self, log: Callable[[str], None], most_held: int = 0) -> None:
        self.most_held = most_held  # 0: as many as the files the process may open allow, asked each time
        self.say = EverySecond(log)
        # Connections waiting for a request's head, oldest first: the ones to close to make room.
        self.waiting: OrderedDict[Any, Any] = OrderedDict()

    def protocol(self) -> type:
        from uvicorn.protocols.http.h11_impl import H11Protocol

        connections = self

        class Protocol(H11Protocol):
            def connection_made(self, transport: Any) -> None:
                super().connection_made(transport)
                connections.await_head(self)
                if len(self.connections) > (connections.most_held or most()):
                    connections.make_room(self)

            def data_received(self, data: bytes) -> None:
                super().data_received(data)
                connections.head_maybe_in(self)

            def on_response_complete(self) -> None:
                super().on_response_complete()
                if not self.transport.is_closing() and _idle(self):  # kept alive: the next head is due
                    connections.await_head(self)

            def connection_lost(self, exc: Any) -> None:
                connections.forget(self)
                super().connection_lost(exc)

        return Protocol

    def await_head(self, protocol: Any) -> None:
        self.forget(protocol)
        self.waiting[protocol] = protocol.loop.call_later(HEAD_TIMEOUT, self.too_slow, protocol)

    def head_maybe_in(self, protocol: Any) -> None:
        if protocol in self.waiting and not _idle(protocol):
            self.forget(protocol)

    def forget(self, protocol: Any) -> None:
        timer = self.waiting.pop(protocol, None)
        if timer is not None:
            timer.cancel()

    def too_slow(self, protocol: Any) -> None:
        self.waiting.pop(protocol, None)
        protocol.transport.close()

    def make_room(self, newcomer: Any) -> None:
        """Too many connections: the oldest still waiting for its head goes, else the newcomer."""
        oldest = next((p for p in self.waiting if p is not newcomer), None)
        if oldest is None:
            self.say(
                "full",
                f"{len(newcomer.connections) - 1} connections open, all busy, the most this server "
                "holds: a new one was closed",
            )
            oldest = newcomer
        self.forget(oldest)
        oldest.connections.discard(oldest)  # counted out now; its transport closes at the next turn
        oldest.transport.close()

    def loop_exception(self, loop: Any, context: Dict[str, Any]) -> None:
        """The event loop's exception handler: out of files, once a second and with room made."""
        error = context.get("exception")
        if isinstance(error, OSError) and error.errno in OUT_OF_FILES:
            if self.waiting:
                self.too_slow(next(iter(self.waiting)))
            self.say("files", f"cannot take a connection: {error.strerror or error}; new ones wait")
            return
        loop.default_exception_handler(context)


def _idle(protocol: Any) -> bool:
    """Whether the client has not yet sent a whole request head (h11's state for it)."""
    import h11

    return protocol.conn.their_state is h11.IDLE
