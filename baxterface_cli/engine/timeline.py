"""A timeline: tracks of timed changes, and the face state they give at any time t.

The compiler (compiler.py) fills the tracks: eyes (x, y), lids, head pan, the
expression's numbers (shape_tracks.py), the emotion's name, speech and the robot cues. The
named parts that themes of pictures show are read off the numbers (pictures.py).
`Timeline.sample(t)` is then a pure lookup.
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, Callable, Dict, List, NamedTuple, Optional, Tuple

from ..core.expression import Expression
from ..core.face_constants import REST
from ..core.face_state import FaceState
from ..core.presets import nearest_parts, speech_mouth
from .effects import Cue, RobotStatus, fold_status
from .pictures import PartsChange, picture_changes
from .shape_tracks import ShapeTracks
from .tracks import Piece, Track

__all__ = [
    "CROSSFADE",
    "PartsChange",
    "Piece",
    "Said",
    "Span",
    "TextToSpeech",
    "Timeline",
    "Track",
    "state_record",
]

if TYPE_CHECKING:
    from ..speech.synthesis import Utterance
    from ..speech.visemes import MouthKey

# Speaks text in a voice (None: the default) at a rate (None: the default).
TextToSpeech = Callable[[str, Optional[str], Optional[int]], "Utterance"]

CROSSFADE = 0.15  # seconds a script's part swap blends over; 0 cuts


class Said(NamedTuple):
    """An utterance the face says from `at`, with the mouth shapes that go with it."""

    at: float
    utterance: Utterance
    mouth: Tuple[MouthKey, ...]

    @property
    def end(self) -> float:
        return self.at + self.utterance.duration


class Span(NamedTuple):
    """What one statement does, for `explain`."""

    start: float
    end: float
    line: int
    text: str


@dataclass
class Timeline:
    """A compiled script: tracks, emotions, robot cues and a length; `parts`, the named parts'
    changes that themes of pictures show, are read off the expression's numbers."""

    eyes: Track
    lids: Track
    head: Track
    emotions: List[Tuple[float, str]]  # (when asked for, name), in time order
    cues: List[Cue]  # robot effects, in time order
    spans: List[Span]
    duration: float
    initial: FaceState
    speech: List[Said] = field(default_factory=list)  # in time order
    shape: Optional[ShapeTracks] = None  # the expression; None: the start's, throughout
    moods: List[Tuple[float, float, float]] = field(default_factory=list)  # (at, valence, arousal)
    parts: List[PartsChange] = field(init=False)
    _part_times: List[float] = field(default_factory=list, repr=False)
    _emotion_times: List[float] = field(default_factory=list, repr=False)
    _speech_times: List[float] = field(default_factory=list, repr=False)
    _mood_times: List[float] = field(default_factory=list, repr=False)

    def __post_init__(self) -> None:
        before = nearest_parts(_shown_first(self.initial))
        self.parts = [] if self.shape is None else picture_changes(self.shape, before)
        self._part_times = [c.at for c in self.parts]
        self._emotion_times = [at for at, _ in self.emotions]
        self._speech_times = [said.at for said in self.speech]
        self._mood_times = [at for at, _, _ in self.moods]

    def mood_at(self, t: float) -> Tuple[float, float]:
        """(valence, arousal) the script's last `mood` asked for by t; the start's before any."""
        i = bisect.bisect_right(self._mood_times, t) - 1
        return self.initial.mood if i < 0 else (self.moods[i][1], self.moods[i][2])

    def sample(self, t: float) -> FaceState:
        """The face at time t (seconds from the start): pure, the same every call."""
        state = self._sample_parts(t)
        said = self._said(t)
        return state if said is None else _speaking(state, said, t)

    def _said(self, t: float) -> Optional[Said]:
        """The utterance being said at t: the latest begun, if it is still going."""
        i = bisect.bisect_right(self._speech_times, t) - 1
        if i >= 0 and t < self.speech[i].end:
            return self.speech[i]
        return None

    def sounding(self, t: float) -> List[Said]:
        """Every utterance heard at t, earliest first: a `together`'s overlap, as the sound mixes them."""
        i = bisect.bisect_right(self._speech_times, t)
        return [said for said in self.speech[:i] if t < said.end]

    def _sample_parts(self, t: float) -> FaceState:
        x, y = self.eyes.value(t)
        i = bisect.bisect_right(self._emotion_times, t) - 1
        state = replace(
            self.initial,
            eye_x=x,
            eye_y=y,
            eyelids=self.lids.value(t),
            head_pan=self.head.value(t),
            emotion=self.emotions[i][1] if i >= 0 else self.initial.emotion,
            expression=self.initial.expression if self.shape is None else self.shape.value(t),
            mood=self.mood_at(t),
        )
        i = bisect.bisect_right(self._part_times, t) - 1
        if i < 0:
            return state
        change = self.parts[i]
        state = replace(state, pictured=change.shows)
        elapsed = t - change.at
        if elapsed < change.fade - 1e-9:  # the end of a fade, up to float rounding, is no fade
            before = self.parts[i - 1].shows if i > 0 else _shown_first(self.initial)
            if nearest_parts(before) != change.parts:
                return replace(state, pictured_from=before, fade=elapsed / change.fade)
        return replace(state, pictured_from=None, fade=1.0)

    def status(self, t: float, start: Optional[RobotStatus] = None) -> RobotStatus:
        """The robot's status at t: `start` with every cue up to t folded in."""
        return fold_status(self.cues, t, start)

    def frame_times(self, fps: float) -> List[float]:
        """Frame times from 0 through the end, the last frame at the end itself."""
        count = int(self.duration * fps + 1e-9) + 1
        return [i / fps for i in range(count)]


