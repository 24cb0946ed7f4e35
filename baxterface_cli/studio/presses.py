"""The studio's session: the panel's presses at their times, kept as the script that replays them.

It is not a live session (engine/live_session.py, which runs handlers and events): a press that
reacts goes into the editor's script's run instead (reacting.py). The session *is* a script
(press_text.py writes it): each press placed at its time, one after another with `wait`s between
them while each has finished before the next; presses that overlap go into a `together`, each
after a `wait` for its own start, so a move pressed later takes over its part from where it has
got to (the language's rule) while the rest carries on. The exported file replays the session,
given the seed in its first line.

A press must cost the same at the 10,000th as at the first, so the preview does not compile the
session again at each one: it plays it in parts, each compiled (as that part's script) from the
face, the robot status, the random draws and the words still being said that the part before
left. A press starts a part of its own wherever that loses nothing: where the face has come to
rest, or where every statement pressed before it has begun (what they began goes on in the new
part, as a live face's take-over lets it, engine/take_over.py, which is what the export's
`together` does with a statement under way). So a press of one statement, the panel's usual,
compiles that statement alone. Only a statement not begun yet (the later steps of a press of
several, a `repeat`) keeps the presses after it in its part, for at most `PART_MOST` presses: a
flood past that is cut where it is, what had begun going on, what had not dropped.
"""

from __future__ import annotations

import random
import time
from dataclasses import replace
from typing import List, NamedTuple, Optional, Tuple

from ..core.face_constants import LIMITS
from ..core.face_state import FaceState
from ..engine.compiler import compile_script
from ..engine.effects import RobotStatus
from ..engine.session_program import not_here
from ..engine.take_over import Carry
from ..engine.timeline import CROSSFADE, Said, Timeline
from ..language.diagnostics import Diagnostic, ScriptError
from ..language.parser import parse
from ..language.syntax_tree import Script
from ..speech.recordings import RecordingError, Recordings
from .press_text import Press, TextSize, body

__all__ = ["PART_MOST", "Press", "Presses", "Stale"]


class Stale(Exception):
    """The session changed while a press was being prepared: prepare it again."""


# Presses a part holds at most while a statement in it has not begun: a flood of presses of
# several statements each is cut here, pause or not (what has not begun is dropped).
PART_MOST = 50
HEADER_BYTES, HEADER_PIECES = 200, 4  # the export's two comment lines, generously
SHOWN_PRESSES = 200  # the latest presses a press's answer lists (the export has them all)


class Part(NamedTuple):
    """A run of presses the preview compiles as one script: from `offset` seconds into the
    session, from the face `start`, the robot status `robot` and the random stream `draws` the
    part before left."""

    offset: float
    presses: List[Press]  # times from the session's first press, as exported
    timeline: Timeline  # times from the part's own first press
    start: FaceState
    robot: RobotStatus
    draws: tuple  # random.Random's state where this part's draws begin
    carry: Optional[Carry] = None  # what the part before began and still finishes in this one
    heard: Tuple[Said, ...] = ()  # words the parts before are still saying, on this part's clock
    after: float = 0.0  # when what the parts before pressed has played out, in the session's time
    drawn: Optional[tuple] = None  # random.Random's state where this part's draws end
    crossfade: Optional[float] = None  # what it was compiled with (session.legacy's), None: not yet

    @property
    def end(self) -> float:
        """When everything pressed so far has played out, in the session's time."""
        ends = [p.at + p.duration for p in self.presses]
        return max([self.offset + self.timeline.duration, self.after, *ends])

    def begun(self, t: float) -> bool:
        """Has every statement pressed in this part begun by `t` (the part's time)?"""
        return all(span.start <= t for span in self.timeline.spans)


class Pending(NamedTuple):
    """A press prepared against one version of the session."""

    generation: int
    press: Press
    part: Part
    started: float
    at: float
    size: TextSize  # the session's text with the press
    legacy: bool  # every press so far spelled as the old node's commands, as `Presses.legacy`


