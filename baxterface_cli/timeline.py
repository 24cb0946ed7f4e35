"""Script -> timeline of tracks -> face state at any time t.

`compile_script` walks the AST with a clock and turns each statement into
changes on tracks: eyes (x, y), lids, head pan, the parts (skin, mouth,
brows, which swap with a short crossfade), the emotion's name, speech (its
mouth shapes over the parts' mouth), and cues of robot effects (see
`effects`). Changes are applied in time order, each
starting from wherever its track is at that moment, so `together` blocks and
interrupted moves compose. `Timeline.sample(t)` is then a pure lookup.
"""

from __future__ import annotations

import bisect
import random
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable, Dict, List, NamedTuple, Optional, Sequence, Tuple

from . import effects as fx
from . import nodes as n
from .durations import move_seconds
from .easing import EASINGS
from .effects import Cue, RobotStatus, StatusFold
from .geometry import clamp_pan, clamp_to_ellipse, dynamic_look, to_radians
from .state import FaceState, Parts
from .tables import EMOTIONS, HEAD_SPEED_RATIO, HEAD_TOP_SPEED, REST, TIMING, viseme_mouth

if TYPE_CHECKING:
    from .speech import Utterance
    from .visemes import MouthKey

# Speaks text in a voice (None: the default) at a rate (None: the default).
Speaker = Callable[[str, Optional[str], Optional[int]], "Utterance"]

CROSSFADE = 0.15  # seconds a script's part swap blends over; 0 cuts


class Piece(NamedTuple):
    """A track moving from `start_value` to `end_value` over [start, end).

    A move interrupted at `until` holds the value its curve had reached
    then; the curve itself is kept, so an eased move is cut, not reshaped.
    """

    start: float
    end: float
    start_value: Any
    end_value: Any
    easing: str
    until: float = float("inf")

    def at(self, t: float) -> Any:
        t = min(t, self.until)
        if t >= self.end or self.end <= self.start:
            return self.end_value
        progress = EASINGS[self.easing]((t - self.start) / (self.end - self.start))
        return _mix(self.start_value, self.end_value, progress)

    @property
    def stop(self) -> float:
        return min(self.end, self.until)


class Track:
    """One animated value: held between pieces, eased within them."""

    def __init__(self, initial: Any) -> None:
        self.initial = initial
        self.pieces: List[Piece] = []
        self._starts: List[float] = []

    def value(self, t: float) -> Any:
        i = bisect.bisect_right(self._starts, t) - 1
        return self.initial if i < 0 else self.pieces[i].at(t)

    def move(self, start: float, duration: float, target: Any, easing: str = "linear") -> None:
        """From wherever the track is at `start`, move to `target`; later pieces give way."""
        current = self.value(start)
        i = bisect.bisect_left(self._starts, start)
        if i > 0 and self.pieces[i - 1].stop > start:  # interrupt the move under way
            self.pieces[i - 1] = self.pieces[i - 1]._replace(until=start)
        del self.pieces[i:], self._starts[i:]  # and drop moves queued after it
        self.pieces.append(Piece(start, start + max(0.0, duration), current, target, easing))
        self._starts.append(start)

    def busy(self, start: float, end: float) -> bool:
        """Does any piece move the track during [start, end)?"""
        return any(p.start < end and start < p.stop for p in self.pieces)

    @property
    def end(self) -> float:
        return self.pieces[-1].stop if self.pieces else 0.0


def _mix(a: Any, b: Any, u: float) -> Any:
    if isinstance(a, tuple):
        return tuple(x + (y - x) * u for x, y in zip(a, b))
    return a + (b - a) * u


