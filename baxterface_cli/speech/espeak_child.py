"""The speech process: libespeak-ng in a process of its own, answering one request at a time.

espeak-ng 1.51 crashes on some short texts (`{}[]{}[]` in voice ky, `1234567890` in kl) with a
segmentation fault or glibc's "buffer overflow detected" abort, which no Python code can catch.
Here it takes down only this process; espeak_process.py, in the process that asked, reports it
and starts another. This module runs in the child and imports only the standard library and
espeak.py (the child skips the package's __init__, see espeak_process.BOOT).

Messages both ways are framed the same: the lengths of a JSON head and of raw data, then both.
"""

from __future__ import annotations

import json
import os
import signal
import struct
from typing import Any, Dict, Optional, Tuple

FRAME = struct.Struct(">II")  # the head's length, the data's length


def send(fd: int, head: Dict[str, Any], data: bytes = b"") -> None:
    encoded = json.dumps(head).encode("utf-8")
    view = memoryview(FRAME.pack(len(encoded), len(data)) + encoded + data)
    while view:
        view = view[os.write(fd, view) :]


def _read_exactly(fd: int, count: int) -> Optional[bytes]:
    parts, left = [], count
    while left:
        part = os.read(fd, min(left, 1 << 20))
        if not part:
            return None
        parts.append(part)
        left -= len(part)
    return b"".join(parts)


def receive(fd: int) -> Optional[Tuple[Dict[str, Any], bytes]]:
    """The next message, waiting as long as it takes; None once the other end has closed."""
    lengths = _read_exactly(fd, FRAME.size)
    if lengths is None:
        return None
    head_length, data_length = FRAME.unpack(lengths)
    body = _read_exactly(fd, head_length + data_length)
    if body is None:
        return None
    return json.loads(body[:head_length].decode("utf-8")), body[head_length:]


def serve(requests: int, replies: int) -> None:
    """Say what is asked on `requests`, answering on `replies`, until `requests` closes."""
    # Ctrl-C at a terminal reaches the whole process group: it is for the parent, which ends this
    # one by closing its pipe. Without this, a press of Ctrl-C would read as a crash.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    # espeak-ng 1.51 opens PulseAudio at its start in every mode, retrieval and synchronous too,
    # and libpulse makes ~/.config/pulse and $TMPDIR/pulse-* to find a server; this process only
    # synthesises (the sound is played by the program, if at all), so its server is none.
    os.environ["PULSE_SERVER"] = "unix:" + os.devnull
    from ..extras import MissingTool
    from .espeak import espeak_library, synthesize, voice_file

    try:
        path, sample_rate, version = espeak_library()
    except MissingTool as e:
        send(replies, {"missing": str(e)})
        return
    send(replies, {"sample_rate": sample_rate, "version": version})
    while True:
        message = receive(requests)
        if message is None:
            return
        request, _ = message
        try:
            if request["op"] == "say":
                spoken = synthesize(path, request["text"], request["voice"], request["rate"])
                heard = [list(h) for h in spoken.heard]
                send(replies, {"status": spoken.status, "heard": heard}, spoken.pcm)
            else:
                send(replies, {"voice_file": voice_file(path, request["voice"])})
        except ValueError as e:  # a voice this espeak-ng lacks
            send(replies, {"refused": str(e)})
