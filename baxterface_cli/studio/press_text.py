"""The session as the script that replays it, and that script's size, kept as presses come.

Presses that do not overlap are written one after another with `wait`s between them; presses
that overlap go into a `together`, each after a `wait` for its own start (presses.py says why).
The size is what a press checks against a script's limits: it must not be found by writing the
whole text again at each press, which cost more the longer the session had grown, so
`TextSize.add` counts only what one press adds to it.
"""

from __future__ import annotations

from typing import List, NamedTuple, Optional, Tuple

from ..language.source import PIECE


class Press(NamedTuple):
    at: float  # seconds from the session's first press, to the millisecond
    command: str
    duration: float  # how long the command runs on its own


def seconds(t: float) -> str:
    """A time as a script writes it: `1.25s`, to the millisecond."""
    return f"{t:.3f}".rstrip("0").rstrip(".") + "s"


def body(presses: List[Press]) -> List[str]:
    """The lines that play `presses` (their times from the text's start)."""
    lines: List[str] = []
    clock = 0.0  # where the text has got to, as it will play: waits are rounded to the millisecond
    for group in overlapping(presses):
        start = group[0].at
        if start - clock >= 0.0005:
            lines.append(f"wait {seconds(start - clock)}")
            clock += float(seconds(start - clock)[:-1])
        if len(group) == 1:
            lines.extend(group[0].command.splitlines())
        else:
            lines.extend(_together(group[0])[:-1])
            for p in group[1:]:
                lines.extend(_joining(p, start))
            lines.append("}")
        clock += max(p.at - start + p.duration for p in group)
    return lines


def overlapping(presses: List[Press]) -> List[List[Press]]:
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


def _together(first: Press) -> List[str]:
    return ["together {", *("  " + line for line in first.command.splitlines()), "}"]


def _joining(p: Press, start: float) -> List[str]:
    """A press's lines in the `together` of presses it overlaps, which started at `start`."""
    lines = ["  repeat 1 {", f"    wait {seconds(p.at - start)}"]
    lines.extend("    " + line for line in p.command.splitlines())
    return [*lines, "  }"]


def lines_size(lines: List[str]) -> Tuple[int, int]:
    """Bytes and pieces (as a script's piece limit counts them) of `lines`, each with its newline.
    The pieces are counted a line at a time: never fewer than in the whole text (where blank lines
    run into one piece), the same without blank lines."""
    return (
        sum(len(line.encode("utf-8", "surrogatepass")) + 1 for line in lines),
        sum(len(PIECE.findall(line)) + 1 for line in lines),
    )


def _plus(a: Tuple[int, int], b: Tuple[int, int]) -> Tuple[int, int]:
    return (a[0] + b[0], a[1] + b[1])


class TextSize(NamedTuple):
    """The size of `body(presses)`, and what adding a press to it needs: the groups before the
    last one (`closed`, with their `wait`s), and the last group as `body` writes it."""

    closed: Tuple[int, int] = (0, 0)
    clock: float = 0.0  # where `body`'s clock is when the last group starts
    first: Optional[Press] = None  # the last group's first press; None before any
    count: int = 0  # presses in the last group
    end: float = float("-inf")  # when its presses have all finished
    longest: float = 0.0  # how long it runs, as `body` adds it to its clock
    group: Tuple[int, int] = (0, 0)  # its bytes and pieces
    plain: bool = True  # no `wait` and no `together` yet: the presses' own lines, one after another

    @property
    def total(self) -> Tuple[int, int]:
        """Bytes and pieces of the whole body."""
        return _plus(self.closed, self.group)

    def add(self, p: Press) -> TextSize:
        """The size with `p` pressed after the presses counted (in time order): one press's lines."""
        if self.first is not None and p.at < self.end:  # it joins the last group
            start = self.first.at
            joining = lines_size(_joining(p, start))
            group = _plus(lines_size(_together(self.first)) if self.count == 1 else self.group, joining)
            return self._replace(
                count=self.count + 1,
                end=max(self.end, p.at + p.duration),
                longest=max(self.longest, p.at - start + p.duration),
                group=group,
                plain=False,
            )
        closed, clock = _plus(self.closed, self.group), self.clock + self.longest
        plain = self.plain
        if p.at - clock >= 0.0005:
            plain = False
            closed = _plus(closed, lines_size([f"wait {seconds(p.at - clock)}"]))
            clock += float(seconds(p.at - clock)[:-1])
        group = lines_size(p.command.splitlines())
        return TextSize(closed, clock, p, 1, p.at + p.duration, p.duration, group, plain)
