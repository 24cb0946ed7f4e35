"""The head camera, for following a face: the newest image through a FaceFollower.

Finding a face takes a few milliseconds to a few tens, and images come at
30 a second, so the face node looks at them on a worker thread and keeps
only the newest: the eyes want where the face is now, not every face there
was. `play --follow-from` looks at each image as it falls due instead
(`threaded=False`), which also makes a run repeatable.
"""

from __future__ import annotations

import threading
from typing import Any, Callable, Optional, Tuple

from ..closing import ClosedOnExit
from ..extras import MissingTool
from .person_choice import DEFAULT_FACE_POLICY

Point = Tuple[float, float]


class CameraWatch(ClosedOnExit):
    """Images in (`give`, from any thread), the eye target of the face in them out (`hand_to`).

    `decode` turns what `give` was handed (a ROS message, say) into an
    HxWx3 BGR image; it runs on the worker, off the caller's thread. An
    image that cannot be decoded or looked at is reported through `warn`
    and skipped. `hfov_deg` is the camera's field of view (None: Baxter's head camera's,
    or the focal length the camera says, `lens`); `policy` which face is followed
    among several (person_choice.FACE_POLICIES).
    """

    def __init__(
        self,
        hand_to: Callable[[Optional[Point]], None],
        hfov_deg: Optional[float] = None,
        decode: Callable[[Any], Any] = lambda image: image,
        warn: Callable[[str], None] = lambda text: None,
        threaded: bool = True,
        policy: str = DEFAULT_FACE_POLICY,
    ) -> None:
        self.hand_to = hand_to
        self.hfov_deg = hfov_deg
        self.policy = policy
        self.focal: Optional[float] = None  # pixels, once the camera has said it (`lens`)
        self.decode = decode
        self.warn = warn
        self.threaded = threaded
        self.follower: Any = None  # a faces.FaceFollower while watching
        self._newest: Optional[Tuple[Any, float, Any]] = None
        self._lock = threading.Lock()
        self._ready = threading.Event()
        self._closed = False
        self._worker: Optional[threading.Thread] = None
        self._told_fallback = False

    def start(self) -> Optional[str]:
        """Look for a face afresh (forgetting any seen before); None, or why it cannot."""
        from .person_finder import (  # OpenCV only when a face is followed
            BAXTER_HEAD_CAMERA_HFOV,
            FaceFollower,
        )

        try:
            follower = FaceFollower(
                hfov_deg=self.hfov_deg or BAXTER_HEAD_CAMERA_HFOV, policy=self.policy, focal=self.focal
            )
        except MissingTool as e:
            return str(e)
        if follower.fallback and not self._told_fallback:  # once: the node's log, play's status line
            self._told_fallback = True
            self.warn(follower.fallback)
        with self._lock:
            self.follower, self._newest = follower, None
        self.hand_to(None)
        if self.threaded and self._worker is None:
            self._worker = threading.Thread(target=self._work, name="baxterface-camera", daemon=True)
            self._worker.start()
        return None

    def lens(self, focal: float) -> None:
        """The camera's focal length in pixels (its camera_info's), for every image from now on; a
        field of view given as `hfov_deg` wins over it. Any thread may call it."""
        if self.hfov_deg is not None:
            return
        self.focal = focal
        follower = self.follower
        if follower is not None:
            follower.focal = focal

    def stop(self) -> None:
        """Stop looking: images given from now on are dropped."""
        with self._lock:
            self.follower, self._newest = None, None

    @property
    def watching(self) -> bool:
        return self.follower is not None

    def give(self, image: Any, at: float) -> None:
        """The camera's newest image, taken at `at` (seconds on the caller's clock)."""
        with self._lock:
            if self.follower is None:
                return
            self._newest = (image, at, self.follower)
        if self.threaded:
            self._ready.set()
        else:
            self._look()

    def close(self) -> None:
        self._closed = True
        self.stop()
        self._ready.set()

    def _work(self) -> None:
        while not self._closed:
            self._ready.wait()
            self._ready.clear()
            self._look()

    def _look(self) -> None:
        with self._lock:
            newest, self._newest = self._newest, None
        if newest is None:
            return
        image, at, follower = newest
        try:
            target = follower.update(self.decode(image), at)
        except Exception as e:  # a bad image must not stop the watching
            self.warn(f"skipped a camera image: {e}")
            return
        if follower is self.follower:  # not a follower that was stopped or replaced meanwhile
            self.hand_to(target)
