"""A live session: commands pressed at times, kept as the script that replays them.

The session *is* a script. Each press is placed at its time: one after
another with `wait`s between them while each has finished before the next;
presses that overlap go into a `together`, each after a `wait` for its own
start, so a move pressed later takes over its part from where it has got to
(the language's rule) while the rest carries on. The studio's preview plays
this very text, so the exported file replays the session exactly, given the
seed in its first line.
"""

from __future__ import annotations

import random
import time
from typing import List, NamedTuple, Optional

from ..engine.compiler import compile_script
from ..engine.timeline import Timeline
from ..language.diagnostics import ScriptError
from ..language.parser import parse
from ..language.syntax_tree import Script
from ..speech.recordings import RecordingError, Recordings


class Stale(Exception):
    """The session changed while a press was being prepared: prepare it again."""


class Press(NamedTuple):
    at: float  # seconds from the session's first press, to the millisecond
    command: str
    duration: float  # how long the command runs on its own


class Pending(NamedTuple):
    """A press prepared against one version of the session."""

    generation: int
    presses: List[Press]
    timeline: Timeline
    started: float
    at: float


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
        self.timeline = compile_script(parse("", filename), self.seed)
        self.generation = 0  # counts the changes, so that a press prepared meanwhile is known stale

    def press(self, text: str, now: float) -> float:
        """Add `text` at `now` (the caller's clock); its time in the session. ScriptError if bad.

        Nothing changes unless the whole session still compiles.
        """
        return self.take(self.prepare(text, now))

    def prepare(self, text: str, now: float) -> Pending:
        """The session with `text` pressed at `now`, parsed and compiled, but not yet taken.

        This is the slow part (the whole session compiles again), so the studio
        does it without holding its lock; the session itself is only read.
        """
        generation, presses, started = self.generation, self.presses, self.started
        command = parse(text, "<command>")
        duration = self._compile(command).duration
        at = 0.0 if started is None else round(now - started, 3)
        pressed = [*presses, Press(at, text.strip(), duration)]
        timeline = self._compile(self._parse(self.text_of(pressed)))
        return Pending(generation, pressed, timeline, now if started is None else started, at)

    def take(self, pending: Pending) -> float:
        """Make a prepared press the session's; Stale if the session changed since it was prepared."""
        if pending.generation != self.generation:
            raise Stale()
        if self.started is None:
            self.began_at = time.strftime("%Y-%m-%d %H:%M:%S")
        self.presses, self.timeline, self.started = pending.presses, pending.timeline, pending.started
        self.generation += 1
        return pending.at

    def _compile(self, script: Script) -> Timeline:
        try:
            return compile_script(script, self.seed, recordings=self.recordings)
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
        self.timeline = compile_script(parse("", self.filename), self.seed)

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

    def as_json(self) -> dict:
        return {
            "presses": [{"at": p.at, "command": p.command} for p in self.presses],
            "text": self.text,
            "seed": self.seed,
        }

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