class PartsChange(NamedTuple):
    at: float
    parts: Parts
    fade: float  # seconds


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
    """A compiled script: tracks, part changes, emotions, robot cues and a length."""

    eyes: Track
    lids: Track
    head: Track
    parts: List[PartsChange]
    emotions: List[Tuple[float, str]]  # (when asked for, name), in time order
    cues: List[Cue]  # robot effects, in time order
    spans: List[Span]
    duration: float
    initial: FaceState
    speech: List[Said] = field(default_factory=list)  # in time order
    _part_times: List[float] = field(default_factory=list, repr=False)
    _emotion_times: List[float] = field(default_factory=list, repr=False)
    _speech_times: List[float] = field(default_factory=list, repr=False)

    def __post_init__(self) -> None:
        self._part_times = [c.at for c in self.parts]
        self._emotion_times = [at for at, _ in self.emotions]
        self._speech_times = [said.at for said in self.speech]

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
        state = self.initial.replace(
            eye_x=x,
            eye_y=y,
            eyelids=self.lids.value(t),
            head_pan=self.head.value(t),
            emotion=self.emotions[i][1] if i >= 0 else self.initial.emotion,
        )
        i = bisect.bisect_right(self._part_times, t) - 1
        if i < 0:
            return state
        change = self.parts[i]
        state = state.with_parts(change.parts)
        elapsed = t - change.at
        if elapsed < change.fade - 1e-9:  # the end of a fade, up to float rounding, is no fade
            before = self.parts[i - 1].parts if i > 0 else self.initial.parts
            if before != change.parts:
                return state.replace(fade_from=before, fade=elapsed / change.fade)
        return state.replace(fade_from=None, fade=1.0)

    def status(self, t: float, start: Optional[RobotStatus] = None) -> RobotStatus:
        """The robot's status at t: `start` with every cue up to t folded in."""
        fold = StatusFold(start)
        for cue in self.cues:
            if cue.at > t:
                break
            cue.effect.visit(fold, cue.at)
        return fold.status

    def frame_times(self, fps: float) -> List[float]:
        """Frame times from 0 through the end, the last frame at the end itself."""
        count = int(self.duration * fps + 1e-9) + 1
        return [i / fps for i in range(count)]


# -- compiling -------------------------------------------------------------


class _Event(NamedTuple):
    at: float
    order: int
    apply: Callable[[float], None]


