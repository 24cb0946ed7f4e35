"""A live session's record on disk: `--log FILE` (the node's `log` parameter), for a study.

JSON Lines, one record a line, each written and flushed by a thread of its own as it comes, so
no end waits for the disk: the node's, `stream`'s and the screen's intake worker and `play`'s
frame loop only hand records over (a bounded backlog; a flood beyond it is counted, and the
count is written in its place). Times (`t`) are seconds on one clock from the session's start;
the first record says when that was by the wall clock, with the log's `version` and the
settings. The records (docs/session-log.md has their fields): `start`, `script` (each script or
command as it arrived), `event` (each event that came, with where from), `log` (every line of
the session's own log, with its kind: engine/session_records.LogKind), `say`, `skipped` and
`end`.

Bounded: past `max_bytes` the file is renamed FILE.1 (FILE.1 to FILE.2, ...; `KEPT` of them
kept) and a new FILE begins with a `continued` record. A file that cannot be written (a full
disk, a folder, no permission) is one line in the end's own log, and the face goes on without it.
"""

from __future__ import annotations

import contextlib
import datetime
import json
import os
import threading
import time
from collections import deque
from typing import Any, Callable, Deque, Dict, List, Optional

from ..closing import ClosedOnExit
from ..language import syntax_tree as n
from ..language.events import in_words

VERSION = 1  # of the records' fields: a reader refuses a log of a later one
DEFAULT_SIZE = 100 * 1024 * 1024  # bytes a file grows to before it is rotated
LEAST_MB = 0.01  # megabytes: a file of a few records
KEPT = 4  # rotated files kept beside FILE: FILE.1 (the latest) to FILE.4
UTC = datetime.timezone.utc
MAX_WAITING = 10_000  # records waiting for the writer; a flood beyond is counted

Warn = Callable[[str], None]


def log_size(megabytes: float) -> int:
    """`--log-size` in bytes; ValueError if it is not a size a log may have."""
    if not megabytes >= LEAST_MB:  # also refuses nan
        raise ValueError(f"must be at least {LEAST_MB:g} MB, not {megabytes:g}")
    return int(megabytes * 1024 * 1024)


