"""One live session: a script and its handlers on one face, events in, face states and robot cues out.

The clock is the caller's. `submit` takes text (handlers install themselves; other statements
become the main script), `post` an event at a time, `tick(now)` the face to show and the robot
cues that fell due. `render`, `play` and `explain --events` run the same session over an events
file (session_run.py), so a video shows what the robot would do.

The face does one thing at a time: the main script, or one handler's run. A handler whose event
comes while only the main script runs starts at once and pauses it; when no handler is left to
run, the main script goes on where it stopped (the statement cut short starts over; a `wait`
waits out what was left). An event whose handler cannot start because another runs follows its
handler's policy: `drop` ignores it (and counts it), `queue` runs it after, in turn, `interrupt`
stops the handler running and runs at once; `cooldown T` ignores the event for T seconds after
its handler last started. Every step is compiled by the engine's compiler from the face as it is
(`Carry`: what was begun finishes), except after an `interrupt`, which stops moves where they
are; whatever stops, its speech stops with it and the mouth comes to rest.

Every public method may be called from any thread (one lock). A frame loop that must never wait
for a compile (a `say` takes espeak-ng's time) calls `frame`, which never compiles, and leaves
`advance` to a worker of its own (session_intake.SessionIntake).
"""

from __future__ import annotations

import dataclasses
import itertools
import random
import threading
from collections import deque
from typing import TYPE_CHECKING, Any, Deque, Dict, List, Optional, Tuple

from ..core.face_constants import LIMITS
from ..core.face_state import FaceState
from ..language import syntax_tree as n
from ..language.diagnostics import Diagnostic, ScriptError
from ..language.events import TIMERS, in_words, matches
from ..language.parser import parse
from . import effects as fx
from .compiler import Carry, compile_script
from .effects import Cue
from .live_face import LiveFace
from .session_program import Await, Play, Raise, Runner
from .session_records import Handler, Logged, Run
from .timeline import Timeline

if TYPE_CHECKING:
    from ..speech.recordings import Recordings

MAX_QUEUE = 32  # events a `queue` handler holds; more are dropped, and counted
MAX_LOG = 10_000  # lines of the log a live session keeps
MAX_STEPS_AT_ONCE = 10_000  # steps one run may take without time passing (signals, zero-length moves)
MAX_STARTS_AT_ONCE = 100  # handler runs started without time passing: `on signal a { signal a }`


