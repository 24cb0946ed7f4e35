"""`render --out show.bag`: a ROS 1 bag (format 2.0) that `rosbag play` replays on the robot.

Written without ROS. The frames go to the robot's display topic as
sensor_msgs/Image (bgr8), only those that differ from the one before; the
script's robot effects go to their command topics (see ros/effect_messages.py).
Chunks are LZ4-compressed as `rosbag record --lz4` writes them, with the
index and chunk info records `rosbag info`, `check` and `play` read.

Bag time: a frame or effect at script time t is stamped START + t, where
START is the `start` argument (seconds since the epoch) or else
$SOURCE_DATE_EPOCH, for reproducible bags, or else the whole second the
render began. Header stamps equal the bag times.

A `say` that something stopped before its end (an `interrupt` handler, a new script, the end
of a run with --events) is asked of sound_play as far as it was heard: its text up to the last
word said (sound_play speaks it in its own voice), and a stop request (PLAY_STOP, as the face
node sends) at the moment it stopped; a recording plays from its file, so the stop alone cuts it.

md5sums are computed from the definitions as genmsg does; the robot and
`rosbag play` check them. Baxter's and sound_play's definitions are those in
ros/messages.py.
"""

from __future__ import annotations

import hashlib
import math
import os
import re
import struct
import time
from pathlib import Path
from typing import Any, Dict, List, NamedTuple, Optional, Tuple

import numpy as np

from ..engine.effects import Cue
from ..engine.stitched import StoppedSpeech
from ..extras import need
from ..ros.effect_messages import (
    COMMAND_TYPES,
    DISPLAY_TOPICS,
    PLAY_STOP,
    SOUND_SAY,
    RosCommand,
    ros_commands,
)
from ..ros.messages import DEFINITIONS, SEPARATOR
from .sink import Export, FileSink

# Chunks of about what `rosbag record` makes (768 KB); a frame is bigger, so
# most chunks hold one frame and the writer keeps at most one chunk in memory.
CHUNK_BYTES = 768 * 1024
# LZ4's high-compression mode at a low level: cartoon frames shrink to about 6 % of
# their size rather than 9 %, for some 10 ms a frame; reading is as fast as ever.
LZ4_LEVEL = 3
HEADER_RECORD_BYTES = 4096  # the bag header record is padded to this, to be rewritten in place
MAGIC = b"#ROSBAG V2.0\n"
NS = 1_000_000_000  # bag times are whole nanoseconds

# Record op codes (format 2.0).
OP_MESSAGE, OP_BAG_HEADER, OP_INDEX, OP_CHUNK, OP_CHUNK_INFO, OP_CONNECTION = 2, 3, 4, 5, 6, 7

# sensor_msgs/Image and std_msgs/Header word for word, comments and all, as ROS Noetic has them:
# `rosbag check` wants a migration for any text that differs from the installed one.
IMAGE_TEXT = (
    "# This message contains an uncompressed image\n"
    "# (0, 0) is at top-left corner of image\n"
    "#\n"
    "\n"
    "Header header        # Header timestamp should be acquisition time of image\n"
    "                     # Header frame_id should be optical frame of camera\n"
    "                     # origin of frame should be optical center of camera\n"
    "                     # +x should point to the right in the image\n"
    "                     # +y should point down in the image\n"
    "                     # +z should point into to plane of the image\n"
    "                     # If the frame_id here and the frame_id of the CameraInfo\n"
    "                     # message associated with the image conflict\n"
    "                     # the behavior is undefined\n"
    "\n"
    "uint32 height         # image height, that is, number of rows\n"
    "uint32 width          # image width, that is, number of columns\n"
    "\n"
    "# The legal values for encoding are in file src/image_encodings.cpp\n"
    "# If you want to standardize a new string format, join\n"
    "# ros-users@lists.sourceforge.net and send an email proposing a new encoding.\n"
    "\n"
    "string encoding       # Encoding of pixels -- channel meaning, ordering, size\n"
    "                      # taken from the list of strings in include/sensor_msgs/image_encodings.h\n"
    "\n"
    "uint8 is_bigendian    # is this data bigendian?\n"
    "uint32 step           # Full row length in bytes\n"
    "uint8[] data          # actual matrix data, size is (step * rows)\n"
)
HEADER_TEXT = (
    "# Standard metadata for higher-level stamped data types.\n"
    "# This is generally used to communicate timestamped data \n"
    "# in a particular coordinate frame.\n"
    "# \n"
    "# sequence ID: consecutively increasing ID \n"
    "uint32 seq\n"
    "#Two-integer timestamp that is expressed as:\n"
    "# * stamp.sec: seconds (stamp_secs) since epoch (in Python the variable is called 'secs')\n"
    "# * stamp.nsec: nanoseconds since stamp_secs (in Python the variable is called 'nsecs')\n"
    "# time-handling sugar is provided by the client library\n"
    "time stamp\n"
    "#Frame this data is associated with\n"
    "string frame_id\n"
)
BOOL_TEXT = "bool data"

