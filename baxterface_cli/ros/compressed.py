"""The face's frames as JPEG on `<display topic>/compressed`, for viewers on other machines.

A sensor_msgs/CompressedImage in image_transport's spelling (`format` "bgr8;
jpeg compressed bgr8"), so rqt_image_view and `image_transport republish`
read it. A JPEG of a 1024x600 face is about 40 KB against the raw frame's
1.8 MB. Frames are encoded only while something subscribes, on a thread of
their own: the frame loop hands the newest over and goes on; a frame that
comes while one is being encoded replaces the one waiting.
"""

from __future__ import annotations

import io
import threading
from typing import Optional

import numpy as np

from ..closing import ClosedOnExit
from .link import Link

FORMAT = "bgr8; jpeg compressed bgr8"
QUALITY = 85
LOOK_EVERY = 0.25  # seconds between looks for a new subscriber while the face is still


def jpeg(frame: np.ndarray, quality: int = QUALITY) -> bytes:
    """A (height, width, 3) B, G, R frame as JPEG bytes."""
    from PIL import Image

    out = io.BytesIO()
    Image.fromarray(np.ascontiguousarray(frame[..., ::-1])).save(out, "JPEG", quality=quality)
    return out.getvalue()


class CompressedFrames(ClosedOnExit):
    """Publishes JPEGs of the frames it is offered, while the topic has subscribers."""

    def __init__(self, link: Link, display_topic: str) -> None:
        topic = display_topic.rstrip("/") + "/compressed"
        self.publisher = link.publisher(topic, "sensor_msgs/CompressedImage", latched=True, queue=1)
        self.topic = self.publisher.topic
        self.log = link.log
        self.waiting: Optional[np.ndarray] = None
        self.last: Optional[np.ndarray] = None  # the newest frame, for a subscriber that comes later
        self.sent_to = 0  # subscribers when a frame last went out
        self.looked_at = -1e9
        self.ready = threading.Condition()
        self.closed = False
        self.thread = threading.Thread(target=self._encode, name="baxterface-jpeg", daemon=True)
        self.thread.start()

    def offer(self, frame: np.ndarray) -> None:
        """A new frame (on the frame loop): sent if someone listens, else only kept."""
        self.last = frame
        listening = self.publisher.listeners()
        self.sent_to = listening
        if listening:
            self._hand(frame)

    def tick(self, now: float) -> None:
        """On the loop: a subscriber that came while the face was still gets the frame it shows."""
        if now < self.looked_at + LOOK_EVERY or self.last is None:
            return
        self.looked_at = now
        listening = self.publisher.listeners()
        if listening > self.sent_to:
            self._hand(self.last)
        self.sent_to = listening

    def _hand(self, frame: np.ndarray) -> None:
        with self.ready:
            self.waiting = frame
            self.ready.notify()

    def _encode(self) -> None:
        while True:
            with self.ready:
                while self.waiting is None and not self.closed:
                    self.ready.wait()
                if self.closed:
                    return
                frame, self.waiting = self.waiting, None
            try:
                self.publisher.publish(format=FORMAT, data=jpeg(frame))
            except Exception as e:  # the link closing under it, or a ROS error: the face goes on
                self.log("warn", f"a JPEG frame on {self.topic} was not sent: {e}", every=5.0)

    def close(self) -> None:
        with self.ready:
            self.closed = True
            self.ready.notify()
        self.thread.join(timeout=1.0)
