"""Frames as sensor_msgs/Image fields and camera images as pixels, with NumPy alone (no cv_bridge).

The same on ROS 1 and ROS 2: a message's `data` is bytes on one and an
array of bytes on the other, and NumPy reads both without copying.
"""

from __future__ import annotations

import math
import struct
from types import SimpleNamespace
from typing import Any, Dict, Optional, Tuple

import numpy as np

CAMERA_ENCODINGS = ("bgr8", "rgb8", "mono8")


def image_fields(frame: np.ndarray, stamp: Optional[float] = None) -> Dict[str, Any]:
    """A (height, width, 3) B, G, R frame as an Image message's fields, encoding bgr8; `stamp`,
    seconds since the epoch, as `stamp`: (sec, nanosec), the links' header.stamp."""
    height, width = frame.shape[:2]
    pixels = np.ascontiguousarray(frame, dtype=np.uint8)
    return {
        **({} if stamp is None else {"stamp": _sec_nanosec(stamp)}),
        "height": height,
        "width": width,
        "encoding": "bgr8",
        "is_bigendian": 0,
        "step": width * 3,
        "data": pixels.tobytes(),
    }


def _sec_nanosec(stamp: float) -> Tuple[int, int]:
    """Seconds as a header's (sec, nanosec): the fraction scaled alone (as nanoseconds since the
    epoch, a float keeps only a quarter of a microsecond)."""
    sec = math.floor(stamp)
    nanosec = round((stamp - sec) * 1e9)
    return (sec + 1, 0) if nanosec >= 1_000_000_000 else (sec, nanosec)


def image_pixels(msg: Any) -> np.ndarray:
    """An Image message (bgr8, rgb8 or mono8) as a (height, width, 3) B, G, R array.

    ValueError for another encoding or for a message whose sizes do not add up.
    """
    if msg.encoding not in CAMERA_ENCODINGS:
        raise ValueError(f"its encoding is {msg.encoding!r}; the face follower takes bgr8, rgb8 or mono8")
    channels = 1 if msg.encoding == "mono8" else 3
    height, width, step = int(msg.height), int(msg.width), int(msg.step)
    data = np.frombuffer(msg.data, dtype=np.uint8)
    if height <= 0 or width <= 0 or step < width * channels or data.size < step * height:
        raise ValueError(
            f"its {data.size} bytes are not a {width}x{height} {msg.encoding} image of step {step}"
        )
    rows = data[: step * height].reshape(height, step)[:, : width * channels]
    pixels = rows.reshape(height, width, channels)
    if channels == 1:
        return np.repeat(pixels, 3, axis=2)
    return np.ascontiguousarray(pixels[..., ::-1] if msg.encoding == "rgb8" else pixels)


# ROS 2 carries messages as CDR (little-endian, after a 4-byte encapsulation header). rclpy's own
# conversion of an Image's 1.8 MB of data between Python and C takes 15 ms out and 6 ms in; as
# CDR bytes written and read here, a frame is one copy.
_CDR_LE = b"\x00\x01\x00\x00"


def _cdr_string(out: bytearray, text: str) -> None:
    raw = text.encode("utf-8") + b"\0"
    _align(out, 4)
    out += struct.pack("<I", len(raw)) + raw


def _align(out: bytearray, size: int) -> None:
    out += b"\0" * (-(len(out) - 4) % size)  # offsets count from after the encapsulation header


def image_cdr(fields: Dict[str, Any], frame_id: str = "") -> bytes:
    """A sensor_msgs/msg/Image as ROS 2's serialized bytes, from `image_fields`' fields."""
    out = bytearray(_CDR_LE)
    out += struct.pack("<iI", *fields.get("stamp", (0, 0)))  # header.stamp (none: as cv_bridge leaves it)
    _cdr_string(out, frame_id)
    _align(out, 4)
    out += struct.pack("<II", fields["height"], fields["width"])
    _cdr_string(out, fields["encoding"])
    out += struct.pack("<B", fields.get("is_bigendian", 0))
    _align(out, 4)
    data = fields["data"]
    out += struct.pack("<II", fields["step"], len(data))
    return bytes(out) + bytes(data)


def image_from_cdr(raw: bytes) -> Any:
    """ROS 2's serialized sensor_msgs/msg/Image as an object with the message's fields
    (`data` a view of the bytes, not a copy). ValueError if it is not one."""
    view = memoryview(raw)
    if bytes(view[:2]) != b"\x00\x01":
        raise ValueError("not little-endian CDR")
    at = 4

    def take(fmt: str, size: int) -> Any:
        nonlocal at
        at += -(at - 4) % size
        values = struct.unpack_from(fmt, view, at)
        at += struct.calcsize(fmt)
        return values

    def text() -> str:
        nonlocal at
        (length,) = take("<I", 4)
        value = bytes(view[at : at + length - 1]).decode("utf-8")
        at += length
        return value

    sec, nanosec = take("<iI", 4)
    frame_id = text()
    height, width = take("<II", 4)
    encoding = text()
    (is_bigendian,) = take("<B", 1)
    step, length = take("<II", 4)
    if at + length > len(view):
        raise ValueError(f"the image's {length} bytes of data run past the message's end")
    header = SimpleNamespace(stamp=SimpleNamespace(sec=sec, nanosec=nanosec), frame_id=frame_id)
    return SimpleNamespace(
        header=header,
        height=height,
        width=width,
        encoding=encoding,
        is_bigendian=is_bigendian,
        step=step,
        data=view[at : at + length],
    )
