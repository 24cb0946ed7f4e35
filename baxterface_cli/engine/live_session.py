"""One live session: a script and its handlers on one face, events in, face states and robot cues out.

The clock is the caller's: `run` takes a script, `post` an event, `tick(now)` gives the face and the
cues due (a frame loop reads `face.state(now)`, lets time pass by `catch_up`, leaves `advance` to a
worker: session_intake.py). Every public method may be called from any thread (one lock). `render`
and `explain` run it over an events file (session_run.py); `play` steps it in real time.

The face does one thing at a time: the main script (or the state it entered), or one handler's
run, which pauses the main script until no handler is left; an event whose handler cannot start
follows its policy (docs/language.md). Each step is compiled from the face as it is
(session_steps.py). Whatever a script says, the session keeps time: a `forever`'s round lasts
`LIMITS.least_round` at least; handlers are bounded (session_handlers.py); what happens at one
instant is bounded and taken in one loop (`_drive`), never a call deeper; a live face (`keep_up`)
that falls behind its clock stops the run doing it; a recorded run counts every step.
"""

from __future__ import annotations

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
from .session_answers import Answering
from .session_handlers import EveryClock, by_kind, install, key_of, why_dropped
from .session_program import Await, Goto, Lap, Listen, Play, Runner
from .session_records import AtOnce, Handler, Logged, LogKind, Run, SessionLog
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
        """`record`: keep each timeline begun (`segments`), for a render; `keep_up`: a real clock's."""
        self.lock = threading.RLock()
        self.face = LiveFace(start or FaceState(), idle=idle, seed=seed, now=now, recordings=recordings)
        self.rng = random.Random(f"one of:{seed}")
        self.recordings, self.crossfade = recordings, crossfade
        self.clock = now
        self.handlers: List[Handler] = []  # swapped whole when it changes: read without the lock
        self._kinds: Dict[str, List[Handler]] = {}  # the handlers of each kind of event
        self.main: Optional[Run] = None
        self.active: Optional[Run] = None
        self.pending: Deque[Tuple[Handler, n.Event]] = deque()
        self.log = SessionLog(log_lines)
        self.segments: Optional[List[Tuple[float, Timeline]]] = [] if record else None
        self.cues: List[Cue] = []  # handed out by the next tick
        self.exited, self.exited_at = False, None  # and when: a recorded run ends there
        self.ignored = 0  # events after the face exited
        self.last_event = now
        self._idle_fired: set = set()
        self._every = EveryClock()
        self.states = States()  # the states installed, the one the face is in
        self._starts = AtOnce()  # handler runs started at one instant
        self.steps = 0  # steps taken: a recorded run takes LIMITS.max_run_steps at most
        self.keep_up = keep_up
        self._behind = 0  # due steps taken in a row while LIMITS.max_lag behind the clock
        self._driving = False  # `_drive` is under way, further up this call
        if script is not None:
            self.run(script, now)

    # -- in

    def run(self, script: n.Script, now: float) -> None:
        """Install `script`'s handlers and states; raise its signals, when that is all it says;
        or else make its statements the main script, stopping whatever runs."""
        with self.lock:
            self._run(script, now)

    def _run(self, script: n.Script, now: float) -> None:
        self.advance(now)
        at = self.clock
        handlers, replaced = install(self.handlers, script)  # ScriptError past the bounds: nothing done
        for event in {key_of(h): h.on.event for h in replaced}.values():
            self.log.note(at, LogKind.REPLACED, f"{in_words(event)}: its handler replaced")
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
        main = Run(Runner(script.body, script.definitions, self.rng), script, "main script")
        self._take_over(main, at, "a new script")
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

    def catch_up(self, now: float) -> List[Cue]:
        """`tick`'s time passing and cues due, for a frame loop that never waits: no compile, no wait for
        the lock (while a worker is busy, or a step it must take is due, time and the cues wait)."""
        cues: List[Cue] = []
        if self.lock.acquire(blocking=False):
            try:
                due = self.next_due()
                if due is None or due[0] > now:  # nothing to compile: time may pass here
                    self.clock = max(self.clock, now)
                    cues, self.cues = self.cues + self.face.due(now), []
            finally:
                self.lock.release()
        return cues

    @property
    def free(self) -> bool:
        """No handler running or waiting, the main script done? (Read without the lock too.)"""
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
        """A live face that cannot keep time: the run due long ago stops, missed ticks are let go."""
        self._behind = 0
        run = self._owner()
        if run is not None and not run.done:
            why = f"{now - self.clock:.1f} s behind the clock, its steps too short to keep time"
            self.log.note(self.clock, LogKind.STOPPED, f"{run.label} stopped: {why}")
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
            found.append((tick[0], 2, lambda: self._fire("every", tick[1])))
        idle = {h.on.event.seconds for h in self._kinds.get("idle", ()) if self.states.live(h.state)}
        for seconds in idle - self._idle_fired:  # each once, until an event comes
            found.append((self.last_event + seconds, 3, lambda s=seconds: self._fire("idle", s)))
        if not found:
            return None
        at, _, action = min(found, key=lambda f: (f[0], f[1]))
        return at, action

    def _fire(self, kind: str, seconds: float) -> None:  # a timer: `every` ticks on, `idle` once
        if kind == "every":
            self._every.tick()
        else:
            self._idle_fired.add(seconds)
        self._dispatch(n.Event(kind, seconds=seconds), self.clock, "")

    # -- events

    def _dispatch(self, event: n.Event, at: float, source: str) -> None:
        if self.exited:
            self.ignored += 1
            return
        if event.kind not in TIMERS:  # a timer's tick is told only by what it starts
            self.log.note(at, LogKind.EVENT, f"event {in_words(event)}" + (f" ({source})" if source else ""))
            self.last_event = at
            self._idle_fired.clear()
        for run in (self.main, self.active):
            if run is not None and run.waiting is not None and self._hears(run, event, at):
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
            self.log.note(at, LogKind.DROPPED, f"dropped {in_words(event)}{why}")
        elif self.active is None:
            self._start(handler, at, cut=handler.on.policy == "interrupt")
        elif handler.on.policy == "queue":
            handler.queued += 1
            self.pending.append((handler, event))
            self.log.note(at, LogKind.QUEUED, f"queued {in_words(event)} for {handler.label}")
        else:
            self.log.note(at, LogKind.INTERRUPTED, f"{self.active.label} interrupted")
            self._pause(self.active, at)  # it may be between steps: raising this very signal
            self.active = None
            self._start(handler, at, cut=True)

    def _start(self, handler: Handler, at: float, cut: bool) -> bool:
        """Start a run of `handler` (`_drive` takes its steps); False if handlers have started one
        another too often at `at`, a loop that takes no time."""
        if self._starts.add(at) > MAX_STARTS_AT_ONCE:
            handler.dropped += 1
            self.pending.clear()
            if self._starts.count == MAX_STARTS_AT_ONCE + 1:
                why = f"{MAX_STARTS_AT_ONCE} handler runs began without time passing"
                why += " (handlers that raise each other's signals?)"
                self.log.note(at, LogKind.STOPPED, f"{handler.label} not run: {why}")
            return False
        handler.runs += 1
        handler.last_start = at
        self._pause(self.main, at)
        run = Run(
            Runner(handler.on.body, handler.script.definitions, self.rng),
            handler.script,
            handler.label,
            handler,
        )
        run.carry = not cut
        self.active = run
        self.log.note(at, LogKind.STARTED, f"{handler.label} runs")
        return True

    # -- runs

    def _owner(self) -> Optional[Run]:
        return self.active if self.active is not None else self.main

    @staticmethod
    def _ready(run: Run) -> bool:
        return not run.done and run.playing is None and run.waiting is None

    def _pause(self, run: Optional[Run], at: float) -> None:
        """Stop what `run` plays at `at`: it starts over (a wait waits out the rest) when it goes on."""
        if run is not None and run.playing is not None:
            play, start, _ = run.playing
            run.runner.cut(play, at - start)
            run.playing = None

    def _woken(self, run: Run, at: float, go: bool = True) -> None:
        run.waiting = None
        if go:
            self._drive(at)

    def _hears(self, run: Run, event: n.Event, at: float) -> bool:
        """Does `run`'s wait take `event`? An `ask` goes on with the answer it chose."""
        wait = run.waiting[0]  # type: ignore[index]
        if not isinstance(wait, Answering):
            return matches(wait.event, event)
        said = wait.take(run.runner, event)
        if said is not None:
            self.log.note(at, LogKind.ANSWERED, f"{run.label}: {said}")
        return said is not None

    def _timed_out(self, run: Run) -> None:
        wait, _ = run.waiting  # type: ignore[misc]
        if isinstance(wait, Answering):
            kind, said = LogKind.ANSWERED, wait.take(run.runner)
        else:
            kind, said = LogKind.TIMED_OUT, f"'wait until {in_words(wait.event)}' timed out"
        self.log.note(self.clock, kind, f"{run.label}: {said}")
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
                    self.log.note(at, LogKind.STOPPED, f"{run.label} stopped: {why}")
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
        elif isinstance(step, Listen):
            run.waiting = (Answering(step.statement), at)  # type: ignore[assignment]
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
            self.log.note(at, LogKind.STOPPED, f"{run.label}: {said} {why}")
            if why.startswith("stopped"):
                self._finished(run, at)
            return
        state, script = self.states.enter(name)
        entered = Run(Runner(state.body, script.definitions, self.rng), script, f"state {name}")
        entered.carry = False  # what the face was doing stops where it is
        self._take_over(entered, at, f"going to {name}", by=run)
        self.log.note(at, LogKind.ENTERED, f"state {name} entered: {run.label}, {said}")

    def _take_over(self, main: Run, at: float, why: str, by: Optional[Run] = None) -> None:
        """`main` is what the face does now: the handler running (but `by`, which said so) and the
        main script stop where they are, and the events queued are let go."""
        if self.active is not None and self.active is not by:
            self.log.note(at, LogKind.TAKEN_OVER, f"{self.active.label} stopped by {why}")
        self._pause(self.active, at)
        self._pause(self.main, at)
        self.active, self.main = None, main
        self.pending.clear()

    def _finished(self, run: Run, at: float) -> None:
        run.done = True
        self.log.note(at, LogKind.ENDED, f"{run.label} ends")
        if run is not self.active:
            return
        self.active = None
        if self.pending:
            handler, _ = self.pending.popleft()
            if self._start(handler, at, cut=False):
                return
        if self.main is not None and not self.main.done and self.active is None:
            self.log.note(at, LogKind.RESUMED, f"{self.main.label} goes on")  # `_drive` takes it on

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
        self.log.note(self.clock, LogKind.EXITED, "the face exits")
        self.exited, self.exited_at = True, self.clock
        self.active = None
        self.pending.clear()

    @property
    def logged(self) -> int:
        return self.log.logged  # lines ever logged: the log keeps the last `log_lines`

    def lines_since(self, logged: int) -> List[Logged]:
        with self.lock:
            return self.log.since(logged)
