"""A live session on the robot: the one frame loop of the face node and of `stream` that reacts.

It owns the session's intake (engine/session_intake.py: steps compiled on a worker, never here),
the robot's senses (robot_senses.py: events in) and its `Robot` (effects out), and the screen:
changed frames go out on the display topic as bgr8 through one latched publisher (JPEGs beside
them while someone subscribes), speech through the speaker given, and with `state` what the face
is doing on `~state` (JSON, latched). All work happens in the loop; callbacks only hand over.
"""

from __future__ import annotations

import dataclasses
import gc
import json
import math
import signal
import sys
import threading
import time
from typing import Any, Callable, Optional, Tuple

from ..core.face_state import FaceState
from ..drawing.renderer import Renderer
from ..engine.change_polling import ChangePolling
from ..engine.effects import Speech
from ..engine.live_session import LiveSession
from ..engine.log_backlog import Backlog
from ..engine.session_intake import SessionIntake
from ..engine.session_log_file import SessionLogFile
from .compressed import CompressedFrames
from .images import image_fields
from .link import STATE, Link
from .node_settings import NodeSettings
from .robot_senses import RobotSenses

STATE_EVERY = 0.1  # seconds between ~state messages while the face moves
# The loop takes the GIL back several times a frame from threads that parse
# commands and receive messages; each time it may wait a whole switch
# interval (5 ms by default). 1 ms halved the worst frame gap under a flood.
SWITCH_INTERVAL = 0.001
# A full garbage collection walks every object that queued scripts hold and
# stops the loop while it does (about 100 ms with a full queue of big ones).
# Python's first two generations still collect young cycles; the full one is
# left for this many of theirs rather than 10.
FULL_COLLECTION_EVERY = 1000


def _log_file(
    settings: NodeSettings, warn: Callable[[str], None], end: str, seed: Optional[int]
) -> Optional[SessionLogFile]:
    """The session's log file of the `log` setting, or None; it ends when the intake closes. The
    session's `seed` in its settings: a replay's `one of`s and faces choose as the session's did."""
    if settings.log is None:
        return None
    kept = {k: v for k, v in dataclasses.asdict(settings).items() if k not in ("log", "log_size")}
    size = int(settings.log_size * 1024 * 1024)
    return SessionLogFile(settings.log, time.monotonic(), {"end": end, "seed": seed, **kept}, warn, size)


