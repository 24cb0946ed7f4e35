"""A live session driven by a worker thread of its own, so a frame loop never waits for a compile.

The intake of the face node's, `stream`'s and the screen's `LiveSession`: each command is parsed
and compiled on a thread of its own. Commands and events come in from any thread (ROS callbacks,
the screen's requests), stamped with the clock as they arrive; the worker
parses, hands them to the session in the order they came, and advances the session whenever
something falls due (a step's end, a timeout, `every`, `idle`), compiling each step there. The
frame loop lets time pass with `LiveSession.catch_up` and reads the face, neither of which compiles.

What waits is bounded, and nothing is lost unsaid. Commands are read in the order they came. A
command that takes over, read while a later one waits, would be replaced the moment it started:
its main statements are let go (counted in `dropped`), but its handlers and signals are taken, so
a batch of handler lines sent back to back installs every one. At most `max_unread` commands,
`max_pending` queued ones among them, wait to be read, and `max_queue` read ones wait their turn;
at most `max_events` events wait for the worker (a storm beyond that is counted in
`events_dropped`, never held). Past a bound an input is refused, and the refusal says why.
A queued command (`~queue`) starts when the face is free: no handler running or waiting and the
main script done. `signal NAME` alone raises the signal without the parser (a storm of them
costs a dictionary look-up each), and never takes over.

A sender that must answer what its input did (the screen's HTTP requests) hands it over with
`take` or `posting` and gets a future, done once the worker has handed it to the session (a
failure to compile is the future's, not the log's); `settled` waits until everything handed over
so far is in the session. The sender waits, on a thread of its own or in its event loop; the
frame loop never does.
"""

from __future__ import annotations

import contextlib
import re
import threading
from collections import deque
from concurrent.futures import Future
from typing import Callable, Deque, Dict, List, Optional, Tuple, Union

from ..closing import ClosedOnExit
from ..extras import MissingTool
from ..language import syntax_tree as n
from ..language.diagnostics import Diagnostic, ScriptError
from ..language.parser import parse
from ..speech.recordings import RecordingError
from .live_session import LiveSession
from .session_log_file import SessionLogFile
from .session_records import LogKind

# What a node's log shows of the session's: every event and drop stays in the session's log and
# counts, as a storm must not flood ROS's.
FORWARDED = (LogKind.REPLACED, LogKind.STOPPED, LogKind.TIMED_OUT)

MAX_PENDING = 8  # queued commands waiting to be read
MAX_UNREAD = 1000  # commands of any kind waiting to be read
MAX_QUEUE = 32  # queued scripts read and waiting their turn
MAX_EVENTS = 10_000  # events waiting for the worker
BATCH = 1000  # inputs taken in one go before the session's time is advanced

# `signal NAME` sent alone: raised without the parser, never a take-over (stream takes only these).
SIGNAL_ALONE = re.compile(r"\s*signal\s+([A-Za-z_][A-Za-z0-9_]*)\s*;?\s*", re.IGNORECASE)
Log = Callable[[str, str], None]  # (level, text)
Sent = Union[str, n.Script]  # a command as sent: its text, or a script its sender has read already


class Refused(Exception):
    """An input the intake could not take: too many are waiting (the reason is the message)."""


def said_ahead(script: n.Script) -> bool:
    """Synthesise what the script's first statement says (a `say`, an `ask`'s question), kept by
    the speech engines for its compile; whether it says anything. A text that cannot be said is
    left for the compile to refuse."""
    from .compiler import engine_say

    first = next((s for s in script.body if not isinstance(s, (n.On, n.Define, n.State))), None)
    says: List[n.Say] = []
    ahead = [] if first is None else [first]
    while ahead:  # its blocks' statements too, but of an `ask` only the question: answers come later
        s = ahead.pop()
        if isinstance(s, (n.Say, n.Ask)):
            says.append(s.question if isinstance(s, n.Ask) else s)
        elif isinstance(s, n.BLOCKS):
            ahead.extend(reversed(s.body))
    texts = [s for s in says if s.file is None]
    for say in texts:
        with contextlib.suppress(Exception):  # noqa: BLE001 - the compile says why, in one line
            engine_say(say.text, say.voice, say.rate)
    return bool(texts)


def _totals(session: LiveSession) -> Dict[str, int]:
    """Every handler's counts together (not by label: two scripts' handlers may share a line)."""
    with session.lock:
        handlers = session.handlers
        return {key: sum(getattr(h, key) for h in handlers) for key in ("runs", "dropped", "queued")}


