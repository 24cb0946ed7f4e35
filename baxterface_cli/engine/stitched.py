"""The timelines a session played, one after another, as one timeline: what `render`, `play` and
`explain` take from a session run over an events file.

Each timeline plays from its start until the next one starts; it is sampled exactly as it would
be alone, at the time since its start. What it had not yet done when the next one took over is
left out: its later cues, its words and sound past the cut. A `say` cut short is a `StoppedSpeech`
cue, its utterance as far as it was heard: a bag tells sound_play to stop it there.

A session's run also says, for each timeline, how many lines its log had when it began (`marks`):
`explain` reads a step between the lines that led to it and those that followed, when they fall
at the same time.
"""

from __future__ import annotations

import bisect
import dataclasses
from typing import Any, List, NamedTuple, Optional, Sequence, Tuple

from ..core.face_state import FaceState
from .effects import Cue, RobotStatus, Speech, fold_status
from .timeline import Said, Span, Timeline

Segments = Sequence[Tuple[float, Timeline]]
# A `say` cut this near its end has lost only the silence kept after its voice (10 ms, the
# synthesis's Trim.keep, and a frame's rounding of where its step ends): it was said whole.
HEARD_WHOLE = 0.02


@dataclasses.dataclass(frozen=True)
class StoppedSpeech(Speech):
    """A `say` that what came next stopped before its end (an `interrupt`, a new script, the run's
    end): its utterance is what was heard. Everything that handles a Speech handles it as one."""


class Piece(NamedTuple):
    """What one segment shows, on the stitched clock, as far as it plays."""

    cues: List[Cue]
    parts: List[Any]
    spans: List[Span]
    speech: List[Said]


class _Joined:
    """One track (eyes or lids) across the segments: what the idle layer asks of a track."""

    def __init__(self, stitched: Stitched, name: str) -> None:
        self.stitched = stitched
        self.name = name

    def value(self, t: float) -> Any:
        start, timeline, _ = self.stitched.segment(t)
        return getattr(timeline, self.name).value(t - start)

    def busy(self, start: float, end: float) -> bool:
        for begin, timeline, stop in self.stitched.overlapping(start, end):
            a, b = max(start, begin), min(end, stop)
            if getattr(timeline, self.name).busy(a - begin, b - begin):
                return True
        return False


class Stitched:
    """Timelines, each from its start until the next's, as one (see the module's docstring)."""

    def __init__(self, segments: Segments, duration: float, marks: Optional[Sequence[int]] = None) -> None:
        if not segments:
            raise ValueError("a stitched timeline needs a timeline")
        self.segments = list(segments)
        self.marks = None if marks is None else list(marks)  # the session's log lines before each began
        self.starts = [start for start, _ in self.segments]
        self.stops = self.starts[1:] + [float("inf")]
        self.duration = duration
        self.initial: FaceState = self.segments[0][1].initial
        self.cues: List[Cue] = []
        self.speech: List[Said] = []
        self.spans: List[Span] = []
        self.parts: List[Any] = []
        self.pieces: List[Piece] = []
        for (start, timeline), stop in zip(self.segments, self.stops):
            piece = _piece(start, timeline, min(stop, duration))
            self.pieces.append(piece)
            self.cues += piece.cues
            self.parts += piece.parts
            self.spans += piece.spans
            self.speech += piece.speech
        self.eyes = _Joined(self, "eyes")
        self.lids = _Joined(self, "lids")
        self._speech_times = [said.at for said in self.speech]

    def segment(self, t: float) -> Tuple[float, Timeline, float]:
        """The timeline playing at `t`: (its start, it, the next's start)."""
        i = max(0, bisect.bisect_right(self.starts, t) - 1)
        return self.starts[i], self.segments[i][1], self.stops[i]

    def overlapping(self, start: float, end: float) -> List[Tuple[float, Timeline, float]]:
        first = max(0, bisect.bisect_right(self.starts, start) - 1)
        last = bisect.bisect_left(self.starts, end)
        return [
            (self.starts[i], self.segments[i][1], self.stops[i]) for i in range(first, max(first + 1, last))
        ]

    def sample(self, t: float) -> FaceState:
        start, timeline, _ = self.segment(t)
        return timeline.sample(t - start)

    def mood_at(self, t: float) -> Tuple[float, float]:
        start, timeline, _ = self.segment(t)
        return timeline.mood_at(t - start)

    def sounding(self, t: float) -> List[Said]:
        i = bisect.bisect_right(self._speech_times, t)
        return [said for said in self.speech[:i] if t < said.end]

    def status(self, t: float, start: Any = None) -> RobotStatus:
        return fold_status(self.cues, t, start)


def _piece(start: float, timeline: Timeline, stop: float) -> Piece:
    spans = []
    for span in timeline.spans:
        if start + span.start <= stop:
            cut = start + span.end > stop
            text = span.text + (" (stopped)" if cut else "")
            spans.append(Span(start + span.start, min(stop, start + span.end), span.line, text))
    return Piece(
        [
            Cue(start + c.at, _heard_effect(c.effect, stop - start - c.at))
            for c in timeline.cues
            if start + c.at <= stop
        ],
        # A change at the very end of a step shows: the next step starts from the face it made.
        [c._replace(at=start + c.at) for c in timeline.parts if start + c.at <= stop],
        spans,
        [cut_short(said, start, stop) for said in timeline.speech if start + said.at < stop],
    )


def cut_short(said: Said, start: float, stop: float) -> Said:
    """`said` (of a timeline started at `start`) on the stitched clock, its sound and words ending
    at `stop`."""
    return said._replace(at=start + said.at, utterance=_heard(said.utterance, stop - (start + said.at)))


def _heard(utterance: Any, left: float) -> Any:
    """`utterance` as far as it is heard in `left` seconds: its sound, words and phonemes."""
    if left >= utterance.duration:
        return utterance
    keep = max(0, int(left * utterance.sample_rate))
    return dataclasses.replace(
        utterance,
        samples=utterance.samples[:keep],
        words=tuple(w for w in utterance.words if w.at < left),
        phonemes=tuple(p for p in utterance.phonemes if p.at < left),
    )


def _heard_effect(effect: Any, left: float) -> Any:
    """A Speech effect with `left` seconds to play before the next timeline: a StoppedSpeech if
    that is less than it lasts."""
    if not isinstance(effect, Speech) or left >= effect.utterance.duration - HEARD_WHOLE:
        return effect
    return StoppedSpeech(_heard(effect.utterance, left))
