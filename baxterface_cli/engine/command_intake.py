"""Commands parsed and compiled off the frame loop, so a big script never stops the face.

A worker thread takes each command text, parses and compiles it, and leaves
the result for the loop, which only has to start it (cheap). What waits is
bounded: of commands that take over at once only the newest is kept (one that
arrives while another waits replaces it: the older one would be replaced the
moment it started anyway), and at most `max_pending` queued ones wait to be
parsed; more are refused, with a reason, at once.
"""

from __future__ import annotations

import threading
from collections import deque
from typing import Callable, Deque, List, NamedTuple, Optional, Tuple

from ..closing import ClosedOnExit
from ..extras import MissingTool
from ..language.diagnostics import Diagnostic, ScriptError
from ..language.parser import parse
from ..speech.recordings import RecordingError
from .live_face import LiveFace, QueueFull
from .timeline import Timeline

MAX_PENDING = 8  # queued commands waiting to be parsed


class Prepared(NamedTuple):
    """A command ready for the loop: its timeline, or the error that stopped it."""

    queued: bool
    timeline: Optional[Timeline]
    error: Optional[ScriptError]
    generation: int  # queued ones from before the latest take-over are stale


class Intake(ClosedOnExit):
    """Command texts in (from any thread); prepared timelines out, for the loop."""

    def __init__(
        self,
        live: LiveFace,
        clock: Callable[[], float],
        ready: Callable[[], None] = lambda: None,
        filename: str = "display_chatter",
        max_pending: int = MAX_PENDING,
    ) -> None:
        self.live = live
        self.clock = clock
        self.ready = ready  # called when something is ready: wakes the loop
        self.filename = filename
        self.max_pending = max_pending
        self.generation = 0
        self._latest: Optional[Tuple[str, int]] = None
        self._queued: Deque[Tuple[str, int]] = deque()
        self._done: Deque[Prepared] = deque()
        self._cond = threading.Condition()
        self._closed = False
        self.dropped = 0  # take-over commands replaced before they started
        self._thread = threading.Thread(target=self._work, name="baxterface-intake", daemon=True)
        self._thread.start()

    def submit(self, text: str, queued: bool = False) -> Optional[str]:
        """Hand a command over; returns why it was refused, or None."""
        with self._cond:
            if queued:
                if len(self._queued) >= self.max_pending:
                    return f"refused a queued script: {self.max_pending} are already waiting to be read"
                self._queued.append((text, self.generation))
            else:
                self.generation += 1
                if self._latest is not None:
                    self.dropped += 1
                self._latest = (text, self.generation)
            self._cond.notify()
        return None

    def take(self) -> List[Prepared]:
        """Everything prepared since the last call, in the order it was finished."""
        out = []
        while self._done:
            out.append(self._done.popleft())
        return out

    def hand_over(
        self, now: float, warn: Callable[[str], None], error: Callable[[str], None]
    ) -> Optional[bool]:
        """Start or queue on the live face what is ready; called by the loop.

        Returns None if nothing changed, True if a script started now, False
        if one was queued (or refused). Bad commands are logged, one line each.
        """
        changed: Optional[bool] = None
        for prepared in self.take():
            if prepared.error is not None:
                error(f"bad command: {prepared.error.summary()}")
                continue
            if prepared.queued and prepared.generation < self.generation:
                continue  # a take-over came after it and cleared the queue
            if not prepared.queued or (self.live.finished(now) and not self.live.queue):
                self.live.begin(prepared.timeline, now)
                changed = True
                continue
            try:
                self.live.enqueue(prepared.timeline)
            except QueueFull as e:
                warn(f"refused a queued script: {e}")
            changed = bool(changed)
        return changed

    def close(self) -> None:
        with self._cond:
            self._closed = True
            self._cond.notify()

    def idle(self) -> bool:
        """Nothing waiting or being prepared."""
        with self._cond:
            return self._latest is None and not self._queued and not self.busy

    busy = False  # preparing a command now

    def _work(self) -> None:
        while True:
            with self._cond:
                while not self._closed and self._latest is None and not self._queued:
                    self._cond.wait()
                if self._closed:
                    return
                if self._latest is not None:  # a take-over first: it makes queued ones moot
                    (text, generation), queued = self._latest, False
                    self._latest = None
                else:
                    (text, generation), queued = self._queued.popleft(), True
                self.busy = True
            try:
                self._done.append(self._prepare(text, queued, generation))
            finally:
                self.busy = False
            self.ready()

    def _prepare(self, text: str, queued: bool, generation: int) -> Prepared:
        try:
            script = parse(text, self.filename)
        except ScriptError as e:
            return Prepared(queued, None, e, generation)
        try:
            if queued:
                timeline = self.live.prepare(script, self._queue_end())
            else:
                timeline = self.live.take_over(script, self.clock())
        except MissingTool as e:  # `say` on a machine without a speech engine: refused, not fatal
            return Prepared(queued, None, ScriptError([Diagnostic(0, 0, str(e))], self.filename), generation)
        except RecordingError as e:  # `say file` of a recording that cannot be read, or not from here
            return Prepared(queued, None, ScriptError([e.diagnostic()], self.filename, text), generation)
        except ScriptError as e:  # the same, found before compiling, or too long with its recordings
            return Prepared(queued, None, e, generation)
        return Prepared(queued, timeline, None, generation)

    def _queue_end(self):
        try:
            return self.live.queue_end()
        except IndexError:  # the loop emptied the queue meanwhile
            return self.live.base_state(self.clock())
