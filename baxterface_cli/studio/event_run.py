"""The studio's one live session: the editor's script run over what came to it so far, the
events fired at it and the commands pressed in the panel, kept so that the next one continues it.

`render --events` runs a script over an events file in one go, and `render LOG.jsonl` over a
session's log, commands and all (engine/session_run.py, engine/log_replay.py). The studio gets its
inputs one at a time, at the preview's position: an event is posted to the session there; a
command (`Command`) takes over there, a new main script from the face as it is, as a command on
the face node does. Running the script again over all of them at each one made the 200th cost 25
times the first; here the run is kept at its last input (a checkpoint: the live session just
after it, never advanced further) and a copy of it (engine/session_fork.py) takes the next one and
runs on to the end; the timelines it played before are kept, joined in chapters (chained.py). So
an input at the end costs the same at the 10,000th as at the first, and the run is the one
`render` makes of the same inputs, to the bit: the same calls, in the same order, on an exact copy.

An input earlier than the last (the preview sought back) continues from the nearest kept
checkpoint before it, one every `EVERY` inputs, running on over the inputs after it.

An edit of the script (`edited`) whose change no event has yet reached, only handlers changed,
added or dropped, continues likewise from the nearest checkpoint before the first event one of them
takes, the checkpoints given the new script's handlers (engine/session_fork.py's `rebase`): the
run before it is the same, call for call. Any other edit runs the script again from the start.
"""

from __future__ import annotations

import bisect
from typing import TYPE_CHECKING, Dict, List, NamedTuple, Optional, Tuple, Union

from ..engine.live_session import LiveSession
from ..engine.session_fork import exactly, fork, rebase
from ..engine.session_records import Logged
from ..engine.session_run import NeverRests, run_end, settle
from ..engine.stitched import Segments
from ..language import syntax_tree as n
from ..language.checker import walk
from ..language.event_trace import Posted
from ..language.events import TIMERS, matches
from .chained import Chained, Chapters, chained

if TYPE_CHECKING:
    from ..speech.recordings import Recordings

WINDOW = 30.0  # seconds a run that never rests is shown past its last event
EVERY = 16  # inputs between the checkpoints kept for one that comes back among the others


class Command(NamedTuple):
    """A command pressed in the panel: a new main script at `at` on the run, taking over from the face
    as it is there (its handlers' and states' statements stay with the editor's script)."""

    at: float
    script: n.Script


Input = Union[Posted, Command]


class Checkpoint(NamedTuple):
    posted: int  # the run's first `posted` inputs are in it
    session: LiveSession  # just after them: only copies of it go on
    segments: int  # the timelines it had played by then
    lines: int  # the log lines it had written by then
    script: n.Script  # whose handlers the session holds: a run of an edit of it goes on with its own