_BUILTINS = {
    "bool", "byte", "char", "int8", "uint8", "int16", "uint16", "int32", "uint32",
    "int64", "uint64", "float32", "float64", "string", "time", "duration",
}  # fmt: skip
_PACK = {
    "bool": "B", "byte": "b", "char": "B", "int8": "b", "uint8": "B", "int16": "h", "uint16": "H",
    "int32": "i", "uint32": "I", "int64": "q", "uint64": "Q", "float32": "f", "float64": "d",
}  # fmt: skip


def _declarations(text: str) -> Tuple[List[Tuple[str, str, str]], List[Tuple[str, str]]]:
    """The constants (type, name, value text) and fields (type, name) of one .msg text."""
    constants, fields = [], []
    for line in text.splitlines():
        clean = line.split("#", 1)[0].strip()
        if not clean:
            continue
        kind = clean.split()[0]
        if "=" in clean:
            # A string constant's value runs to the end of the line, '#' and all.
            name, value = (line if kind == "string" else clean).split(None, 1)[1].split("=", 1)
            constants.append((kind, name.strip(), value.strip()))
        else:
            fields.append((kind, clean.split()[1]))
    return constants, fields


def md5sum(text: str, nested: Optional[Dict[str, str]] = None) -> str:
    """A message type's md5sum as ROS computes it: over its declarations without comments,
    constants first, each nested type replaced by its own md5sum (`nested`, by the type
    as written in `text`)."""
    constants, fields = _declarations(text)
    lines = [f"{kind} {name}={value}" for kind, name, value in constants]
    for kind, name in fields:
        bare = re.sub(r"\[\d*\]$", "", kind)
        lines.append(f"{kind} {name}" if bare in _BUILTINS else f"{(nested or {})[bare]} {name}")
    return hashlib.md5("\n".join(lines).encode()).hexdigest()


class MessageType(NamedTuple):
    """What a bag's connection header says of a type."""

    name: str  # package/Name
    definition: str  # the full text: the type's own, then each nested type's after a separator
    md5sum: str
    fields: List[Tuple[str, str]]


def _message_type(name: str, text: str, nested: Tuple[Tuple[str, str, str], ...] = ()) -> MessageType:
    """`nested`: (as written, package/Name, text) of each nested type, all builtin-only."""
    # Laid out as genpy's _full_text, which `rosbag record` stores: it drops the last newline.
    full = text + "\n" + "".join(f"{SEPARATOR}\nMSG: {full_name}\n{sub}\n" for _, full_name, sub in nested)
    full = full[:-1]
    md5s = {written: md5sum(sub) for written, _, sub in nested}
    return MessageType(name, full, md5sum(text, md5s), _declarations(text)[1])


def message_types() -> Dict[str, MessageType]:
    """Every type a bag holds, by package/Name: the display's and the robot commands'."""
    texts = {"std_msgs/Bool": BOOL_TEXT}
    texts.update((name, carried.text) for name, carried in DEFINITIONS.items())
    types = {
        "sensor_msgs/Image": _message_type(
            "sensor_msgs/Image", IMAGE_TEXT, (("Header", "std_msgs/Header", HEADER_TEXT),)
        )
    }
    types.update((kind, _message_type(kind, texts[kind])) for kind in COMMAND_TYPES.values())
    return types


def _string(text: str) -> bytes:
    data = text.encode("utf-8")
    return _u32(len(data)) + data


# How each builtin field type is written: little-endian and packed; a string as its length, then UTF-8.
_WRITE = {kind: struct.Struct("<" + code).pack for kind, code in _PACK.items()}
_WRITE["string"] = _string


def serialize_flat(kind: MessageType, fields: Dict[str, Any]) -> bytes:
    """A message of builtin fields (numbers, bools, strings), serialized as ROS 1 does."""
    return b"".join(_WRITE[t](fields[name]) for t, name in kind.fields)


def _u32(n: int) -> bytes:
    return struct.pack("<I", n)


def _time(ns: int) -> bytes:
    return struct.pack("<II", *divmod(ns, NS))


