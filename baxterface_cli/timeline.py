"""Script -> timeline of tracks -> face state at any time t.

`compile_script` walks the AST with a clock and turns each statement into
changes on tracks: eyes (x, y), lids, head pan, the parts (skin, mouth,
brows, which swap with a short crossfade) and robot actions (enable, follow,
nod, exit). Changes are applied in time order, each starting from wherever
its track is at that moment, so `together` blocks and interrupted moves
compose. `Timeline.sample(t)` is then a pure lookup.
"""

from __future__ import annotations

import bisect
import random
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, List, NamedTuple, Optional, Sequence

from . import nodes as n
from .easing import EASINGS
from .face import emotion_variants
from .geometry import clamp_pan, clamp_to_ellipse
from .state import FaceState, Parts
from .tables import EMOTIONS, EYE_RADIUS_X, TIMING

CROSSFADE = 0.15  # seconds a script's part swap blends over; 0 cuts
EYE_SPAN_RAD = 0.25  # the eyes alone cover this much either side of the head
RAD_PER_PIXEL = 3.0 / 160.0  # eye x 80 <-> head 1.5 rad


def to_radians(x: float) -> float:
    return x * RAD_PER_PIXEL


def to_pixels(rad: float) -> float:
    return rad / RAD_PER_PIXEL


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


class Action(NamedTuple):
    """Something only the robot can do, at a time: enable, disable, nod, follow, head, exit."""

    at: float
    kind: str
    value: Any = None
    duration: float = 0.0


class Span(NamedTuple):
    """What one statement does, for `explain`."""

    start: float
    end: float
    line: int
    text: str


class RobotStatus(NamedTuple):
    """What the robot would be doing at a time, beyond the screen."""

    enabled: Optional[bool]  # None: the script never said
    following: Optional[str]  # "human", "left arm", "right arm" or None
    follow_dynamic: bool
    nodding: bool
    exited: bool