class FaceLoop:
    """`session` on the robot: its intake, the robot's senses, frames, speech and ~state."""

    def __init__(
        self,
        link: Link,
        session: LiveSession,
        settings: NodeSettings,
        renderer: Renderer,
        speaker: Any,
        log: Backlog,
        state: bool = True,
        filename: str = "display_chatter",
        end: str = "node",
        seed: Optional[int] = None,
    ) -> None:
        """`end`: what runs it (node, stream), and `seed`, the session's, as its log file's first
        record says."""
        self.link = link
        self.session = session
        self.live = session.face  # read by the loop without the session's lock
        self.renderer = renderer
        self.speaker = speaker
        self.log = log
        self.fps = settings.fps
        self.wake = threading.Event()
        # A plain flag: a handler runs between any two steps of the loop, inside `wake.wait()`
        # too, where setting an Event would wait for the lock that very wait holds. The loop
        # looks at the flag at least once a tick. Set from here on, not from the loop's start: a
        # SIGTERM while the node starts (its camera, speaker, ears) is a clean stop, not exit 143.
        self.stopping = False
        for signum in (signal.SIGINT, signal.SIGTERM):
            signal.signal(signum, lambda *_: setattr(self, "stopping", True))
        self.intake = SessionIntake(
            session,
            time.monotonic,
            ready=self.wake.set,
            log=self._logged,
            filename=filename,
            record=_log_file(settings, log.warn, end, seed),
        )
        self.saying: Optional[Tuple[str, float]] = None  # (text, when it ends) while the face speaks
        self.senses = RobotSenses(link, self.intake, settings, self._speak, log.warn, log.info)
        self.robot = self.senses.robot
        self.image_pub = link.publisher(settings.display_topic, "sensor_msgs/Image", latched=True, queue=1)
        self.jpeg = CompressedFrames(link, self.image_pub.topic)  # JPEGs only while someone subscribes
        self.state_pub = link.publisher(STATE, "std_msgs/String", latched=True, queue=1) if state else None
        self.shown_timeline: Any = self.live.timeline  # a new one: a step began (speech cut, state sent)
        # A frame's header.stamp is the wall clock at its `now`, from one pair of readings: the
        # session log's start, when there is one, so a stamp less the log's `unix` is its `t`.
        record = self.intake.record
        self.clock_at, self.wall_at = (
            (record.origin, record.unix) if record is not None else (time.monotonic(), time.time())
        )
        self.last_key: Any = None
        self.last_frame_at = -math.inf
        self.change_polling = ChangePolling()  # after a command, looked at often until it shows
        self.last_state_text = ""
        self.last_state_at = -math.inf

    def _logged(self, level: str, text: str) -> None:  # the session's worker: the backlog logs it
        getattr(self.log, level if level in ("info", "error") else "warn")(text)

    def _speak(self, effect: Speech) -> None:
        # Timed here, not by the script's status: a take-over restarts the script's clock.
        self.saying = (effect.utterance.said, time.monotonic() + effect.duration)
        # Reported in this very tick, as a step's start is: a loop that a busy machine then holds
        # up past a short utterance's end would otherwise never say that it spoke.
        self.last_state_at = -math.inf
        self.speaker.speak(effect)

    # -- the loop

    def run(
        self, done: Callable[[float], bool] = lambda now: False, deaf: Optional[Callable[[str], None]] = None
    ) -> float:
        """Until the face exits, SIGINT or SIGTERM, or `done(now)`; the time it ended. Without ears
        (`_listen` given, its extra, device or recording missing) it goes on, after `deaf(why)`
        (by default a warning in the log), which may raise to stop instead."""
        # Left in the reverse order: the ears, the speaker, the JPEGs, the camera.
        with self.robot.camera, self.jpeg, self.speaker:
            problem = self.senses.start()
            try:
                if problem and deaf is not None:
                    deaf(problem)
                elif problem:
                    self.link.log("warn", f"no words are heard: {problem}")
                return self._run(done)
            finally:
                self.senses.close()
                self.intake.close()
                self.log.flush(timeout=0.3)

    def _run(self, done: Callable[[float], bool]) -> float:
        sys.setswitchinterval(SWITCH_INTERVAL)
        young, middle, _ = gc.get_threshold()
        gc.set_threshold(young, middle, FULL_COLLECTION_EVERY)
        period = 1.0 / self.fps
        next_tick = now = time.monotonic()
        while not self.stopping and self.link.ok():
            now = time.monotonic()
            took = self._take_commands(now)
            self.senses.check(now)
            cues = self.session.catch_up(now)
            face = self.live.state(now)
            for cue in cues:
                self.robot.take(cue.effect, now)
            self.senses.watch_camera()
            state = self.robot.look(face, now)
            self.robot.tick(now)
            if self.live.exited or done(now):
                self._publish_frame(state, now, force=True)
                self._publish_state(state, now, force=True)
                time.sleep(0.5)  # let the last frame reach its subscribers
                break
            # The cap: frames at most `fps` a second (a little slack for a
            # tick that comes early; ticks themselves keep the average).
            if now >= self.last_frame_at + 0.75 * period and self._publish_frame(state, now):
                self.change_polling.shown()
            self._publish_state(state, now)
            self.jpeg.tick(now)
            # Ticks keep their own rhythm, publishing or not, whatever woke the loop
            # between them; a late loop skips the ticks it missed rather than hurrying.
            if now >= next_tick:
                next_tick += period
                if next_tick < now:
                    next_tick = now + period
            if took:
                self.change_polling.heard(now)
            wake_at = self.change_polling.next_look(next_tick, now)
            self.wake.wait(max(0.0, wake_at - time.monotonic()))  # or until a command comes
            self.wake.clear()
        return now

    def _take_commands(self, now: float) -> bool:
        """True if the session began a step since the last look (its worker did)."""
        timeline = self.live.timeline
        if timeline is self.shown_timeline:
            return False
        self.shown_timeline = timeline
        self.last_state_at = -math.inf  # report the change at once
        if self.saying is not None and now < self.saying[1]:  # cut off with the step that said it
            self.saying = None
            self.speaker.stop()
        return True

    def _publish_frame(self, state: FaceState, now: float, force: bool = False) -> bool:
        """Publish the frame of `state` if it changed (or `force`); True if one went out."""
        key = self.renderer.frame_key(state)
        if key == self.last_key and not force:
            return False
        frame = self.renderer.render(state)
        self.image_pub.publish(**image_fields(frame, self.wall_at + (now - self.clock_at)))
        self.jpeg.offer(frame)
        self.last_key, self.last_frame_at = key, now
        return True

    def _publish_state(self, state: FaceState, now: float, force: bool = False) -> None:
        if self.state_pub is None or (now - self.last_state_at < STATE_EVERY and not force):
            return
        measured = self.robot.head
        if measured is not None:  # the robot's own pan, when it says it
            state = state.replace(head_pan=measured)
        session = self.intake.session
        report = {
            **state.as_record(),
            "enabled": self.robot.enabled,
            "following": self.robot.gaze.target,  # not the script's wish: what the robot can follow
            "follow_dynamic": self.robot.gaze.dynamic,
            "follow_seen": self.robot.gaze.seen,
            "playing": not self.live.finished(now),
            "queued": len(self.intake.waiting),
            "handlers": self.intake.counts,
            # Read without the session's lock: the worker swaps each whole.
            "running": session.active.label if session.active is not None else None,
            "state": session.states.current,
            "saying": self.saying[0] if self.saying and now < self.saying[1] else None,
        }
        text = json.dumps(report, sort_keys=True)
        if text != self.last_state_text or force:
            self.state_pub.publish(data=text)
            self.last_state_text = text
        self.last_state_at = now