class _Compiler:
    """Walks the AST with a clock, queueing track changes to apply in time order."""

    def __init__(
        self, script: n.Script, rng: random.Random, start: FaceState, crossfade: float, speak: Speaker
    ) -> None:
        self.definitions = script.definitions
        self.speak = speak
        self.rng = rng
        self.crossfade = crossfade
        self.start = start
        self.eyes = Track((start.eye_x, start.eye_y))
        self.lids = Track(start.eyelids)
        self.head = Track(start.head_pan)
        self.parts: List[PartsChange] = []
        self.emotions: List[Tuple[float, str]] = []
        self.cues: List[Cue] = []
        self.spans: List[Span] = []
        self.speech: List[Said] = []
        self.events: List[_Event] = []
        self.exit_at: Optional[float] = None

    def later(self, at: float, apply: Callable[[float], None]) -> None:
        self.events.append(_Event(at, len(self.events), apply))

    def sequence(self, body: Sequence[Any], t: float) -> float:
        for statement in body:
            if self.exit_at is not None:
                break
            t = self.statement(statement, t)
        return t

    def statement(self, s: Any, t: float) -> float:
        handler = getattr(self, "do_" + type(s).__name__.lower())
        end = handler(s, t)
        if not isinstance(s, (n.Repeat, n.Together, n.Call, n.Define)):
            self.spans.append(Span(t, end, s.pos.line, describe(s)))
        return end

    # -- blocks

    def do_repeat(self, s: n.Repeat, t: float) -> float:
        for _ in range(s.count):
            t = self.sequence(s.body, t)
        return t

    def do_together(self, s: n.Together, t: float) -> float:
        return max([self.sequence((child,), t) for child in s.body], default=t)

    def do_call(self, s: n.Call, t: float) -> float:
        return self.sequence(self.definitions[s.name].body, t)

    def do_define(self, s: n.Define, t: float) -> float:
        return t

    # -- the face

    def do_emotion(self, s: n.Emotion, t: float) -> float:
        spec = EMOTIONS[s.name]
        mouth, brows = self.rng.choice(spec.variants)

        def lids_first(at: float) -> None:
            self.emotions.append((at, s.name))
            self.lids.move(at, spec.lid_seconds, spec.eyelids)

        self.later(t, lids_first)
        self.change_parts(t + spec.lid_seconds, skin=spec.skin, mouth=mouth, brows=brows)
        return t + spec.lid_seconds

    def do_look(self, s: n.Look, t: float) -> float:
        duration, easing = move_seconds(s), s.timing.easing
        if not s.dynamic:
            target = clamp_to_ellipse(s.x, s.y)
            self.later(t, lambda at: self.eyes.move(at, duration, target, easing))
            return t + duration

        def dynamic(at: float) -> None:
            pan, eye_x = dynamic_look(to_radians(s.x), self.head.value(at))
            if pan is not None:
                self.pan_head(at, pan, duration, easing)
            self.eyes.move(at, duration, clamp_to_ellipse(eye_x, s.y), easing)

        self.later(t, dynamic)
        return t + duration

    def pan_head(self, at: float, target: float, duration: float, easing: str) -> None:
        """Move the head track, and cue the robot with the speed that keeps pace with it."""
        start = self.head.value(at)
        self.head.move(at, duration, target, easing)
        self.cues.append(Cue(at, fx.HeadPan(target, head_speed(start, target, duration), duration)))

    def do_blink(self, s: n.Blink, t: float) -> float:
        def blink(at: float) -> None:
            before = self.lids.value(at)
            self.lids.move(at, TIMING.blink_close, 0.0)
            self.lids.move(at + TIMING.blink_close, TIMING.blink_open, before)

        self.later(t, blink)
        return t + TIMING.blink_close + TIMING.blink_open

    def do_eyelids(self, s: n.Eyelids, t: float) -> float:
        duration = move_seconds(s)
        self.later(t, lambda at: self.lids.move(at, duration, s.openness, s.timing.easing))
        return t + duration

    def do_skin(self, s: n.Skin, t: float) -> float:
        self.change_parts(t, skin=s.index)
        return t

    def do_mouth(self, s: n.Mouth, t: float) -> float:
        self.change_parts(t, mouth=s.name)
        return t

    def do_brows(self, s: n.Brows, t: float) -> float:
        self.change_parts(t, brows=s.name)
        return t

    def change_parts(self, t: float, **changed: Any) -> None:
        def apply(at: float) -> None:
            current = self.parts[-1].parts if self.parts else self.start.parts
            self.parts.append(PartsChange(at, current._replace(**changed), self.crossfade))

        self.later(t, apply)

    def do_wait(self, s: n.Wait, t: float) -> float:
        return t + s.duration

    # -- the robot

    def do_wobble(self, s: n.Wobble, t: float) -> float:
        duration = move_seconds(s)
        self.later(t, lambda at: self.pan_head(at, clamp_pan(s.angle), duration, s.timing.easing))
        return t + duration

    def cue(self, t: float, effect: fx.Effect) -> None:
        self.later(t, lambda at: self.cues.append(Cue(at, effect)))

    def do_nod(self, s: n.Nod, t: float) -> float:
        self.cue(t, fx.HeadNod(TIMING.nod))
        return t + TIMING.nod

    def do_enable(self, s: n.Enable, t: float) -> float:
        self.cue(t, fx.SetEnabled(True))
        return t

    def do_disable(self, s: n.Disable, t: float) -> float:
        self.cue(t, fx.SetEnabled(False))
        return t

    def do_follow(self, s: n.Follow, t: float) -> float:
        self.cue(t, fx.Follow(s.target, s.dynamic))
        if s.target is None:  # stopping recentres the eyes, as the original did
            self.later(t, lambda at: self.eyes.move(at, TIMING.look, (0.0, 0.0)))
        return t

    def do_say(self, s: n.Say, t: float) -> float:
        from .visemes import mouth_track

        utterance = self.speak(s.text, s.voice, s.rate)
        said = Said(t, utterance, mouth_track(utterance))
        self.later(t, lambda at: self.speech.append(said))
        self.cue(t, fx.Speech(utterance))
        return t + utterance.duration

    def do_exit(self, s: n.Exit, t: float) -> float:
        # The sleep face, fully faded in, is the last thing shown.
        end = self.do_emotion(n.Emotion("sleep", pos=s.pos), t) + self.crossfade
        self.cue(end, fx.Exit())
        self.exit_at = end
        return end


def _speaking(state: FaceState, said: Said, t: float) -> FaceState:
    """The face with the speech shape at t for its mouth; the rest of the face goes on.

    A tween between two shapes uses the crossfade; during an emotion's own
    crossfade, both sides of it show the shape, and the emotion's fade wins.
    """
    from .visemes import shape_at

    shape, tween_from, progress = shape_at(said.mouth, t - said.at)

    def mouth(parts: Parts, name: str) -> Parts:
        return parts._replace(mouth=parts.mouth if name == REST else viseme_mouth(name))

    now = mouth(state.parts, shape)
    if state.fade_from is not None:
        return state.with_parts(now).replace(fade_from=mouth(state.fade_from, shape))
    if tween_from is not None and progress < 1.0:
        before = mouth(state.parts, tween_from)
        if before != now:
            return state.with_parts(now).replace(fade_from=before, fade=progress)
    return state.with_parts(now)