@dataclass
class Timeline:
    """A compiled script: tracks, part changes, robot actions and a length."""

    eyes: Track
    lids: Track
    head: Track
    parts: List[PartsChange]
    actions: List[Action]
    spans: List[Span]
    duration: float
    initial: FaceState
    _part_times: List[float] = field(default_factory=list, repr=False)

    def __post_init__(self) -> None:
        self._part_times = [c.at for c in self.parts]

    def sample(self, t: float) -> FaceState:
        """The face at time t (seconds from the start): pure, the same every call."""
        x, y = self.eyes.value(t)
        state = self.initial.replace(
            eye_x=x, eye_y=y, eyelids=self.lids.value(t), head_pan=self.head.value(t)
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

    def status(self, t: float) -> RobotStatus:
        enabled, following, dynamic, nodding, exited = None, None, False, False, False
        for action in self.actions:
            if action.at > t:
                break
            if action.kind in ("enable", "disable"):
                enabled = action.kind == "enable"
            elif action.kind == "follow":
                following, dynamic = action.value
            elif action.kind == "nod":
                nodding = t < action.at + action.duration
            elif action.kind == "exit":
                exited = True
        return RobotStatus(enabled, following, dynamic, nodding, exited)

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

    def __init__(self, script: n.Script, rng: random.Random, start: FaceState, crossfade: float) -> None:
        self.definitions = script.definitions
        self.rng = rng
        self.crossfade = crossfade
        self.start = start
        self.eyes = Track((start.eye_x, start.eye_y))
        self.lids = Track(start.eyelids)
        self.head = Track(start.head_pan)
        self.parts: List[PartsChange] = []
        self.actions: List[Action] = []
        self.spans: List[Span] = []
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
        mouth, brows = self.rng.choice(emotion_variants(s.name))
        self.later(t, lambda at: self.lids.move(at, spec.lid_seconds, spec.eyelids))
        self.change_parts(t + spec.lid_seconds, skin=spec.skin, mouth=mouth, brows=brows)
        return t + spec.lid_seconds

    def do_look(self, s: n.Look, t: float) -> float:
        duration = TIMING.look if s.duration is None else s.duration
        target = clamp_to_ellipse(s.x, s.y)
        if not s.dynamic:
            self.later(t, lambda at: self.eyes.move(at, duration, target, s.easing))
            return t + duration

        def dynamic(at: float) -> None:
            head_rad = self.head.value(at)
            want = to_radians(s.x)
            if abs(want - head_rad) > EYE_SPAN_RAD:
                pan = clamp_pan(want)
                self.head.move(at, duration, pan, s.easing)
                self.actions.append(Action(at, "head", pan, duration))
                self.eyes.move(at, duration, clamp_to_ellipse(0.0, s.y), s.easing)
            else:
                eye_x = max(-EYE_RADIUS_X, min(EYE_RADIUS_X, to_pixels(want - head_rad)))
                self.eyes.move(at, duration, clamp_to_ellipse(eye_x, s.y), s.easing)

        self.later(t, dynamic)
        return t + duration

    def do_blink(self, s: n.Blink, t: float) -> float:
        def blink(at: float) -> None:
            before = self.lids.value(at)
            self.lids.move(at, TIMING.blink_close, 0.0)
            self.lids.move(at + TIMING.blink_close, TIMING.blink_open, before)

        self.later(t, blink)
        return t + TIMING.blink_close + TIMING.blink_open

    def do_eyelids(self, s: n.Eyelids, t: float) -> float:
        duration = TIMING.eyelids if s.duration is None else s.duration
        self.later(t, lambda at: self.lids.move(at, duration, s.openness, s.easing))
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
        duration = TIMING.wobble if s.duration is None else s.duration
        pan = clamp_pan(s.angle)

        def wobble(at: float) -> None:
            self.head.move(at, duration, pan, s.easing)
            self.actions.append(Action(at, "head", pan, duration))

        self.later(t, wobble)
        return t + duration

    def do_nod(self, s: n.Nod, t: float) -> float:
        self.later(t, lambda at: self.actions.append(Action(at, "nod", None, TIMING.nod)))
        return t + TIMING.nod

    def do_enable(self, s: n.Enable, t: float) -> float:
        self.later(t, lambda at: self.actions.append(Action(at, "enable")))
        return t

    def do_disable(self, s: n.Disable, t: float) -> float:
        self.later(t, lambda at: self.actions.append(Action(at, "disable")))
        return t

    def do_follow(self, s: n.Follow, t: float) -> float:
        def follow(at: float) -> None:
            self.actions.append(Action(at, "follow", (s.target, s.dynamic)))
            if s.target is None:  # stopping recentres the eyes, as the original did
                self.eyes.move(at, TIMING.look, (0.0, 0.0))

        self.later(t, follow)
        return t

    def do_exit(self, s: n.Exit, t: float) -> float:
        # The sleep face, fully faded in, is the last thing shown.
        end = self.do_emotion(n.Emotion("sleep", pos=s.pos), t) + self.crossfade
        self.later(end, lambda at: self.actions.append(Action(at, "exit")))
        self.exit_at = end
        return end


def compile_script(
    script: n.Script,
    seed: Optional[int] = 0,
    start: Optional[FaceState] = None,
    crossfade: Optional[float] = None,
) -> Timeline:
    """Compile a parsed script; the same script and seed give the same timeline.

    Part swaps blend over `crossfade` seconds: by default CROSSFADE for a
    script and none (a cut, as the old node did) for legacy commands.
    """
    if crossfade is None:
        crossfade = 0.0 if script.legacy else CROSSFADE
    compiler = _Compiler(script, random.Random(seed), start or FaceState(), crossfade)
    end = compiler.sequence(script.body, 0.0)
    for event in sorted(compiler.events, key=lambda e: (e.at, e.order)):
        event.apply(event.at)
    compiler.actions.sort(key=lambda a: a.at)
    tails = [end, compiler.eyes.end, compiler.lids.end, compiler.head.end]
    tails += [c.at + c.fade for c in compiler.parts] + [a.at + a.duration for a in compiler.actions]
    duration = max(tails)
    if compiler.exit_at is not None:
        duration = compiler.exit_at
    compiler.spans.sort(key=lambda s: (s.start, s.line))
    return Timeline(
        compiler.eyes,
        compiler.lids,
        compiler.head,
        compiler.parts,
        compiler.actions,
        compiler.spans,
        duration,
        start or FaceState(),
    )


def describe(s: Any) -> str:
    """A statement in words, for `explain`."""

    def timed(duration: Optional[float], easing: str, default: float) -> str:
        seconds = default if duration is None else duration
        return f" in {seconds:g}s" + ("" if easing == "linear" else f" {easing}")

    if isinstance(s, n.Emotion):
        return s.name
    if isinstance(s, n.Look):
        kind = "dynamic look" if s.dynamic else "look"
        return f"{kind} {s.x:g} {s.y:g}{timed(s.duration, s.easing, TIMING.look)}"
    if isinstance(s, n.Wobble):
        return f"wobble {s.angle:g} rad{timed(s.duration, s.easing, TIMING.wobble)}"
    if isinstance(s, n.Eyelids):
        return f"eyelids {s.openness:g}{timed(s.duration, s.easing, TIMING.eyelids)}"
    if isinstance(s, n.Wait):
        return f"wait {s.duration:g}s"
    if isinstance(s, n.Skin):
        return f"skin {s.index}"
    if isinstance(s, (n.Mouth, n.Brows)):
        return f"{type(s).__name__.lower()} {s.name}"
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
        "enabled": status.enabled,
        "following": status.following,
        "follow_dynamic": status.follow_dynamic,
        "nodding": status.nodding,
        "exited": status.exited,
    }
