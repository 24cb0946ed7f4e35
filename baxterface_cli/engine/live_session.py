"""One live session: a script and its handlers on one face, events in, face states and robot cues out.

The clock is the caller's: `run` takes a script, `post` an event, `tick(now)` gives the face and
the robot cues due (`frame`, for a loop that must never wait for a compile, leaves `advance` to a
worker: session_intake.py). Every public method may be called from any thread (one lock). `render`,
`play` and `explain --events` run the same session over an events file (session_run.py).

The face does one thing at a time: the main script (or the state it entered), or one handler's
run, which pauses the main script until no handler is left; an event whose handler cannot start
follows its policy (docs/language.md). Each step is compiled from the face as it is
(session_steps.py). Whatever a script says, the session keeps time: a `forever`'s round lasts
`LIMITS.least_round` at least; handlers are bounded (session_handlers.py); what happens at one
instant is bounded and taken in one loop (`_drive`), never a call deeper; a live face (`keep_up`)
that falls behind its clock stops the run doing it; a recorded run counts every step.
"""

from __future__ import annotations

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
from .effects import Cue
from .live_face import LiveFace
from .session_handlers import EveryClock, by_kind, install, key_of, why_dropped
from .session_program import Await, Goto, Lap, Play, Runner
from .session_records import Handler, Logged, LogKind, Run
from .session_states import States
from .session_steps import compile_step, round_rest
from .timeline import Timeline

if TYPE_CHECKING:
    from ..speech.recordings import Recordings