def _kept_of(script: n.Script) -> Optional[n.Script]:
    """A take-over replaced before it started: what of it still counts (its handlers, states,
    definitions and signals), or None if it said nothing else (it is taken as it is)."""
    kept = tuple(s for s in script.body if isinstance(s, (n.On, n.State, n.Define, n.Signal)))
    if len(kept) == len(script.body):
        return None
    return n.Script(kept, script.filename, source=script.source, legacy=script.legacy)


class SessionIntake(ClosedOnExit):
    """Commands and events in (from any thread); the session advanced on a worker (see above)."""

    def __init__(
        self,
        session: LiveSession,
        clock: Callable[[], float],
        ready: Callable[[], None] = lambda: None,
        log: Log = lambda level, text: None,
        filename: str = "display_chatter",
        max_pending: int = MAX_PENDING,
        max_queue: int = MAX_QUEUE,
        max_events: int = MAX_EVENTS,
        max_unread: int = MAX_UNREAD,
        record: Optional[SessionLogFile] = None,
    ) -> None:
        """`record`: the session's log file, told of each input as the worker takes it and of
        the session's log lines as they come (never by the frame loop)."""
        self.session = session
        self.clock = clock
        self.ready = ready  # called after the worker changed something: wakes the frame loop
        self.log = log
        self.filename = filename
        self.max_pending, self.max_queue, self.max_events = max_pending, max_queue, max_events
        self.max_unread = max_unread
        self._arrived = 0  # orders commands and events as they came
        self._handled = 0  # the last of them the worker has handed to the session (or let go)
        # Each with the future its sender waits on, if it waits: (order, text, time, future).
        self._takeovers: Deque[Tuple[int, Sent, float, Optional[Future]]] = deque()  # unread
        self._texts: Deque[Tuple[int, Sent, float, Optional[Future]]] = deque()  # queued, unread
        self._events: Deque[Tuple[int, n.Event, float, str, Optional[Future]]] = deque()
        self.waiting: Deque[n.Script] = deque()  # queued scripts, read, waiting for the face
        self.dropped = 0
        self.events_dropped = 0
        self.posted = 0  # events handed to the session
        self.counts: Dict[str, Dict[str, int]] = {}  # the session's, as the worker last left it
        self._logged = session.logged
        self._forwarded: Dict[str, Tuple[float, int]] = {}  # a text forwarded: when, repeats hidden since
        self._cond = threading.Condition()
        self._closed = False
        self.busy = False
        self.record = record
        if record is not None:
            record.logged = session.logged
            record.watch(session.face)
        self._thread = threading.Thread(target=self._work, name="baxterface-session", daemon=True)
        self._thread.start()

    # -- in, from any thread

    def submit(self, text: str, queued: bool = False) -> Optional[str]:
        """Hand a command over; returns why it was refused, or None."""
        signal = SIGNAL_ALONE.fullmatch(text)
        if signal is not None:
            return self.post(n.Event("signal", signal.group(1).lower()), self.filename)
        return self._hand(text, queued, None)

    def take(self, script: n.Script, queued: bool = False) -> Future:
        """Hand over a script already read, to take over as a command does (or, `queued`, to wait
        for the face to be free): a future, done (None) once the session has it, or holding the
        ScriptError that stopped it."""
        done: Future = Future()
        refusal = self._hand(script, queued, done)
        if refusal is not None:
            done.set_exception(Refused(refusal))
        return done

    def _hand(self, sent: Sent, queued: bool, done: Optional[Future]) -> Optional[str]:
        with self._cond:
            if self._closed:
                return "refused a command: the face has stopped"
            if queued and len(self._texts) >= self.max_pending:
                return f"refused a queued script: {self.max_pending} are already waiting to be read"
            if len(self._texts) + len(self._takeovers) >= self.max_unread:
                return f"refused a command: {self.max_unread} are already waiting to be read"
            self._arrived += 1
            (self._texts if queued else self._takeovers).append((self._arrived, sent, self.clock(), done))
            self._cond.notify()
        return None

    def post(self, event: n.Event, source: str = "", done: Optional[Future] = None) -> Optional[str]:
        """Hand an event over, at the clock's time now; returns why it was refused, or None."""
        with self._cond:
            if self._closed:
                return f"dropped event {event.kind}: the face has stopped"
            if len(self._events) >= self.max_events:
                self.events_dropped += 1
                return f"dropped event {event.kind}: {self.max_events} are waiting"
            self._arrived += 1
            self._events.append((self._arrived, event, self.clock(), source, done))
            self._cond.notify()
        return None

    def posting(self, event: n.Event, source: str = "") -> Future:
        """`post`, with a future: what the event did once the session has it (the handlers' runs,
        dropped and queued it moved, a dict), or the error (Refused, or a handler's ScriptError)."""
        done: Future = Future()
        refusal = self.post(event, source, done)
        if refusal is not None:
            done.set_exception(Refused(refusal))
        return done

    def settled(self, timeout: Optional[float] = None) -> bool:
        """Wait until all handed over so far is in the session (False: `timeout` passed first)."""
        with self._cond:
            until = self._arrived
            return self._cond.wait_for(lambda: self._handled >= until or self._closed, timeout)

    def close(self) -> None:
        with self._cond:
            self._closed = True
            self._cond.notify_all()
            # Nothing will take what still waits: its senders are let go.
            for item in [*self._takeovers, *self._texts, *self._events]:
                if item[-1] is not None:
                    item[-1].cancel()
        if self.record is not None:  # its last record: the shutdown
            self.record.close(self.clock())

    def idle(self) -> bool:
        """Nothing waiting to be read or handed over, and the worker not busy."""
        with self._cond:
            return not self._takeovers and not self._texts and not self._events and not self.busy

    # -- the worker

    def _work(self) -> None:
        while True:
            with self._cond:
                while not self._closed and not self._has_input():
                    wait = self._until_due()
                    if wait is not None and wait <= 0:
                        break
                    self._cond.wait(wait)
                if self._closed:
                    return
                self.busy = True
            shown = self.session.face.timeline
            try:
                for _ in range(BATCH):  # what came meanwhile, in one go: one wake of the loop a batch
                    with self._cond:
                        item = self._next_input()
                    if item is None:
                        break
                    try:
                        self._do(item)
                        if self.record is not None:
                            self.record.follow(self.session)
                    finally:
                        with self._cond:
                            self._handled = item[2]
                            self._cond.notify_all()
                self.session.advance(self.clock())
                self._start_queued()
                self._forward_log()
                if self.record is not None:
                    self.record.follow(self.session)
                self.counts = self.session.counts()
            except Exception as e:  # noqa: BLE001 - a bug in one step must not stop the face for good
                self.log("error", f"the live session failed: {type(e).__name__}: {e}")
            finally:
                self.busy = False
            if self.session.face.timeline is not shown:  # a step began: show it now, not next tick
                self.ready()

    def _has_input(self) -> bool:
        return bool(self._takeovers) or bool(self._texts) or bool(self._events)

    def _until_due(self) -> Optional[float]:
        with self.session.lock:
            due = self.session.next_due()
        return None if due is None else due[0] - self.clock()

    def _next_input(self):
        """The input that came first, or None (only time passed)."""
        firsts = []
        if self._takeovers:
            firsts.append((self._takeovers[0][0], "take over"))
        if self._texts:
            firsts.append((self._texts[0][0], "queue"))
        if self._events:
            firsts.append((self._events[0][0], "event"))
        if not firsts:
            return None
        _, kind = min(firsts)
        if kind == "take over":
            item = self._takeovers.popleft()
            return (kind, bool(self._takeovers)) + item
        if kind == "queue":
            return (kind, False) + self._texts.popleft()
        return (kind, False) + self._events.popleft()

    def _note(self, item) -> None:
        """The input, as it came and when it took effect, in the session's log file (if it has one)."""
        if self.record is None:
            return
        if item[0] == "event":
            _, _, _, event, at, source, _ = item
            self.record.event(at, event, source)
            return
        kind, _, _, said, at, _ = item
        text = said.source if isinstance(said, n.Script) else said
        name = said.filename if isinstance(said, n.Script) else self.filename
        self.record.script(at, text, name, kind == "queue")

    def _taking(self, item, at: float):
        """`item` as it takes effect: at `at`, or at the session's clock if a frame moved it past
        that meanwhile; noted in the log file at that time. Called with the session's lock held,
        until the item is taken, so the log's time is the one the session used."""
        item = (*item[:4], max(at, self.session.clock), *item[5:])
        self._note(item)
        return item

    def _do(self, item) -> None:
        if item[0] == "event":
            with self.session.lock:
                _, _, _, event, at, source, done = self._taking(item, item[4])
                self._post(event, at, source, done)
            return
        kind, replaced, _, said, at, done = item
        if done is not None and not done.set_running_or_notify_cancel():
            with self.session.lock:
                self._taking(item, at)
            return
        script = self._read(said)
        if script is not None and said_ahead(script):
            # Its first words synthesised before it starts (outside the lock: frames go on): it
            # starts now, its speech whole, where starting at its arrival would have cut the
            # synthesis's time (a natural voice's 20 to 190 ms) from its sound and mouth.
            at = max(at, self.clock())
        with self.session.lock:
            at = self._taking(item, at)[4]
            if script is not None:
                self._start(kind, replaced, script, at, done)

    def _post(self, event: n.Event, at: float, source: str, done: Optional[Future]) -> None:
        self.posted += 1
        if done is None:
            self.session.post(event, at, source)
            return
        if done.set_running_or_notify_cancel():
            try:  # what this event did, counted as it is handed over: others may come meanwhile
                before = _totals(self.session)
                self.session.post(event, at, source)
                after = _totals(self.session)
                done.set_result({k: after[k] - before[k] for k in after})
            except Exception as e:  # noqa: BLE001 - its sender answers it
                done.set_exception(e)

    def _start(self, kind: str, replaced: bool, script: n.Script, at: float, done: Optional[Future]) -> None:
        kept = _kept_of(script) if replaced else None
        if kept is not None:  # another take-over waits: this one would be replaced as it started
            self.dropped += 1
            script = kept
        if kind == "queue" and (self.waiting or not self.session.free):
            if len(self.waiting) >= self.max_queue:
                self.log("warn", f"refused a queued script: the queue is full ({self.max_queue} scripts)")
            else:
                self.waiting.append(script)
            return
        if kind == "take over":
            self.waiting.clear()
        self._run(script, at, done)

    def _read(self, text: Sent) -> Optional[n.Script]:
        if isinstance(text, n.Script):
            return text
        try:
            script = parse(text, self.filename)
            recordings = self.session.recordings
            # A recording's length is in its header, which parsing does not read: checked here.
            unsaid = recordings.check(script) if recordings is not None and "file" in text.lower() else []
            if unsaid:
                raise ScriptError(unsaid, self.filename, text)
            return script
        except ScriptError as e:
            self.log("error", f"bad command: {e.summary()}")
        except RecordingError as e:
            self.log("error", f"bad command: {ScriptError([e.diagnostic()], self.filename, text).summary()}")
        return None

    def _run(self, script: n.Script, at: float, done: Optional[Future] = None) -> None:
        try:
            self.session.run(script, at)
        except MissingTool as e:  # `say` on a machine without a speech engine: refused, not fatal
            self._bad(ScriptError([Diagnostic(0, 0, str(e))], self.filename), done)
        except RecordingError as e:
            self._bad(ScriptError([e.diagnostic()], self.filename), done)
        except ScriptError as e:
            self._bad(e, done)
        except Exception as e:  # noqa: BLE001 - a bug: its sender answers it, the worker logs it
            if done is not None:
                done.set_exception(e)
            raise
        else:
            if done is not None:
                done.set_result(None)

    def _bad(self, error: ScriptError, done: Optional[Future] = None) -> None:
        if done is not None:  # its sender tells it
            done.set_exception(error)
        else:
            self.log("error", f"bad command: {error.summary()}")

    def _start_queued(self) -> None:
        while self.waiting and self.session.free and not self.session.exited:
            self._run(self.waiting.popleft(), self.session.clock)
            self.session.advance(self.clock())

    def _forward_log(self) -> None:
        """The session's lines a node's log should show: handlers replaced, runs stopped, failures.
        Every event and drop stays in the session's log and counts: a storm must not flood ROS's."""
        lines = self.session.lines_since(self._logged)
        self._logged = self.session.logged
        for line in lines:
            if line.kind in FORWARDED:
                self._forward(line.at, line.text)

    def _forward(self, at: float, text: str) -> None:
        """One line of a kind a second at most (a `forever` of waits that time out repeats its
        line every round): the repeats are counted, and the count goes with the next one shown."""
        last, hidden = self._forwarded.get(text, (None, 0))
        if last is not None and at - last < 1.0:
            self._forwarded[text] = (last, hidden + 1)
            return
        if len(self._forwarded) > 1000:  # texts that name a line or a time: forget the old ones
            self._forwarded.clear()
        self._forwarded[text] = (at, 0)
        self.log("info", text + (f" ({hidden} more like it in the second before)" if hidden else ""))
