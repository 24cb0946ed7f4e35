"""Frames as sensor_msgs/Image fields and camera images as pixels, with NumPy alone (no cv_bridge).

The same on ROS 1 and ROS 2: a message's `data` is bytes on one and an
array of bytes on the other, and NumPy reads both without copying.
"""

from __future__ import annotations

from typing import Any, Dict

import numpy as np

CAMERA_ENCODINGS = ("bgr8", "rgb8", "mono8")


def image_fields(frame: np.ndarray) -> Dict[str, Any]:
    """A (height, width, 3) B, G, R frame as an Image message's fields, encoding bgr8."""
    height, width = frame.shape[:2]
    pixels = np.ascontiguousarray(frame, dtype=np.uint8)
    return {
        "height": height,
        "width": width,
        "encoding": "bgr8",
        "is_bigendian": 0,
        "step": width * 3,
        "data": pixels.tobytes(),
    }


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