def _speaking(state: FaceState, said: Said, t: float) -> FaceState:
    """The face with the speech shape at t for its mouth; the rest of the face goes on.

    A tween between two shapes uses the crossfade; during an emotion's own
    crossfade, both sides of it show the shape, and the emotion's fade wins.
    """
    from ..speech.visemes import coarticulated_at, shape_at

    shape, tween_from, progress = shape_at(said.mouth, t - said.at)
    heading = _pictured(state)  # the pictures' mouth steps from one speech shape's to the next

    # The drawn face's mouth moves through the shapes between two sounds, not a crossfade.
    drawn, drawn_from, drawn_progress = coarticulated_at(said.mouth, t - said.at)
    spoken = _spoken(state.expression, drawn)
    if drawn_from is not None and drawn_progress < 1.0:
        spoken = _spoken(state.expression, drawn_from).mix(spoken, drawn_progress)
    state = replace(state, expression=spoken)

    now = _spoken(heading, shape)
    if state.pictured_from is not None:
        return replace(state, pictured=now, pictured_from=_spoken(state.pictured_from, shape))
    if tween_from is not None and progress < 1.0:
        before = _spoken(heading, tween_from)
        if nearest_parts(before) != nearest_parts(now):
            return replace(state, pictured=now, pictured_from=before, fade=progress)
    return replace(state, pictured=now)


def _shown_first(state: FaceState) -> Expression:
    """What the pictures showed before a timeline's first change: where a crossfade under way
    when it began (a session's step starts where the last left off) comes from, so the step's
    carried move goes on fading rather than holding the fade's first picture."""
    if state.pictured_from is not None and state.fade < 1.0:
        return state.pictured_from
    return _pictured(state)


def _pictured(state: FaceState) -> Expression:
    """Where the numbers a theme of pictures shows are heading."""
    return state.expression if state.pictured is None else state.pictured


def _spoken(expression: Expression, shape: str) -> Expression:
    return expression if shape == REST else speech_mouth(expression, shape)


def state_record(t: float, state: FaceState, status: RobotStatus) -> Dict[str, Any]:
    """One frame of `explain --json`: the whole face state and robot status."""
    return {
        "t": round(t, 6),
        **state.as_record(),
        "enabled": status.enabled,
        "following": status.following,
        "follow_dynamic": status.follow_dynamic,
        "nodding": status.nodding(t),
        "exited": status.exited,
        "saying": status.speaking(t),
    }
