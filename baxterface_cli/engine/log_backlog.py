"""Log lines written by a thread of their own, so logging never stalls the frame loop.

A ROS log call can take tens of milliseconds (rospy asks the master for a
parameter and writes a file for each line): a flood of bad commands logged
from the loop stopped frames for seconds. Lines wait in a bounded backlog;
beyond it they are counted and the count is logged in their place.
"""

from __future__ import annotations

import threading
from collections import deque
from typing import Callable, Deque, Tuple

MAX_WAITING = 200  # lines; a flood beyond this is summarised by a count


class Backlog:
    """`warn`, `error` and `info` that return at once; `write(level, text)` runs on a worker."""

    def __init__(self, write: Callable[[str, str], None], max_waiting: int = MAX_WAITING) -> None:
        self._write = write
        self.max_waiting = max_waiting
        self._lines: Deque[Tuple[str, str]] = deque()
        self._cond = threading.Condition()
        self._skipped = 0
        self._closed = False
        self._busy = False
        self._thread = threading.Thread(target=self._work, name="baxterface-log", daemon=True)
        self._thread.start()

    def info(self, text: str) -> None:
        self._put("info", text)

    def warn(self, text: str) -> None:
        self._put("warn", text)

    def error(self, text: str) -> None:
        self._put("error", text)

    def _put(self, level: str, text: str) -> None:
        with self._cond:
            if len(self._lines) >= self.max_waiting:
                self._skipped += 1
                return
            self._lines.append((level, text))
            self._cond.notify()

    def flush(self, timeout: float = 5.0) -> bool:
        """Wait until every line so far is written; False if that took longer than `timeout`."""
        with self._cond:
            return self._cond.wait_for(lambda: not self._lines and not self._busy, timeout)

    def close(self) -> None:
        with self._cond:
            self._closed = True
            self._cond.notify_all()

    def _work(self) -> None:
        while True:
            with self._cond:
                self._cond.wait_for(lambda: self._lines or self._closed)
                if not self._lines:
                    return
                level, text = self._lines.popleft()
                skipped, self._skipped = (self._skipped, 0) if not self._lines else (0, self._skipped)
                self._busy = True
            try:
                self._write(level, text)
                if skipped:
                    self._write("warn", f"{skipped} more log lines were skipped: too many at once")
            except Exception:  # a log that fails must not end logging
                pass
            finally:
                with self._cond:
                    self._busy = False
                    self._cond.notify_all()
