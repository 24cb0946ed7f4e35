"""A live session: commands pressed at times, kept as the script that replays them.

The session *is* a script. Each press is placed at its time: one after
another with `wait`s between them while each has finished before the next;
presses that overlap go into a `together`, each after a `wait` for its own
start, so a move pressed later takes over its part from where it has got to
(the language's rule) while the rest carries on. The exported file replays
the session, given the seed in its first line.

A press must cost the same at the 10,000th as at the first, so the preview
does not compile the whole session again at each one: it plays the session in
parts of at most `PART_PRESSES` presses, each compiled (as that part's
script) from the face and robot status the part before left. A part ends
where the face has come to rest, nothing under way, so the next starts from
exactly that face; only a flood of overlapping presses, `PART_MOST` of them
without a pause, is cut where it is, and what the part before began finishes
in the next (a live face's take-over, engine/take_over.py), as it does when
the export replays the session.
"""

from __future__ import annotations

import random
import time
from typing import List, NamedTuple, Optional, Tuple

from ..core.face_constants import LIMITS
from ..core.face_state import FaceState
from ..engine.compiler import compile_script
from ..engine.effects import RobotStatus
from ..engine.session_program import not_here
from ..engine.take_over import Carry
from ..engine.timeline import Timeline
from ..language.diagnostics import Diagnostic, ScriptError
from ..language.parser import parse
from ..language.source import PIECE
from ..language.syntax_tree import Script
from ..speech.recordings import RecordingError, Recordings


class Stale(Exception):
    """The session changed while a press was being prepared: prepare it again."""


class Press(NamedTuple):
    at: float  # seconds from the session's first press, to the millisecond
    command: str
    duration: float  # how long the command runs on its own


PART_PRESSES = 20  # presses a part of the session holds before the next pause starts another
# A flood of overlapping presses starts another part here, pause or not, the moves begun going on
# (as a live face's take-over): a press compiles at most this many, at the 10,000th as at the 50th.
PART_MOST = 50
HEADER_BYTES = 200  # the export's two comment lines, generously
PART_BYTES = 16  # the `wait` that starts a part in the export
SHOWN_PRESSES = 200  # the latest presses a press's answer lists (the export has them all)


class Part(NamedTuple):
    """A run of presses the preview compiles as one script: from `offset` seconds into the session,
    from the face `start` and the robot status `robot` the part before left."""

    offset: float
    presses: List[Press]  # times from the session's first press, as exported
    timeline: Timeline  # times from the part's own first press
    start: FaceState
    robot: RobotStatus
    size: Tuple[int, int] = (0, 0)  # its text: bytes, and pieces as `_check_whole` counts them
    carry: Optional[Carry] = None  # what the part before began and still finishes in this one

    @property
    def end(self) -> float:
        """When everything pressed in this part has played out, in the session's time."""
        ends = [p.at + p.duration for p in self.presses]
        return max([self.offset + self.timeline.duration, *ends])


class Pending(NamedTuple):
    """A press prepared against one version of the session."""

    generation: int
    press: Press
    part: Part
    started: float
    at: float
    closed_size: Tuple[int, int]  # the parts before it, as `Session.closed_size`


def seconds(t: float) -> str:
    """A time as a script writes it: `1.25s`, to the millisecond."""
    return f"{t:.3f}".rstrip("0").rstrip(".") + "s"