def _fields(fields: Dict[str, bytes]) -> bytes:
    """A record header or connection header: each field as length, name=value."""
    return b"".join(_u32(len(k) + 1 + len(v)) + k.encode() + b"=" + v for k, v in fields.items())


def _record(header: Dict[str, bytes], data: bytes) -> bytes:
    head = _fields(header)
    return _u32(len(head)) + head + _u32(len(data)) + data


def cue_commands(cue: Cue) -> List[Tuple[float, RosCommand]]:
    """The messages a cue makes, at their times: a stopped `say` as far as it was heard, then stopped
    (see the module's docstring)."""
    commands = [(cue.at, command) for command in ros_commands(cue.effect)]
    if not isinstance(cue.effect, StoppedSpeech):
        return commands
    utterance, cut = cue.effect.utterance, []
    for at, (topic, fields) in commands:
        if fields["sound"] == SOUND_SAY:
            fields = {**fields, "arg": said_text(utterance)}
            if not fields["arg"]:  # stopped before its first word
                continue
        elif not utterance.duration:  # stopped as it began
            continue
        cut += [
            (at, RosCommand(topic, fields)),
            (at + utterance.duration, RosCommand(topic, {**fields, "command": PLAY_STOP})),
        ]
    return cut


def said_text(utterance: Any) -> str:
    """An utterance's text up to the end of the last of its words it still has, with the
    punctuation that ends it (words are the text's own, in order, without that punctuation)."""
    text, end = utterance.text, 0
    for word in utterance.words:
        found = text.find(word.text, end)
        if found < 0:
            break
        end = found + len(word.text)
    return text[: re.compile(r"\S*").match(text, end).end()] if end else ""


def start_time() -> int:
    """The default bag start, whole seconds since the epoch: $SOURCE_DATE_EPOCH or now."""
    try:
        return int(os.environ["SOURCE_DATE_EPOCH"])
    except (KeyError, ValueError):
        return int(time.time())


class _Connection(NamedTuple):
    id: int
    topic: str
    kind: MessageType
    latching: bool


class _Chunk:
    """Records on their way into one compressed chunk, with the index that finds them."""

    def __init__(self) -> None:
        self.parts: List[bytes] = []
        self.size = 0
        self.index: Dict[int, List[Tuple[int, int]]] = {}  # connection -> (time ns, offset)
        self.start = self.end = 0

    def add(self, record_parts: List[bytes], connection: Optional[int] = None, ns: int = 0) -> None:
        if connection is not None:
            if not self.index:
                self.start = ns
            self.start, self.end = min(self.start, ns), max(self.end, ns)
            self.index.setdefault(connection, []).append((ns, self.size))
        self.parts.extend(record_parts)
        self.size += sum(len(p) for p in record_parts)