class Presses:
    """Presses in, the script that replays them (the session's text) and its timeline out."""

    def __init__(
        self,
        seed: Optional[int] = None,
        filename: str = "session.face",
        recordings: Optional[Recordings] = None,
    ) -> None:
        self.seed = random.randrange(2**31) if seed is None else seed
        self.filename = filename
        self.recordings = recordings or Recordings(None)  # where `say file` reads: nowhere by default
        self.presses: List[Press] = []
        self.started: Optional[float] = None  # the caller's clock at the first press
        self.began_at = ""  # wall-clock time of the first press, for the header
        self.part = self._empty_part()
        self.size = TextSize()  # the session's text: its size, as presses add to it
        # Every press spelled as the old node's commands: while the session's text is only those,
        # one after another, it is a legacy script, which cuts between parts (no crossfade).
        self.legacy = True
        self.generation = 0  # counts the changes, so that a press prepared meanwhile is known stale
        self.compiled_presses = 0  # presses compiled for the preview so far: what a press costs

    def _empty_part(self) -> Part:
        draws = random.Random(self.seed).getstate()
        return Part(
            0.0, [], compile_script(parse("", self.filename), self.seed), FaceState(), RobotStatus(), draws
        )

    @property
    def timeline(self) -> Timeline:
        """The part of the session now playing (its times from `part.offset`)."""
        return self.part.timeline

    @property
    def duration(self) -> float:
        return self.part.end

    def press(self, text: str, now: float) -> float:
        """Add `text` at `now` (the caller's clock); its time in the session. ScriptError if bad.

        Nothing changes unless the whole session still compiles.
        """
        return self.take(self.prepare(text, now))

    def prepare(self, text: str, now: float) -> Pending:
        """The session with `text` pressed at `now`, parsed and compiled, but not yet taken.

        This is the slow part (the part of the session the press falls in compiles, usually
        the press alone), so the studio does it without holding its lock; the session itself
        is only read.
        """
        generation, part, started = self.generation, self.part, self.started
        command = parse(text, "<command>")
        duration = self._compile(command).duration
        at = 0.0 if started is None else round(now - started, 3)
        press = Press(at, text.strip(), duration)
        size = self._check_whole(press)
        legacy = self.legacy and command.legacy
        # Each part is compiled as the whole session's text is, whatever its own text looks like.
        crossfade = 0.0 if legacy and size.plain else CROSSFADE
        if not part.presses:  # the session's first press: its first part
            part = part._replace(offset=at)
        elif part.crossfade == crossfade and (
            at >= part.end or part.begun(at - part.offset) or len(part.presses) >= PART_MOST
        ):
            part = self._next_part(part, at)
        pressed = [*part.presses, press]
        shifted = [p._replace(at=round(p.at - part.offset, 3)) for p in pressed]
        script = self._parse(self.text_of(shifted))
        draws = random.Random()
        draws.setstate(part.draws)
        timeline = self._compile(script, part.start, part.carry, draws, crossfade)
        if part.heard:  # the words the parts before are still saying: heard, and the mouth says them
            ends = [timeline.duration] + [said.end for said in part.heard]
            timeline = replace(timeline, speech=[*part.heard, *timeline.speech], duration=max(ends))
        self.compiled_presses += len(pressed)
        part = part._replace(presses=pressed, timeline=timeline, drawn=draws.getstate(), crossfade=crossfade)
        return Pending(generation, press, part, now if started is None else started, at, size, legacy)

    def _next_part(self, part: Part, at: float) -> Part:
        """A new part from `at`: the face, the robot status, the random draws and the words the part
        before leaves there."""
        t = at - part.offset
        robot = part.timeline.status(t, part.robot)
        # Their times were the old part's; what is over stays over, what goes on goes on.
        shift = part.offset - at
        robot = robot._replace(
            nodding_until=robot.nodding_until + shift, saying_until=robot.saying_until + shift
        )
        heard = tuple(said._replace(at=said.at - t) for said in part.timeline.sounding(t))
        return Part(
            at,
            [],
            part.timeline,
            part.timeline.sample(t),
            robot,
            part.drawn or part.draws,
            carry=Carry(part.timeline, t),
            heard=heard,
            after=part.end,
        )

    def _check_whole(self, press: Press) -> TextSize:
        """The session's text with `press`: ScriptError past a script's limits, which the session as
        a whole keeps to, so that `play` takes the export."""
        size = self.size.add(press)
        text, pieces = size.total
        if press.at + press.duration > LIMITS.max_seconds:
            why = f"run past {LIMITS.max_seconds / 60:.0f} minutes, the longest a script may run"
        elif text + HEADER_BYTES > LIMITS.max_bytes or pieces + HEADER_PIECES > LIMITS.max_pieces:
            why = f"grow past {LIMITS.max_bytes // 1024} KiB, the largest a script may be"
        else:
            return size
        message = f"the session would break: it would {why}; export it and clear it to go on"
        raise ScriptError([Diagnostic(0, 0, message)], "<command>")

    def take(self, pending: Pending) -> float:
        """Make a prepared press the session's; Stale if the session changed since it was prepared."""
        if pending.generation != self.generation:
            raise Stale()
        if self.started is None:
            self.began_at = time.strftime("%Y-%m-%d %H:%M:%S")
        self.presses.append(pending.press)
        self.size, self.legacy = pending.size, pending.legacy
        self.part, self.started = pending.part, pending.started
        self.generation += 1
        return pending.at

    def _compile(
        self,
        script: Script,
        start: Optional[FaceState] = None,
        carry: Optional[Carry] = None,
        draws: Optional[random.Random] = None,
        crossfade: Optional[float] = None,
    ) -> Timeline:
        # A press plays in the session, which is compiled: a script that reacts runs in the editor.
        refused = not_here(script, "a press in the studio's panel (the editor's script does)")
        if refused is not None:
            raise refused
        try:
            return compile_script(
                script,
                self.seed,
                start=start,
                recordings=self.recordings,
                carry=carry,
                rng=draws,
                crossfade=crossfade,
            )
        except RecordingError as e:  # a press that says a recording it cannot
            raise ScriptError([e.diagnostic()._replace(line=0, column=0)], "<command>") from None

    def _parse(self, text: str) -> Script:
        try:
            return parse(text, self.filename)
        except ScriptError as e:  # the press alone was fine: the session as a whole is not
            raise ScriptError(
                [
                    d._replace(line=0, column=0, message=f"the session would break: {d.message}")
                    for d in e.errors
                ],
                "<command>",
            ) from None

    def clear(self) -> None:
        self.generation += 1
        self.presses, self.started, self.began_at = [], None, ""
        self.part, self.size, self.legacy = self._empty_part(), TextSize(), True

    def position(self, now: float) -> float:
        """Seconds into the session at `now`."""
        return 0.0 if self.started is None else now - self.started

    @property
    def text(self) -> str:
        return self.text_of(self.presses)

    def text_of(self, presses: List[Press], filename: Optional[str] = None) -> str:
        """The runnable script of `presses`, with a header saying how to replay it as `filename`."""
        header = [
            f"# baxterface studio session{', ' + self.began_at if self.began_at else ''}: "
            f"{len(presses)} press" + ("" if len(presses) == 1 else "es"),
            f"# replays exactly with: baxterface play {filename or self.filename} --seed {self.seed}",
        ]
        return "\n".join(header + body(presses)) + "\n"

    def as_json(self, whole: bool = False) -> dict:
        """The latest `SHOWN_PRESSES` presses and their count; `whole`: every press, and the text.
        A press is answered with the latest only, so that it costs the same however long the
        session has grown."""
        shown = self.presses if whole else self.presses[-SHOWN_PRESSES:]
        answer = {
            "presses": [{"at": p.at, "command": p.command} for p in shown],
            "count": len(self.presses),
            "seed": self.seed,
        }
        if whole:
            answer["text"] = self.text
        return answer

    def __len__(self) -> int:
        return len(self.presses)