class Session:
    """Presses in, the session's script text and timeline out."""

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
        self.closed_size = (0, 0)  # the parts before the one playing: bytes and pieces of their text
        self.generation = 0  # counts the changes, so that a press prepared meanwhile is known stale
        self.compiled_presses = 0  # presses compiled for the preview so far: what a press costs

    def _empty_part(self) -> Part:
        return Part(0.0, [], compile_script(parse("", self.filename), self.seed), FaceState(), RobotStatus())

    @property
    def timeline(self) -> Timeline:
        """The part of the session now playing (its times from `part.offset`)."""
        return self.part.timeline

    @property
    def duration(self) -> float:
        return self.part.offset + self.part.timeline.duration

    def press(self, text: str, now: float) -> float:
        """Add `text` at `now` (the caller's clock); its time in the session. ScriptError if bad.

        Nothing changes unless the whole session still compiles.
        """
        return self.take(self.prepare(text, now))

    def prepare(self, text: str, now: float) -> Pending:
        """The session with `text` pressed at `now`, parsed and compiled, but not yet taken.

        This is the slow part (the part of the session now playing compiles
        again, at most `PART_MOST` presses), so the studio does it without
        holding its lock; the session itself is only read.
        """
        generation, part, started = self.generation, self.part, self.started
        command = parse(text, "<command>")
        duration = self._compile(command).duration
        at = 0.0 if started is None else round(now - started, 3)
        press = Press(at, text.strip(), duration)
        pressed = [*part.presses, press]
        if not part.presses:  # the session's first press: its first part
            part = part._replace(offset=at)
        elif len(part.presses) >= PART_MOST or (len(part.presses) >= PART_PRESSES and at >= part.end):
            part, pressed = self._next_part(part, at), [press]
        closed = self.closed_size
        if part is not self.part and self.part.presses:  # the part before is closed now
            closed = (closed[0] + self.part.size[0] + PART_BYTES, closed[1] + self.part.size[1] + 2)
        shifted = [p._replace(at=round(p.at - part.offset, 3)) for p in pressed]
        text = "\n".join(_body(shifted))
        size = self._check_whole(closed, text, at + duration)
        script = self._parse(self.text_of(shifted))
        timeline = self._compile(script, part.start, part.carry)
        self.compiled_presses += len(pressed)
        part = part._replace(presses=pressed, timeline=timeline, size=size)
        return Pending(generation, press, part, now if started is None else started, at, closed)

    def _next_part(self, part: Part, at: float) -> Part:
        """A new part from `at`: the face and the robot status the part before leaves there."""
        t = at - part.offset
        robot = part.timeline.status(t, part.robot)
        # Their times were the old part's; what is over stays over, what goes on goes on.
        shift = part.offset - at
        robot = robot._replace(
            nodding_until=robot.nodding_until + shift, saying_until=robot.saying_until + shift
        )
        return Part(at, [], part.timeline, part.timeline.sample(t), robot, carry=Carry(part.timeline, t))

    def _check_whole(self, closed: Tuple[int, int], text: str, seconds: float) -> Tuple[int, int]:
        """ScriptError past a script's limits, which the session as a whole keeps to, so that `play`
        takes the export: the parts before (`closed`: bytes and pieces) and this one's `text`, whose
        bytes and pieces it returns."""
        own = (len(text.encode("utf-8")), sum(1 for _ in PIECE.finditer(text)))
        size, pieces = own[0] + closed[0] + HEADER_BYTES, own[1] + closed[1]
        if seconds > LIMITS.max_seconds:
            why = f"run past {LIMITS.max_seconds / 60:.0f} minutes, the longest a script may run"
        elif size > LIMITS.max_bytes or pieces > LIMITS.max_pieces:
            why = f"grow past {LIMITS.max_bytes // 1024} KiB, the largest a script may be"
        else:
            return own
        message = f"the session would break: it would {why}; export it and clear it to go on"
        raise ScriptError([Diagnostic(0, 0, message)], "<command>")

    def take(self, pending: Pending) -> float:
        """Make a prepared press the session's; Stale if the session changed since it was prepared."""
        if pending.generation != self.generation:
            raise Stale()
        if self.started is None:
            self.began_at = time.strftime("%Y-%m-%d %H:%M:%S")
        self.presses.append(pending.press)
        self.closed_size = pending.closed_size
        self.part, self.started = pending.part, pending.started
        self.generation += 1
        return pending.at

    def _compile(
        self, script: Script, start: Optional[FaceState] = None, carry: Optional[Carry] = None
    ) -> Timeline:
        # A press plays in the session, which is compiled: a script that reacts runs in the editor.
        refused = not_here(script, "a press in the studio's panel (the editor's script does)")
        if refused is not None:
            raise refused
        try:
            return compile_script(script, self.seed, start=start, recordings=self.recordings, carry=carry)
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
        self.part, self.closed_size = self._empty_part(), (0, 0)

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
        return "\n".join(header + _body(presses)) + "\n"

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


def _body(presses: List[Press]) -> List[str]:
    lines: List[str] = []
    clock = 0.0  # where the text has got to, as it will play: waits are rounded to the millisecond
    for group in _overlapping(presses):
        start = group[0].at
        if start - clock >= 0.0005:
            lines.append(f"wait {seconds(start - clock)}")
            clock += float(seconds(start - clock)[:-1])
        if len(group) == 1:
            lines.extend(group[0].command.splitlines())
        else:
            lines.append("together {")
            lines.extend("  " + line for line in group[0].command.splitlines())
            for p in group[1:]:
                lines.append("  repeat 1 {")
                lines.append(f"    wait {seconds(p.at - start)}")
                lines.extend("    " + line for line in p.command.splitlines())
                lines.append("  }")
            lines.append("}")
        clock += max(p.at - start + p.duration for p in group)
    return lines


def _overlapping(presses: List[Press]) -> List[List[Press]]:
    """Presses in runs where each starts before the ones before it in its run have all finished."""
    groups: List[List[Press]] = []
    end = float("-inf")
    for p in presses:
        if groups and p.at < end:
            groups[-1].append(p)
            end = max(end, p.at + p.duration)
        else:
            groups.append([p])
            end = p.at + p.duration
    return groups