class SessionLogFile(ClosedOnExit):
    """Records in from any thread, written to `path` by a thread of its own (see above)."""

    def __init__(
        self,
        path: str,
        origin: float,
        settings: Dict[str, Any],
        warn: Warn = lambda text: None,
        max_bytes: int = DEFAULT_SIZE,
    ) -> None:
        """`origin`: the session's clock at its start (every `t` is from it); `settings`: what
        the session was started with (the end, its command line or parameters)."""
        self.path = path
        self.origin = origin
        self.warn = warn
        self.max_bytes = max_bytes
        self.logged = 0  # the session's log lines recorded so far (`follow`)
        self._records: Deque[Dict[str, Any]] = deque()
        self._cond = threading.Condition()
        self._skipped = 0
        self._closed = False
        self._file: Any = None
        self._size = 0
        self._part = 0
        self._failed = False
        now = time.time()
        # To the microsecond: a frame's stamp (the node's header.stamp) less it is its `t`.
        self.unix = round(now, 6)
        self._wall = {
            "version": VERSION,
            "wall": datetime.datetime.fromtimestamp(now, UTC).isoformat(timespec="milliseconds"),
            "unix": self.unix,
        }
        self._put({"type": "start", "t": 0.0, **self._wall, "settings": settings})
        self._thread = threading.Thread(target=self._work, name="baxterface-session-log", daemon=True)
        self._thread.start()

    # -- in, from any thread

    def _t(self, at: float) -> float:
        # Not rounded: a replay begins each step at the very time the session did, so its frames
        # are the live ones to the bit (at 0.1 ms, a mouth moving in speech was not).
        return max(0.0, at - self.origin)

    def script(self, at: float, text: str, source: str, queued: bool = False) -> None:
        """A script or command as it arrived (its text), from `source` (a topic, a page, a file)."""
        record = {"type": "script", "t": self._t(at), "text": text, "source": source}
        self._put({**record, "queued": True} if queued else record)

    def event(self, at: float, event: n.Event, source: str) -> None:
        """An event as it came, written as an events file writes it (language/event_trace.py)."""
        self._put({"type": "event", "t": self._t(at), "event": in_words(event), "source": source})

    def note(self, at: float, record: Dict[str, Any]) -> None:
        """`record` (its `type` and fields) at `at`: an end's own, as the studio's (`cleared`)."""
        self._put({"type": record["type"], "t": self._t(at), **record})

    def follow(self, session: Any) -> None:
        """The session's log lines since the last call, each with its kind; call it where the
        session's lines are read already (never from a frame loop that could wait for its lock)."""
        lines = session.lines_since(self.logged)
        self.logged = session.logged
        for line in lines:
            self._put({"type": "log", "t": self._t(line.at), "kind": line.kind, "text": line.text})

    def begun(self, timeline: Any, at: float) -> None:
        """A timeline the face began at `at` (LiveFace's `begun`): what it says, and when."""
        for said in timeline.speech:
            u = said.utterance
            length = round(u.duration, 4)
            self._put(
                {
                    "type": "say",
                    "t": self._t(at + said.at),
                    "text": u.said,
                    "voice": u.voice,
                    "length": length,
                }
            )

    def watch(self, face: Any) -> None:
        """Be told of every timeline `face` (a LiveFace) begins from now on."""
        face.begun = self.begun

    def waiting(self) -> int:
        """Records handed over and not yet written (a session on a fast clock waits for them)."""
        with self._cond:
            return len(self._records)

    def close(self, at: Optional[float] = None) -> None:
        """The shutdown's record; everything waiting written (a second at most), the file closed."""
        with self._cond:
            if self._closed:
                return
        self._put({"type": "end", "t": self._t(time.monotonic() if at is None else at)})
        with self._cond:
            self._closed = True
            self._cond.notify_all()
        self._thread.join(timeout=1.0)

    def _put(self, record: Dict[str, Any]) -> None:
        with self._cond:
            if self._closed or self._failed:
                return
            if len(self._records) >= MAX_WAITING:
                self._skipped += 1
                return
            self._records.append(record)
            self._cond.notify()

    # -- the writer

    def _work(self) -> None:
        while True:
            with self._cond:
                self._cond.wait_for(lambda: self._records or self._closed)
                batch: List[Dict[str, Any]] = list(self._records)
                self._records.clear()
                skipped, self._skipped = self._skipped, 0
                closed = self._closed
            if skipped:
                batch.append({"type": "skipped", "t": batch[-1]["t"] if batch else 0.0, "records": skipped})
            if batch and not self._failed:
                self._write(batch)
            if closed and not self._records:
                self._close_file()
                return

    def _write(self, batch: List[Dict[str, Any]]) -> None:
        try:
            for record in batch:
                line = (json.dumps(record, ensure_ascii=False) + "\n").encode("utf-8")
                if self._file is None:
                    self._open()
                elif self._size + len(line) > self.max_bytes and self._size > 0:
                    self._rotate(record["t"])
                self._file.write(line)
                self._size += len(line)
            self._file.flush()
        except OSError as e:
            self._failed = True
            why = e.strerror or str(e)
            self.warn(f"the session log {self.path} cannot be written ({why}): the face goes on without it")
            self._close_file()

    def _open(self) -> None:
        if os.path.isfile(self.path):  # a session before this one: kept as FILE.1
            self._shift()
        self._file = open(self.path, "wb")  # noqa: SIM115 - closed by the writer at the end
        self._size = 0

    def _rotate(self, t: float) -> None:
        self._close_file()
        self._shift()
        self._part += 1
        self._file = open(self.path, "wb")  # noqa: SIM115 - as above
        self._size = 0
        line = json.dumps({"type": "continued", "t": t, **self._wall, "part": self._part}) + "\n"
        self._file.write(line.encode("utf-8"))
        self._size += len(line)

    def _shift(self) -> None:
        """FILE to FILE.1, FILE.1 to FILE.2, ..., the oldest past `KEPT` let go."""
        for i in range(KEPT - 1, 0, -1):
            older = f"{self.path}.{i}"
            if os.path.exists(older):
                os.replace(older, f"{self.path}.{i + 1}")
        os.replace(self.path, f"{self.path}.1")

    def _close_file(self) -> None:
        if self._file is not None:
            with contextlib.suppress(OSError):
                self._file.close()
            self._file = None