class EventRun:
    """The run of `script` over `inputs` (see the module's docstring); each `with_input` makes a
    new one and leaves this one as it was, so a failure changes nothing."""

    def __init__(
        self,
        script: n.Script,
        seed: Optional[int],
        recordings: Optional[Recordings],
        inputs: Tuple[Input, ...],
        played: Segments,
        checkpoints: Tuple[Checkpoint, ...],
        chapters: Chapters,
        lines: List[Logged],
        shown: bool = True,
        handed: int = 0,
    ) -> None:
        """`shown`: the run on to its end made now, for the preview (not for a run about to go on);
        `handed`: the inputs handed to the session to make it from its checkpoint (what it cost).
        `played` and `lines` may be shared with the run this one goes on from (`_continued`): a
        run reads only as many of them as it had when it was made."""
        self.script, self.seed, self.recordings = script, seed, recordings
        self.inputs = inputs
        self.played = played  # the timelines played up to the last input, with their starts
        self.lines = lines  # the session's log up to the last input (a copy's log starts empty)
        self._had = (len(played), len(lines))
        self._tail_log: Tuple[Logged, ...] = ()
        self.checkpoints = checkpoints
        self.chapters = chapters
        self.handed = handed
        if shown:
            self.timeline, self.counts = self._shown()

    @classmethod
    def start(
        cls,
        script: n.Script,
        seed: Optional[int],
        recordings: Optional[Recordings] = None,
        inputs: Tuple[Input, ...] = (),
    ) -> EventRun:
        """`script` run over `inputs` from the start (ScriptError or MissingTool if it cannot play)."""
        # As run_over makes it: the same session, given the same calls.
        # Its log whole: the studio's timeline shows the handlers' runs, states and events from it.
        session = LiveSession(
            script, seed=seed, idle=False, recordings=recordings, record=True, log_lines=None
        )
        played, session.segments = list(session.segments or ()), []
        lines = list(session.log)
        first = (Checkpoint(0, session, len(played), len(lines), script),)
        run = cls(script, seed, recordings, (), played, first, Chapters(), lines, shown=not inputs)
        return run._continued(run.checkpoints[0], list(inputs)) if inputs else run

    def with_input(self, item: Input) -> EventRun:
        """This run with `item` among its inputs, after any at the same time."""
        if not self.inputs or item.at >= self.inputs[-1].at:  # at the end, as most come: no search
            i = len(self.inputs)
        else:
            i = bisect.bisect_right([e.at for e in self.inputs], item.at)
        inputs = [*self.inputs[:i], item, *self.inputs[i:]]
        since = next(c for c in reversed(self.checkpoints) if c.posted <= i)
        return self._continued(since, inputs)

    def edited(self, script: n.Script) -> EventRun:
        """`script` (the script edited) run over these inputs: from the start, or on from the last
        checkpoint the edit does not reach (see the module's docstring)."""
        reached = unreached(self.script, script, self.inputs)
        kept = tuple(c for c in self.checkpoints if c.posted <= reached)
        if reached == 0 or len(kept) < 2:
            return EventRun.start(script, self.seed, self.recordings, self.inputs)
        # The checkpoints kept go on with the edit's handlers when one is used (`_continued`): what
        # the edits since a checkpoint's script changed, no event before it reached.
        played, lines = list(self.played[: self._had[0]]), list(self.lines[: self._had[1]])
        run = EventRun(
            script, self.seed, self.recordings, self.inputs, played, kept, self.chapters, lines, shown=False
        )
        return run._continued(kept[-1], list(self.inputs))

    def _continued(self, since: Checkpoint, inputs: List[Input]) -> EventRun:
        """The run from the checkpoint `since` on over the rest of `inputs` (the first
        `since.posted` of them are in it already)."""
        if since.script is not self.script:  # kept through an edit: with the edit's handlers now
            since = since._replace(session=rebase(since.session, self.script), script=self.script)
        session = fork(since.session)
        # Gone on from its end (the usual: an input at the end), this run's lists are the new one's,
        # grown in place, so that an input does not copy the whole run's; a failure takes back what
        # it added. From further back, the new run's own copies.
        shared = (since.segments, since.lines) == self._had == (len(self.played), len(self.lines))
        played = self.played if shared else list(self.played[: since.segments])
        lines = self.lines if shared else list(self.lines[: since.lines])
        checkpoints = [c for c in self.checkpoints if c.posted < since.posted] + [since]
        try:
            for k in range(since.posted, len(inputs)):
                item = inputs[k]
                if isinstance(item, Command):  # as `render LOG.jsonl` takes a command that takes over
                    session.run(item.script, item.at)
                else:
                    session.post(item.event, item.at, f"events:{k + 1}")
                played += session.segments  # type: ignore[operator]
                session.segments = []
                lines += session.log
                session.log.clear()
                session.cues.clear()  # for a robot to take: no one does, and each copy copied them
                if (k + 1) % EVERY == 0 or k + 1 == len(inputs):
                    checkpoints.append(Checkpoint(k + 1, session, len(played), len(lines), self.script))
                    if k + 1 < len(inputs):
                        session = fork(session)
        except BaseException:
            del played[since.segments :], lines[since.lines :]
            raise
        # One every EVERY inputs, and the last: the run goes on from there.
        checkpoints = [c for c in checkpoints[:-1] if c.posted % EVERY == 0] + checkpoints[-1:]
        chapters = self.chapters.upto(since.segments).grown(played)
        try:
            return EventRun(
                self.script, self.seed, self.recordings, tuple(inputs), played, tuple(checkpoints),
                chapters, lines, handed=len(inputs) - since.posted,
            )  # fmt: skip
        except BaseException:
            del played[since.segments :], lines[since.lines :]
            raise

    def _shown(self) -> Tuple[Chained, Dict[str, int]]:
        """The whole run, on from the last input to its end, as `run_log` ends it; and what its
        handlers did in all. Its whole log is kept as `log`."""
        last = self.checkpoints[-1]
        end_at = self.inputs[-1].at if self.inputs else 0.0
        tail = fork(last.session)
        duration: Optional[float] = None
        try:
            end = settle(tail, self.script, end_at, bool(self.inputs), None)
        except NeverRests:
            tail, duration = fork(last.session), end_at + WINDOW
            end = settle(tail, self.script, end_at, bool(self.inputs), duration)
        # What the finished chapters do not hold: the rest of what was played, and the tail.
        rest = [*self.played[self.chapters.covered : self._had[0]], *(tail.segments or ())]
        if not rest and not self.chapters.covered:  # nothing played: the face it started with
            rest = [(0.0, tail.face.timeline)]
        end = run_end(tail, rest, end, duration)
        self._tail_log = tuple(tail.log)
        counts = tail.counts().values()
        totals = {key: sum(c[key] for c in counts) for key in ("runs", "dropped", "queued")}
        return chained(self.chapters, rest, end), totals

    @property
    def log(self) -> Tuple[Logged, ...]:
        """The session's whole log, on to the run's end (made when asked: an input never asks)."""
        return (*self.lines[: self._had[1]], *self._tail_log)


def unreached(old: n.Script, new: n.Script, inputs: Tuple[Input, ...]) -> int:
    """How many of `inputs` come before the edit from `old` to `new` can change the run: all of
    them when none can; 0 when it may change it from the start (anything but handlers changed,
    a timer's handler, or a signal's that a statement raises, the scripts' or a command's, whose
    time no input says)."""
    rest = [[s for s in script.body if not isinstance(s, n.On)] for script in (old, new)]
    if not exactly(*rest) or old.legacy != new.legacy:
        return 0
    ons = [[s for s in script.body if isinstance(s, n.On)] for script in (old, new)]
    kept = [
        [on for on in mine if any(exactly(on, other) for other in theirs)]
        for mine, theirs in (ons, ons[::-1])
    ]
    if not exactly(*kept):  # the handlers kept in another order: which one takes an event first changes
        return 0
    changed = [on.event for mine, same in zip(ons, kept) for on in mine if not any(on is k for k in same)]
    commands = [i.script for i in inputs if isinstance(i, Command)]
    said = (s for script in (old, new, *commands) for s in walk(script.body))
    raised = {s.name for s in said if isinstance(s, n.Signal)}
    for event in changed:
        if event.kind in TIMERS or any(matches(event, n.Event("signal", name)) for name in raised):
            return 0
    posted = ((k, i) for k, i in enumerate(inputs) if isinstance(i, Posted))
    return next((k for k, e in posted if any(matches(c, e.event) for c in changed)), len(inputs))