class LiveSession:
    """A script, its handlers and the events that reach them, on one face (see the module's docstring)."""

    def __init__(
        self,
        script: Optional[n.Script] = None,
        seed: Optional[int] = 0,
        now: float = 0.0,
        start: Optional[FaceState] = None,
        idle: bool = True,
        recordings: Optional[Recordings] = None,
        crossfade: Optional[float] = None,
        record: bool = False,
        log_lines: Optional[int] = MAX_LOG,
    ) -> None:
        """`record` keeps every timeline started, with its time (`segments`), for a render."""
        self.lock = threading.RLock()
        self.face = LiveFace(start or FaceState(), idle=idle, seed=seed, now=now, recordings=recordings)
        self.rng = random.Random(f"one of:{seed}")
        self.recordings = recordings
        self.crossfade = crossfade
        self.clock = now
        self.handlers: List[Handler] = []
        self.main: Optional[Run] = None
        self.active: Optional[Run] = None
        self.pending: Deque[Tuple[Handler, n.Event]] = deque()
        self.log: Deque[Logged] = deque(maxlen=log_lines)
        self.logged = 0  # lines ever logged: the log keeps the last `log_lines`
        self.segments: Optional[List[Tuple[float, Timeline]]] = [] if record else None
        self.cues: List[Cue] = []  # handed out by the next tick
        self.exited = False
        self.exited_at: Optional[float] = None  # when: a recorded run ends there
        self.ignored = 0  # events after the face exited
        self.last_event = now
        self._idle_fired: set = set()
        self._every: Dict[float, float] = {}
        self._burst = (now, 0)  # (an instant, the handler runs started at it)
        self.steps = 0  # steps played: a recorded run takes LIMITS.max_run_steps at most
        if script is not None:
            self.run(script, now)

    # -- in

    def submit(self, text: str, now: float, filename: str = "display_chatter") -> n.Script:
        """Parse `text` and `run` it at `now`; ScriptError if it is bad."""
        script = parse(text, filename)  # outside the lock: a long script parses while frames go on
        self.run(script, now)
        return script

    def run(self, script: n.Script, now: float) -> None:
        """Install `script`'s handlers (one for an event already handled replaces it); raise its
        signals, when that is all it says; or else make its statements the main script, stopping
        whatever runs."""
        with self.lock:
            self._run(script, now)

    def _run(self, script: n.Script, now: float) -> None:
        self.advance(now)
        at = self.clock
        for on in (s for s in script.body if isinstance(s, n.On)):
            key = (on.event.kind, on.event.arg, on.event.seconds)
            # Sent later, a handler replaces the one for its event; in one script, both are kept
            # (the first starts, the other follows its policy), as `check` says.
            kept = [
                h
                for h in self.handlers
                if h.script is script or (h.on.event.kind, h.on.event.arg, h.on.event.seconds) != key
            ]
            if len(kept) < len(self.handlers):
                self._note(at, f"{in_words(on.event)}: its handler replaced")
            self.handlers = kept + [Handler(on, script)]
            if on.event.kind == "every":
                self._every.setdefault(on.event.seconds, at + on.event.seconds)
        rest = [s for s in script.body if not isinstance(s, (n.On, n.Define))]
        if rest and all(isinstance(s, n.Signal) for s in rest) and self.main is not None:
            for s in rest:
                self.post(n.Event("signal", s.name), at, f"signal {s.name}")
            return
        if not rest and self.main is not None:
            return
        if self.active is not None:
            self._note(at, f"{self.active.label} stopped by a new script")
            self.active = None
        self.pending.clear()
        self._pause(self.main, at)
        self.main = Run(Runner(script.body, script.definitions, self.rng), script, "main script")
        self._go(self.main, at)

    def post(self, event: n.Event, at: float, source: str = "") -> None:
        """An event at `at` (the session's clock, if that is later): waits on it end, handlers run."""
        with self.lock:
            self.advance(at)
            self._dispatch(event, max(at, self.clock), source)

    # -- out

    def tick(self, now: float) -> Tuple[FaceState, List[Cue]]:
        """The face to show at `now`, and the robot cues that fell due since the last tick."""
        with self.lock:
            self.advance(now)
            state = self.face.state(now)
            cues, self.cues = self.cues + self.face.due(now), []
            return state, cues

    def frame(self, now: float) -> Tuple[FaceState, List[Cue]]:
        """`tick` for a frame loop that must not wait: never compiles, never waits for the lock.
        While a worker is busy, or a step falls due that it has still to take, the face is what
        plays (its idle life goes on) and the cues wait for a later frame."""
        cues: List[Cue] = []
        if self.lock.acquire(blocking=False):
            try:
                due = self.next_due()
                if due is None or due[0] > now:  # nothing to compile: time may pass here
                    self.clock = max(self.clock, now)
                    cues, self.cues = self.cues + self.face.due(now), []
            finally:
                self.lock.release()
        return self.face.state(now), cues

    def counts(self) -> Dict[str, Dict[str, int]]:
        """Each handler's runs, and the events it dropped and queued."""
        with self.lock:
            return {h.label: dict(runs=h.runs, dropped=h.dropped, queued=h.queued) for h in self.handlers}

    @property
    def resting(self) -> bool:
        """Is nothing left to do but wait for events: no handler running or queued, and the main
        script done, in a `forever`, or waiting for an event without a timeout?"""
        if self.exited:
            return True
        if self.active is not None or self.pending:
            return False
        main = self.main
        if main is None or main.done:
            return True
        waiting = (
            main.waiting is not None
            and main.waiting[0].timeout is None
            and main.waiting[0].event.kind != "idle"
        )
        return waiting or main.runner.forever

    # -- time

    def advance(self, until: float) -> None:
        """Do, at their own times and in order, whatever falls due up to `until`."""
        with self.lock:
            while True:
                due = self.next_due()
                if due is None or due[0] > until:
                    break
                self.clock = max(self.clock, due[0])
                due[1]()
            self.clock = max(self.clock, until)

    def next_due_at(self) -> Optional[float]:
        with self.lock:
            due = self.next_due()
            return None if due is None else due[0]

    def next_due(self) -> Optional[Tuple[float, Any]]:
        """The earliest thing the session does by itself, and how: (time, action); None if none."""
        if self.exited:
            return None
        found: List[Tuple[float, int, Any]] = []
        owner = self._owner()
        if owner is not None and owner.playing is not None:
            found.append((owner.playing[2], 0, lambda: self._played(owner)))
        for run in (self.main, self.active):
            if run is not None and run.waiting is not None:
                wait, since = run.waiting
                if wait.timeout is not None:
                    found.append((since + wait.timeout, 1, lambda run=run: self._timed_out(run)))
                if wait.event.kind == "idle":
                    at = max(since, self.last_event) + wait.event.seconds
                    found.append((at, 1, lambda run=run: self._woken(run, self.clock)))
        for period, at in self._every.items():
            found.append((at, 2, lambda period=period: self._tick_every(period)))
        for seconds in {h.on.event.seconds for h in self.handlers if h.on.event.kind == "idle"}:
            if seconds not in self._idle_fired:
                found.append((self.last_event + seconds, 3, lambda s=seconds: self._fire_idle(s)))
        if not found:
            return None
        at, _, action = min(found, key=lambda f: (f[0], f[1]))
        return at, action

    def _tick_every(self, period: float) -> None:
        self._every[period] += period
        self._dispatch(n.Event("every", seconds=period), self.clock, "")

    def _fire_idle(self, seconds: float) -> None:
        self._idle_fired.add(seconds)
        self._dispatch(n.Event("idle", seconds=seconds), self.clock, "")

    # -- events

    def _dispatch(self, event: n.Event, at: float, source: str) -> None:
        if self.exited:
            self.ignored += 1
            return
        if event.kind not in TIMERS:  # a timer's tick is told only by what it starts
            self._note(at, f"event {in_words(event)}" + (f" ({source})" if source else ""))
            self.last_event = at
            self._idle_fired.clear()
        for run in (self.main, self.active):
            if run is not None and run.waiting is not None and matches(run.waiting[0].event, event):
                self._woken(run, at, go=False)
        for handler in [h for h in self.handlers if matches(h.on.event, event)]:
            self._offer(handler, event, at)
        owner = self._owner()
        if owner is not None and self._ready(owner):
            self._go(owner, at)

    def _offer(self, handler: Handler, event: n.Event, at: float) -> None:
        on = handler.on
        if on.cooldown and handler.last_start is not None and at < handler.last_start + on.cooldown:
            handler.dropped += 1
            until = handler.last_start + on.cooldown
            self._note(at, f"dropped {in_words(event)}: {handler.label} cools down till {until:.2f} s")
            return
        if self.active is None:
            self._start(handler, at, cut=on.policy == "interrupt")
        elif on.policy == "drop":
            handler.dropped += 1
            whose = "" if self.active.handler is handler else f" for {handler.label}"
            self._note(at, f"dropped {in_words(event)}{whose}: {self.active.label} is running")
        elif on.policy == "queue":
            if sum(1 for h, _ in self.pending if h is handler) >= MAX_QUEUE:
                handler.dropped += 1
                self._note(at, f"dropped {in_words(event)}: {handler.label} has {MAX_QUEUE} queued")
            else:
                handler.queued += 1
                self.pending.append((handler, event))
                self._note(at, f"queued {in_words(event)} for {handler.label}")
        else:
            self._note(at, f"{self.active.label} interrupted")
            self._pause(self.active, at)  # it may be between steps: raising this very signal
            self.active = None
            self._start(handler, at, cut=True)

    def _start(self, handler: Handler, at: float, cut: bool) -> bool:
        """Start a run of `handler`; False if handlers have started one another too often at `at`,
        a loop that takes no time (each start is a level deeper in this call)."""
        started = self._burst[1] + 1 if self._burst[0] == at else 1
        self._burst = (at, started)
        if started > MAX_STARTS_AT_ONCE:
            handler.dropped += 1
            self.pending.clear()
            if started == MAX_STARTS_AT_ONCE + 1:
                self._note(
                    at,
                    f"{handler.label} not run: {MAX_STARTS_AT_ONCE} handler runs began "
                    "without time passing (handlers that raise each other's signals?)",
                )
            return False
        handler.runs += 1
        handler.last_start = at
        if self.main is not None:
            self._pause(self.main, at)
        script = handler.script
        run = Run(Runner(handler.on.body, script.definitions, self.rng), script, handler.label, handler)
        run.carry = not cut
        self.active = run
        self._note(at, f"{handler.label} runs")
        self._go(run, at)
        return True

    # -- runs

    def _owner(self) -> Optional[Run]:
        return self.active if self.active is not None else self.main

    @staticmethod
    def _ready(run: Run) -> bool:
        return not run.done and run.playing is None and run.waiting is None

    def _pause(self, run: Optional[Run], at: float) -> None:
        if run is not None and run.playing is not None:
            self._cut(run, at)

    def _cut(self, run: Run, at: float) -> None:
        play, start, _ = run.playing  # type: ignore[misc]
        run.runner.cut(play, at - start)
        run.playing = None

    def _woken(self, run: Run, at: float, go: bool = True) -> None:
        run.waiting = None
        if go and run is self._owner():
            self._go(run, at)

    def _timed_out(self, run: Run) -> None:
        wait, _ = run.waiting  # type: ignore[misc]
        self._note(self.clock, f"{run.label}: 'wait until {in_words(wait.event)}' timed out")
        self._woken(run, self.clock)

    def _played(self, run: Run) -> None:
        run.playing = None
        run.carry = True
        if run.exiting:
            self._exit()
        else:
            self._go(run, self.clock)

    def _go(self, run: Run, at: float) -> None:
        """Take `run`'s steps from `at` until one takes time, waits, or hands the face on."""
        for _ in range(MAX_STEPS_AT_ONCE):
            if run is not self._owner() or not self._ready(run):
                return
            step = run.runner.next()
            if step is None:
                self._finished(run, at)
                return
            if isinstance(step, Play):
                self._play(run, step, at)
                return
            if isinstance(step, Await):
                run.waiting = (step.statement, at)
                continue
            if isinstance(step, Raise):
                self._dispatch(n.Event("signal", step.statement.name), at, f"line {step.statement.pos.line}")
        self._note(at, f"{run.label} stopped: it took {MAX_STEPS_AT_ONCE} steps without time passing")
        self._finished(run, at)

    def _finished(self, run: Run, at: float) -> None:
        run.done = True
        self._note(at, f"{run.label} ends")
        if run is not self.active:
            return
        self.active = None
        if self.pending:
            handler, _ = self.pending.popleft()
            if self._start(handler, at, cut=False):
                return
        if self.main is not None and not self.main.done and self.active is None:
            self._note(at, "main script goes on")
            self._go(self.main, at)

    def _play(self, run: Run, step: Play, at: float) -> None:
        self.steps += 1
        if self.segments is not None and self.steps > LIMITS.max_run_steps:
            steps = f"{LIMITS.max_run_steps:,}"
            why = f"the run takes more than {steps} steps by {at:.1f} s: a 'forever' of very short rounds?"
            raise ScriptError([Diagnostic(0, 0, why)], run.script.filename, run.script.source)
        playing, started = self.face.timeline, self.face.started
        self.cues.extend(self.face.due(at))
        into = at - started
        script = n.Script(
            tuple(run.script.definitions.values()) + (step.statement,),
            run.script.filename,
            source=run.script.source,
            legacy=run.script.legacy,  # the old node's commands cut, as the old node did
        )
        timeline = self._compile(script, at_rest(playing, into), Carry(playing, into) if run.carry else None)
        run.carry = True
        self.face.begin(timeline, at)
        if self.segments is not None:
            self.segments.append((at, timeline))
        exits = any(isinstance(c.effect, fx.ShutDown) for c in timeline.cues)
        length = timeline.duration if exits else max((s.end for s in timeline.spans), default=0.0)
        run.exiting = exits
        run.playing = (step, at, at + length)

    def _compile(self, script: n.Script, start: FaceState, carry: Optional[Carry]) -> Timeline:
        from ..speech.recordings import RecordingError

        seed = self.face.rng.randrange(2**32)
        try:
            return compile_script(
                script, seed, start, self.crossfade, recordings=self.recordings, carry=carry
            )
        except RecordingError as e:  # found only in saying it: a text espeak-ng crashed on
            raise ScriptError([e.diagnostic()], script.filename, script.source) from None

    def _exit(self) -> None:
        self._note(self.clock, "the face exits")
        self.exited, self.exited_at = True, self.clock
        self.active = None
        self.pending.clear()

    def _note(self, at: float, text: str) -> None:
        self.log.append(Logged(at, text))
        self.logged += 1

    def lines_since(self, logged: int) -> List[Logged]:
        """The log's lines after the first `logged` ever logged (those it still keeps)."""
        with self.lock:
            new = min(self.logged - logged, len(self.log))
            return list(itertools.islice(reversed(self.log), new))[::-1]  # the new only: a storm


def at_rest(timeline: Timeline, t: float) -> FaceState:
    """The face at `t` with its speech stopped: the mouth as the expression has it, at rest."""
    if not timeline.sounding(t):
        return timeline.sample(t)
    return dataclasses.replace(timeline, speech=[]).sample(t)