class BagWriter(FileSink):
    """Frames and robot effects into a bag, streamed a chunk at a time."""

    def __init__(
        self, path: Path, export: Export, start: Optional[float] = None, chunk_bytes: int = CHUNK_BYTES
    ) -> None:
        self._lz4 = need("lz4.frame", "bag", "writing a ROS bag")
        start = start_time() if start is None else start
        # Seconds apart: epoch nanoseconds in one float would be rounded to 256.
        whole = math.floor(start)
        self._start_ns = whole * NS + round((start - whole) * NS)
        self._chunk_bytes = chunk_bytes
        self._types = message_types()
        self._display = DISPLAY_TOPICS[export.robot]
        # Stable: effects at one time keep the script's order (disable; enable ends enabled).
        self._commands = sorted(
            ((self._ns(at), command) for cue in export.cues for at, command in cue_commands(cue)),
            key=lambda c: c[0],
        )
        self._next_command = 0
        self._connections: Dict[str, _Connection] = {}
        self._chunk = _Chunk()
        self._chunk_infos: List[Tuple[int, int, int, Dict[int, int]]] = []
        self._previous: Optional[np.ndarray] = None
        self._seq = 0
        super().__init__(Path(path))
        try:
            self.file.write(MAGIC + self._bag_header(0))
        except BaseException:
            self.abort()
            raise

    def _ns(self, t: float) -> int:
        return self._start_ns + round(t * NS)

    def add(self, frame_bgr: np.ndarray, t: float) -> None:
        ns = self._ns(t)
        self._commands_until(ns)
        if self._previous is not None and np.array_equal(frame_bgr, self._previous):
            return  # the screen keeps showing it
        self._previous = frame_bgr.copy()
        height, width = frame_bgr.shape[:2]
        pixels = np.ascontiguousarray(frame_bgr, dtype=np.uint8).tobytes()
        head = (
            struct.pack("<I", self._seq)
            + _time(ns)
            + _u32(0)  # frame_id: ""
            + struct.pack("<II", height, width)
            + _u32(4)
            + b"bgr8"
            + struct.pack("<BI", 0, 3 * width)
            + _u32(len(pixels))
        )
        self._seq += 1
        # Latched, as the face node publishes frames: a screen that subscribes late still gets the face.
        self._message(self._display, "sensor_msgs/Image", ns, [head, pixels], latching=True)

    def _commands_until(self, ns: Optional[int]) -> None:
        """Write the robot's commands due by `ns` (all that are left, for None)."""
        while self._next_command < len(self._commands):
            at, command = self._commands[self._next_command]
            if ns is not None and at > ns:
                return
            kind = COMMAND_TYPES[command.topic]
            self._message(command.topic, kind, at, [serialize_flat(self._types[kind], command.fields)])
            self._next_command += 1

    def _message(self, topic: str, kind: str, ns: int, data: List[bytes], latching: bool = False) -> None:
        connection = self._connections.get(topic)
        if connection is None:
            connection = _Connection(len(self._connections), topic, self._types[kind], latching)
            self._connections[topic] = connection
            # Also inside a chunk, where it is first used, as rosbag writes it: `rosbag reindex` needs it.
            self._chunk.add([self._connection_record(connection)])
        size = sum(len(p) for p in data)
        head = _fields({"op": bytes([OP_MESSAGE]), "conn": _u32(connection.id), "time": _time(ns)})
        self._chunk.add([_u32(len(head)), head, _u32(size), *data], connection.id, ns)
        if self._chunk.size >= self._chunk_bytes:
            self._write_chunk()

    def _connection_record(self, c: _Connection) -> bytes:
        header = {
            "topic": c.topic.encode(),
            "type": c.kind.name.encode(),
            "md5sum": c.kind.md5sum.encode(),
            "message_definition": c.kind.definition.encode(),
            "latching": b"1" if c.latching else b"0",
        }
        return _record(
            {"op": bytes([OP_CONNECTION]), "conn": _u32(c.id), "topic": c.topic.encode()}, _fields(header)
        )

    def _write_chunk(self) -> None:
        chunk = self._chunk
        if not chunk.index:
            return
        raw = b"".join(chunk.parts)
        chunk.parts = []
        # What roslz4 reads: independent blocks, a content checksum and no stored
        # size; it rejects python-lz4's defaults.
        packed = self._lz4.compress(
            raw,
            compression_level=LZ4_LEVEL,
            block_size=self._lz4.BLOCKSIZE_MAX1MB,
            block_linked=False,
            content_checksum=True,
            store_size=False,
        )
        position = self.file.tell()
        self.file.write(
            _record({"op": bytes([OP_CHUNK]), "compression": b"lz4", "size": _u32(len(raw))}, packed)
        )
        for connection, entries in chunk.index.items():
            header = {
                "op": bytes([OP_INDEX]),
                "ver": _u32(1),
                "conn": _u32(connection),
                "count": _u32(len(entries)),
            }
            self.file.write(_record(header, b"".join(_time(ns) + _u32(offset) for ns, offset in entries)))
        counts = {connection: len(entries) for connection, entries in chunk.index.items()}
        self._chunk_infos.append((position, chunk.start, chunk.end, counts))
        self._chunk = _Chunk()

    def _bag_header(self, index_position: int) -> bytes:
        header = _fields(
            {
                "op": bytes([OP_BAG_HEADER]),
                "index_pos": struct.pack("<Q", index_position),
                "conn_count": _u32(len(self._connections)),
                "chunk_count": _u32(len(self._chunk_infos)),
            }
        )
        padding = HEADER_RECORD_BYTES - 8 - len(header)
        return _u32(len(header)) + header + _u32(padding) + b" " * padding

    def finish(self) -> None:
        self._commands_until(None)
        self._write_chunk()
        index_position = self.file.tell()
        for connection in self._connections.values():
            self.file.write(self._connection_record(connection))
        for position, start, end, counts in self._chunk_infos:
            header = {
                "op": bytes([OP_CHUNK_INFO]),
                "ver": _u32(1),
                "chunk_pos": struct.pack("<Q", position),
                "start_time": _time(start),
                "end_time": _time(end),
                "count": _u32(len(counts)),
            }
            self.file.write(_record(header, b"".join(_u32(c) + _u32(n) for c, n in counts.items())))
        self.file.seek(len(MAGIC))
        self.file.write(self._bag_header(index_position))