MAX_LOG = 10_000  # lines of the log a live session keeps
MAX_STEPS_AT_ONCE = 10_000  # steps one run may take without time passing (signals, zero-length moves)
MAX_STARTS_AT_ONCE = 100  # handler runs started without time passing: `on signal a { signal a }`
MAX_BEHIND = 200  # due steps a live face takes while `LIMITS.max_lag` behind, before it stops their run


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
        keep_up: bool = False,
    ) -> None:
        """`record` keeps every timeline started, with its time (`segments`), for a render;
        `keep_up` is for a face on a real clock, which stops a run that cannot keep time."""
        self.lock = threading.RLock()
        self.face = LiveFace(start or FaceState(), idle=idle, seed=seed, now=now, recordings=recordings)
        self.rng = random.Random(f"one of:{seed}")
        self.recordings = recordings
        self.crossfade = crossfade
        self.clock = now
        self.handlers: List[Handler] = []  # swapped whole when it changes: read without the lock
        self._kinds: Dict[str, List[Handler]] = {}  # the handlers of each kind of event
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
        self._every = EveryClock()
        self.states = States()  # the states installed, the one the face is in
        self._burst = (now, 0)  # (an instant, the handler runs started at it)
        self.steps = 0  # steps taken: a recorded run takes LIMITS.max_run_steps at most
        self.keep_up = keep_up
        self._behind = 0  # due steps taken in a row while LIMITS.max_lag behind the clock
        self._driving = False  # `_drive` is under way, further up this call
        if script is not None:
            self.run(script, now)

    # -- in

    def run(self, script: n.Script, now: float) -> None:
        """Install `script`'s handlers (one for an event already handled replaces it); raise its
        signals, when that is all it says; or else make its statements the main script, stopping
        whatever runs."""
        with self.lock:
            self._run(script, now)

    def _run(self, script: n.Script, now: float) -> None:
        self.advance(now)
        at = self.clock
        handlers, replaced = install(self.handlers, script)  # ScriptError past the bounds: nothing done
        for event in {key_of(h): h.on.event for h in replaced}.values():
            self._note(at, LogKind.REPLACED, f"{in_words(event)}: its handler replaced")
        self.states.install(script)
        if handlers is not self.handlers:
            self.handlers, self._kinds = handlers, by_kind(handlers)
            self.last_event, self._idle_fired = max(self.last_event, at), set()  # `idle` from its arrival
            for h in self._kinds.get("every", ()):
                self._every.add(h.on.event.seconds, at)
        rest = [s for s in script.body if not isinstance(s, (n.On, n.Define, n.State))]
        if rest and all(isinstance(s, n.Signal) for s in rest) and self.main is not None:
            for s in rest:
                self.post(n.Event("signal", s.name), at, f"signal {s.name}")
            return
        if not rest and self.main is not None:
            return
        if self.active is not None:
            self._note(at, LogKind.TAKEN_OVER, f"{self.active.label} stopped by a new script")
            self.active = None
        self.pending.clear()
        self._pause(self.main, at)
        self.main = Run(Runner(script.body, script.definitions, self.rng), script, "main script")
        self._drive(at)

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

    @property
    def free(self) -> bool:
        """Is the face free for a queued script: no handler running or waiting, the main script done?
        (Read without the lock too, by a loop that must not wait: each of these is swapped whole.)"""
        main = self.main
        return self.active is None and not self.pending and (main is None or main.done)

    def counts(self) -> Dict[str, Dict[str, int]]:
        """Each handler's runs, and the events it dropped and queued."""
        with self.lock:
            return {h.label: dict(runs=h.runs, dropped=h.dropped, queued=h.queued) for h in self.handlers}

    # -- time

    def advance(self, until: float) -> None:
        """Do, at their own times and in order, whatever falls due up to `until`."""
        with self.lock:
            while True:
                due = self.next_due()
                if due is None or due[0] > until:
                    break
                if self.keep_up and until - due[0] > LIMITS.max_lag:
                    self._behind += 1
                    if self._behind > MAX_BEHIND:
                        self._fall_behind(until)
                        continue
                self.clock = max(self.clock, due[0])
                due[1]()
            self._behind = 0
            self.clock = max(self.clock, until)

    def _fall_behind(self, now: float) -> None:
        """A live face that cannot keep time: the run whose steps fell due long ago is stopped, the
        `every` ticks missed meanwhile are let go, and the face goes on from `now`."""
        self._behind = 0
        run = self._owner()
        if run is not None and not run.done:
            why = f"{now - self.clock:.1f} s behind the clock, its steps too short to keep time"
            self._note(self.clock, LogKind.STOPPED, f"{run.label} stopped: {why}")
            run.playing = run.waiting = None
            self._finished(run, self.clock)
        self._every.skip_past(now)
        self.clock = max(self.clock, now)
        self._drive(self.clock)

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
        tick = self._every.first()
        if tick is not None:
            found.append((tick[0], 2, self._tick_every))
        for seconds in {h.on.event.seconds for h in self._kinds.get("idle", ()) if self.states.live(h.state)}:
            if seconds not in self._idle_fired:
                found.append((self.last_event + seconds, 3, lambda s=seconds: self._fire_idle(s)))
        if not found:
            return None
        at, _, action = min(found, key=lambda f: (f[0], f[1]))
        return at, action

    def _tick_every(self) -> None:
        period = self._every.tick()
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
            self._note(at, LogKind.EVENT, f"event {in_words(event)}" + (f" ({source})" if source else ""))
            self.last_event = at
            self._idle_fired.clear()
        for run in (self.main, self.active):
            if run is not None and run.waiting is not None and matches(run.waiting[0].event, event):
                self._woken(run, at, go=False)
        live = [h for h in self._kinds.get(event.kind, ()) if self.states.live(h.state)]
        for handler in [h for h in live if matches(h.on.event, event)]:
            self._offer(handler, event, at)
        self._drive(at)

    def _offer(self, handler: Handler, event: n.Event, at: float) -> None:
        queued = sum(1 for h, _ in self.pending if h is handler)
        why = why_dropped(handler, at, self.active, queued)
        if why is not None:
            handler.dropped += 1
            self._note(at, LogKind.DROPPED, f"dropped {in_words(event)}{why}")
        elif self.active is None:
            self._start(handler, at, cut=handler.on.policy == "interrupt")
        elif handler.on.policy == "queue":
            handler.queued += 1
            self.pending.append((handler, event))
            self._note(at, LogKind.QUEUED, f"queued {in_words(event)} for {handler.label}")
        else:
            self._note(at, LogKind.INTERRUPTED, f"{self.active.label} interrupted")
            self._pause(self.active, at)  # it may be between steps: raising this very signal
            self.active = None
            self._start(handler, at, cut=True)

    def _start(self, handler: Handler, at: float, cut: bool) -> bool:
        """Start a run of `handler` (`_drive` takes its steps); False if handlers have started one
        another too often at `at`, a loop that takes no time."""
        started = self._burst[1] + 1 if self._burst[0] == at else 1
        self._burst = (at, started)
        if started > MAX_STARTS_AT_ONCE:
            handler.dropped += 1
            self.pending.clear()
            if started == MAX_STARTS_AT_ONCE + 1:
                self._note(
                    at,
                    LogKind.STOPPED,
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
        self._note(at, LogKind.STARTED, f"{handler.label} runs")
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
        if go:
            self._drive(at)

    def _timed_out(self, run: Run) -> None:
        wait, _ = run.waiting  # type: ignore[misc]
        said = f"'wait until {in_words(wait.event)}'"
        self._note(self.clock, LogKind.TIMED_OUT, f"{run.label}: {said} timed out")
        self._woken(run, self.clock)

    def _played(self, run: Run) -> None:
        run.playing = None
        run.carry = True
        if run.exiting:
            self._exit()
        else:
            self._drive(self.clock)

    def _drive(self, at: float) -> None:
        """Take the steps of whichever run has the face, from `at`, until one takes time or waits,
        or nothing is left to run. A signal, a handler starting or a run ending is taken here in
        turn, never a call deeper: a thousand signals in a row cost no stack."""
        if self._driving:
            return  # the loop further up this call goes on with whatever changed
        self._driving = True
        taken: Dict[int, int] = {}
        try:
            while True:
                run = self._owner()
                if run is None or not self._ready(run):
                    return
                taken[id(run)] = taken.get(id(run), 0) + 1
                if taken[id(run)] > MAX_STEPS_AT_ONCE:
                    why = f"it took {MAX_STEPS_AT_ONCE} steps without time passing"
                    self._note(at, LogKind.STOPPED, f"{run.label} stopped: {why}")
                    self._finished(run, at)
                    continue
                self._step(run, at)
        finally:
            self._driving = False

    def _step(self, run: Run, at: float) -> None:
        self.steps += 1
        if self.segments is not None and self.steps > LIMITS.max_run_steps:
            steps = f"{LIMITS.max_run_steps:,}"
            why = f"the run takes more than {steps} steps by {at:.1f} s: a 'forever' of very short rounds?"
            raise ScriptError([Diagnostic(0, 0, why)], run.script.filename, run.script.source)
        step = run.runner.next()
        if step is None:
            self._finished(run, at)
        elif isinstance(step, Play):
            self._play(run, step, at)
        elif isinstance(step, Await):
            run.waiting = (step.statement, at)
        elif isinstance(step, Goto):
            self._go_to(run, step.statement, at)
        elif isinstance(step, Lap):
            rest = round_rest(step.frame, at)  # a wait that begins nothing new: nothing to compile
            if rest is not None:
                run.playing = (rest, at, at + rest.statement.duration)
        else:
            self._dispatch(n.Event("signal", step.statement.name), at, f"line {step.statement.pos.line}")

    def _go_to(self, run: Run, go: n.Go, at: float) -> None:
        """`go NAME` in `run`: what runs stops as an `interrupt` stops it, and the state's body
        becomes what the face does (session_states.py); or one line saying why it cannot."""
        name, why = self.states.target(go, at)
        said = f"line {go.pos.line} 'go {go.name}'"
        if name is None:
            self._note(at, LogKind.STOPPED, f"{run.label}: {said} {why}")
            if why.startswith("stopped"):
                self._finished(run, at)
            return
        if self.active is not None and self.active is not run:
            self._note(at, LogKind.TAKEN_OVER, f"{self.active.label} stopped: the face goes to state {name}")
        self._pause(self.active, at)
        self.active = None
        self.pending.clear()
        self._pause(self.main, at)
        state, script = self.states.enter(name)
        self._note(at, LogKind.ENTERED, f"state {name} entered: {run.label}, {said}")
        self.main = Run(Runner(state.body, script.definitions, self.rng), script, f"state {name}")
        self.main.carry = False  # what the face was doing stops where it is

    def _finished(self, run: Run, at: float) -> None:
        run.done = True
        self._note(at, LogKind.ENDED, f"{run.label} ends")
        if run is not self.active:
            return
        self.active = None
        if self.pending:
            handler, _ = self.pending.popleft()
            if self._start(handler, at, cut=False):
                return
        if self.main is not None and not self.main.done and self.active is None:
            self._note(at, LogKind.RESUMED, f"{self.main.label} goes on")  # `_drive` takes it on

    def _play(self, run: Run, step: Play, at: float) -> None:
        playing, started = self.face.timeline, self.face.started
        self.cues.extend(self.face.due(at))
        timeline, length, exits = compile_step(
            run, step, playing, at - started, self.face.rng, self.crossfade, self.recordings
        )
        run.carry = True
        self.face.begin(timeline, at)
        if self.segments is not None:
            self.segments.append((at, timeline))
        run.exiting = exits
        run.playing = (step, at, at + length)

    def _exit(self) -> None:
        self._note(self.clock, LogKind.EXITED, "the face exits")
        self.exited, self.exited_at = True, self.clock
        self.active = None
        self.pending.clear()

    def _note(self, at: float, kind: str, text: str) -> None:
        self.log.append(Logged(at, text, kind))
        self.logged += 1

    def lines_since(self, logged: int) -> List[Logged]:
        """The log's lines after the first `logged` ever logged (those it still keeps)."""
        with self.lock:
            new = min(self.logged - logged, len(self.log))
            return list(itertools.islice(reversed(self.log), new))[::-1]  # the new only: a storm
