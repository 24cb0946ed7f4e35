"""The open pages, each a WebSocket: what the frame pump sends is framed once and written to them all.

A frame of the face is a JPEG of some 40 KB. Sent through each page's ASGI connection, a frame
cost every page a queue, a task, a copy and, when the page asked for it, a deflate (which does not
shrink a JPEG): a command's frame reached the last of 500 pages 1.2 to 2.7 s later (p95). Here the
WebSocket message is built once and written straight to each page's transport, which the server
puts in the connection's scope (`page_protocol`). A page still sending the last frame skips to the
newest one once it has sent it, at the pump's next turn; messages (status, changes on disk) are
never skipped; a page that has read nothing for `MOST_BUFFERED` bytes is closed (it opens again by
itself).
"""

from __future__ import annotations

import json
from typing import Any, Dict, Optional, Set

TRANSPORT = "baxterface.transport"  # the key of a page's transport in its scope's extensions
MOST_BUFFERED = 4 * 1024 * 1024  # bytes waiting to go to one page before it is closed
BINARY, TEXT = 0x2, 0x1


def message(opcode: int, payload: bytes) -> bytes:
    """A whole WebSocket message from the server (RFC 6455 5.2: final, unmasked)."""
    size = len(payload)
    if size < 126:
        head = bytes((0x80 | opcode, size))
    elif size < 1 << 16:
        head = bytes((0x80 | opcode, 126)) + size.to_bytes(2, "big")
    else:
        head = bytes((0x80 | opcode, 127)) + size.to_bytes(8, "big")
    return head + payload


def page_protocol() -> type:
    """uvicorn's WebSocket protocol, with the connection's transport in its ASGI scope."""
    from uvicorn.protocols.websockets.auto import AutoWebSocketsProtocol

    class PageProtocol(AutoWebSocketsProtocol):  # type: ignore[misc, valid-type]
        async def run_asgi(self) -> None:
            self.scope["extensions"][TRANSPORT] = self.transport
            await super().run_asgi()

    return PageProtocol


def transport_of(scope: Dict[str, Any]) -> Any:
    return scope["extensions"][TRANSPORT]


class Pages:
    """The pages open now, by their transports, and the newest frame (as a WebSocket message)."""

    def __init__(self) -> None:
        self.open: Set[Any] = set()
        self.owed: Set[Any] = set()  # pages the newest frame has not been written to yet
        self.frame: Optional[bytes] = None
        self.frames_sent = 0

    def add(self, transport: Any) -> None:
        """A page that has had its first frame and status (through its own connection)."""
        self.open.add(transport)

    def remove(self, transport: Any) -> None:
        self.open.discard(transport)
        self.owed.discard(transport)

    def send(self, item: Any) -> None:
        """A frame (bytes: a JPEG) or a message (a dict, sent as JSON text) to every page."""
        if isinstance(item, bytes):
            self.frame = message(BINARY, item)
            self.frames_sent += 1
            self.owed = set(self.open)
            self.catch_up()
            return
        text = message(TEXT, json.dumps(item).encode("utf-8"))
        for transport in list(self.open):
            if self._stuck(transport):
                continue
            transport.write(text)

    def catch_up(self) -> None:
        """The newest frame to each page that has not had it and has sent all it had to send."""
        if self.frame is None:
            return
        for transport in list(self.owed):
            if self._stuck(transport):
                continue
            if not transport.get_write_buffer_size():
                transport.write(self.frame)
                self.owed.discard(transport)

    def _stuck(self, transport: Any) -> bool:
        """Is the page gone, or so far behind that it is closed now?"""
        if transport.is_closing():
            self.remove(transport)
            return True
        if transport.get_write_buffer_size() > MOST_BUFFERED:
            transport.close()
            self.remove(transport)
            return True
        return False
