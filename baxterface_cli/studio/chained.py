"""A long run's timelines as one, built in chapters so that a new event rebuilds only the last.

`render --events` joins the timelines a session played into one (engine/stitched.py). The studio
shows the same run while events are fired at it, one at a time, for as long as an hour: joining
every timeline again at each event cost more the longer the run. Here the run is cut into
chapters of `CHAPTER` timelines that no event can change any more (each a `Stitched` ending where
the next chapter starts), and only the last chapter, the one an event changes, is joined again.
Every question is answered by the chapter it falls in, as the whole would answer it: the same
face, the same sounds, the same robot status, to the bit.
"""

from __future__ import annotations

import bisect
from typing import Any, List, Optional, Sequence, Tuple

from ..core.face_state import FaceState
from ..engine.effects import RobotStatus, fold_status
from ..engine.stitched import Segments, Stitched
from ..engine.timeline import Said, Span, Timeline

CHAPTER = 64  # timelines a finished chapter holds


class Chapters:
    """The finished chapters of a run: `Stitched`s over its first `covered` segments, and the
    robot's status where each starts (the cues of those before it, folded once)."""

    def __init__(
        self,
        chapters: Tuple[Stitched, ...] = (),
        covered: int = 0,
        before: Tuple[Optional[RobotStatus], ...] = (None,),
    ) -> None:
        self.chapters = chapters
        self.covered = covered
        self.before = before

    def grown(self, segments: Sequence[Tuple[float, Timeline]]) -> Chapters:
        """These chapters, and as many more as `segments` (which begin with what they cover)
        finish: a chapter ends where a later timeline starts later than its last one (two that
        start at once stay in one chapter, where the whole would look at both)."""
        chapters, covered, before = list(self.chapters), self.covered, list(self.before)
        while len(segments) - covered > CHAPTER:
            end = covered + CHAPTER
            while end < len(segments) and segments[end][0] <= segments[end - 1][0]:
                end += 1
            if end >= len(segments):
                break
            chapters.append(Stitched(segments[covered:end], segments[end][0]))
            before.append(fold_status(chapters[-1].cues, float("inf"), before[-1]))
            covered = end
        return Chapters(tuple(chapters), covered, tuple(before))

    def upto(self, segments: int) -> Chapters:
        """The chapters that end before the `segments`-th timeline (those it cannot change)."""
        kept, covered = [], 0
        for chapter in self.chapters:
            after = covered + len(chapter.segments)
            if after >= segments:  # the next chapter's first timeline, its end, may change
                break
            kept.append(chapter)
            covered = after
        return Chapters(tuple(kept), covered, self.before[: len(kept) + 1])


class _Joined:
    """One track (eyes or lids) across the chapters, as `Stitched`'s."""

    def __init__(self, chained: Chained, name: str) -> None:
        self.chained = chained
        self.name = name

    def value(self, t: float) -> Any:
        return getattr(self.chained.chapter(t), self.name).value(t)

    def busy(self, start: float, end: float) -> bool:
        for begin, chapter, stop in self.chained.overlapping(start, end):
            if getattr(chapter, self.name).busy(max(start, begin), min(end, stop)):
                return True
        return False


class Chained:
    """Finished chapters and the last one, as one timeline (see the module's docstring)."""

    def __init__(self, finished: Chapters, last: Stitched) -> None:
        self.finished = finished
        self.chapters: List[Stitched] = [*finished.chapters, last]
        self.starts = [c.starts[0] for c in self.chapters]
        self.stops = self.starts[1:] + [float("inf")]
        self.duration = last.duration
        self.initial: FaceState = self.chapters[0].initial
        self.eyes = _Joined(self, "eyes")
        self.lids = _Joined(self, "lids")

    def _index(self, t: float) -> int:
        return max(0, bisect.bisect_right(self.starts, t) - 1)

    def chapter(self, t: float) -> Stitched:
        return self.chapters[self._index(t)]

    def overlapping(self, start: float, end: float) -> List[Tuple[float, Stitched, float]]:
        first = self._index(start)
        last = max(first + 1, bisect.bisect_left(self.starts, end))
        return [(self.starts[i], self.chapters[i], self.stops[i]) for i in range(first, last)]

    def sample(self, t: float) -> FaceState:
        return self.chapter(t).sample(t)

    def mood_at(self, t: float) -> Tuple[float, float]:
        return self.chapter(t).mood_at(t)

    def sounding(self, t: float) -> List[Said]:
        return self.chapter(t).sounding(t)  # a chapter's words end where it does

    def status(self, t: float, start: Optional[RobotStatus] = None) -> RobotStatus:
        if start is not None:  # from another status: every cue up to t
            return fold_status(self.cues, t, start)
        i = self._index(t)
        return self.chapters[i].status(t, self.finished.before[i])

    # The whole run's lists, made when asked: a fired event never asks for them.

    @property
    def cues(self) -> list:
        return [cue for chapter in self.chapters for cue in chapter.cues]

    @property
    def speech(self) -> List[Said]:
        return [said for chapter in self.chapters for said in chapter.speech]

    @property
    def spans(self) -> List[Span]:
        return [span for chapter in self.chapters for span in chapter.spans]

    def near(self, t: float, most: int) -> Tuple[List[Span], int, List[Said]]:
        """At most `most` spans around `t` (from the chapters nearest it), how many come before
        them, and what those chapters say: what the page lists of a long run, whatever its length."""
        i = self._index(t)
        first, last = i, i + 1
        found = len(self.chapters[i].spans)
        while found < most and (first > 0 or last < len(self.chapters)):
            if last < len(self.chapters):
                found += len(self.chapters[last].spans)
                last += 1
            if first > 0 and found < most:
                first -= 1
                found += len(self.chapters[first].spans)
        spans = [span for chapter in self.chapters[first:last] for span in chapter.spans]
        before = sum(len(chapter.spans) for chapter in self.chapters[:first])
        later = [j for j, span in enumerate(spans) if span.end >= t]
        start = max(0, min((later[0] if later else len(spans)) - most // 4, len(spans) - most))
        speech = [said for chapter in self.chapters[first:last] for said in chapter.speech]
        return spans[start : start + most], before + start, speech


def chained(finished: Chapters, rest: Segments, duration: float) -> Chained:
    """The run until `duration`: the chapters `finished` joined, then `rest`, the timelines played
    after them."""
    return Chained(finished, Stitched(list(rest), duration))