def head_speed(start: float, target: float, duration: float) -> float:
    """The speed ratio that pans the head from `start` to `target` in `duration` seconds."""
    if duration <= 0:
        return HEAD_SPEED_RATIO[1]
    low, high = HEAD_SPEED_RATIO
    return min(high, max(low, abs(target - start) / duration / HEAD_TOP_SPEED))


def compile_script(
    script: n.Script,
    seed: Optional[int] = 0,
    start: Optional[FaceState] = None,
    crossfade: Optional[float] = None,
    speak: Optional[Speaker] = None,
) -> Timeline:
    """Compile a parsed script; the same script and seed give the same timeline.

    Part swaps blend over `crossfade` seconds: by default CROSSFADE for a
    script and none (a cut, as the old node did) for legacy commands. `say`
    speaks through `speak`, by default the espeak-ng engine, which is only
    loaded when a script says something (`extras.MissingTool` without it).
    """
    if crossfade is None:
        crossfade = 0.0 if script.legacy else CROSSFADE
    compiler = _Compiler(script, random.Random(seed), start or FaceState(), crossfade, speak or _engine_say)
    end = compiler.sequence(script.body, 0.0)
    for event in sorted(compiler.events, key=lambda e: (e.at, e.order)):
        event.apply(event.at)
    tails = [end, compiler.eyes.end, compiler.lids.end, compiler.head.end]
    tails += [c.at + c.fade for c in compiler.parts]
    tails += [c.at + c.effect.duration for c in compiler.cues]
    duration = max(tails)
    if compiler.exit_at is not None:
        duration = compiler.exit_at
    compiler.spans.sort(key=lambda s: (s.start, s.line))
    return Timeline(
        compiler.eyes,
        compiler.lids,
        compiler.head,
        compiler.parts,
        compiler.emotions,
        compiler.cues,
        compiler.spans,
        duration,
        start or FaceState(),
        compiler.speech,
    )


def _engine_say(text: str, voice: Optional[str], rate: Optional[int]) -> Utterance:
    from .speech import engine
    from .voices import DEFAULT_RATE, DEFAULT_VOICE

    return engine().say(text, voice or DEFAULT_VOICE, rate or DEFAULT_RATE)


def describe(s: Any) -> str:
    """A statement in words, for `explain`."""

    def timed(s: Any) -> str:
        easing = s.timing.easing
        return f" in {move_seconds(s):g}s" + ("" if easing == "linear" else f" {easing}")

    if isinstance(s, n.Emotion):
        return s.name
    if isinstance(s, n.Look):
        kind = "dynamic look" if s.dynamic else "look"
        return f"{kind} {s.x:g} {s.y:g}{timed(s)}"
    if isinstance(s, n.Wobble):
        return f"wobble {fx.radians_and_degrees(s.angle)}{timed(s)}"
    if isinstance(s, n.Eyelids):
        return f"eyelids {s.openness:g}{timed(s)}"
    if isinstance(s, n.Wait):
        return f"wait {s.duration:g}s"
    if isinstance(s, n.Skin):
        return f"skin {s.index}"
    if isinstance(s, (n.Mouth, n.Brows)):
        return f"{type(s).__name__.lower()} {s.name}"
    if isinstance(s, n.Say):
        return (
            f"say {fx.quoted(s.text)}"
            + (f" voice {s.voice}" if s.voice else "")
            + (f" rate {s.rate}" if s.rate else "")
        )
    if isinstance(s, n.Follow):
        if s.target is None:
            return "follow off"
        return f"follow {s.target}" + (" dynamic" if s.dynamic else "")
    return type(s).__name__.lower()


def state_record(t: float, state: FaceState, status: RobotStatus) -> Dict[str, Any]:
    """One frame of `explain --json`: the whole face state and robot status."""
    return {
        "t": round(t, 6),
        "skin": state.skin,
        "mouth": state.mouth,
        "brows": state.brows,
        "eye_x": round(state.eye_x, 4),
        "eye_y": round(state.eye_y, 4),
        "eyelids": round(state.eyelids, 4),
        "head_pan": round(state.head_pan, 4),
        "fade_from": list(state.fade_from) if state.fade_from else None,
        "fade": round(state.fade, 4),
        "emotion": state.emotion,
        "enabled": status.enabled,
        "following": status.following,
        "follow_dynamic": status.follow_dynamic,
        "nodding": status.nodding(t),
        "exited": status.exited,
        "saying": status.speaking(t),
    }
