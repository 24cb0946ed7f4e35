"""Robot effects: what a script asks of the robot beyond its screen, as typed values.

A compiled timeline carries them as cues (an effect at a time). Every consumer
(`explain`, `play`'s status line, the live face, the ROS node and `stream`)
handles them through one interface, `EffectHandler`: one method per effect,
reached by the effect's own `visit`. Adding an effect is one class here and one
method on each handler; a handler that lacks one cannot be instantiated.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, NamedTuple, Optional, Sequence

from ..core.face_constants import TIMING, FollowTarget
from ..language.statements import quoted, radians_and_degrees

if TYPE_CHECKING:  # speech needs numpy; the effects themselves do not
    from ..speech.synthesis import Utterance


class Effect:
    """Something only the robot can do; subclasses are frozen dataclasses."""

    duration: float = 0.0  # seconds the robot is busy with it

    def visit(self, handler: EffectHandler, at: float) -> Any:  # pragma: no cover - abstract
        raise NotImplementedError


@dataclass(frozen=True)
class HeadPan(Effect):
    """Pan the head to `target` radians (already clamped) over `duration` seconds.

    `speed` is the speed ratio (0..1 of the head's top speed) that covers the
    distance in that time, from where the script had the head.
    """

    target: float
    speed: float = 1.0
    duration: float = 0.0

    def visit(self, handler: EffectHandler, at: float) -> Any:
        return handler.head_pan(self, at)


@dataclass(frozen=True)
class HeadNod(Effect):
    """Nod once; the robot's nod takes about `duration` seconds."""

    duration: float = TIMING.nod

    def visit(self, handler: EffectHandler, at: float) -> Any:
        return handler.head_nod(self, at)


@dataclass(frozen=True)
class SetEnabled(Effect):
    """Enable (True) or disable (False) the robot's motors."""

    enabled: bool

    def visit(self, handler: EffectHandler, at: float) -> Any:
        return handler.set_enabled(self, at)


@dataclass(frozen=True)
class SetFollowing(Effect):
    """Start following `target` ("human", "face", "left arm", "right arm"); None stops.

    With `dynamic` the head turns too when the target is beyond the eyes' reach.
    """

    target: Optional[FollowTarget]  # a plain string names one too: FollowTarget("human")
    dynamic: bool = False

    def visit(self, handler: EffectHandler, at: float) -> Any:
        return handler.follow(self, at)


@dataclass(frozen=True)
class ShutDown(Effect):
    """The script is over for good: the face node shuts down."""

    def visit(self, handler: EffectHandler, at: float) -> Any:
        return handler.exit(self, at)


@dataclass(frozen=True)
class Speech(Effect):
    """Say an utterance: its sound plays from the cue's time, for as long as it lasts."""

    utterance: Utterance

    @property
    def duration(self) -> float:  # type: ignore[override]
        return self.utterance.duration

    def visit(self, handler: EffectHandler, at: float) -> Any:
        return handler.speech(self, at)


EFFECTS = (HeadPan, HeadNod, SetEnabled, SetFollowing, ShutDown, Speech)


class Cue(NamedTuple):
    """An effect at a time (seconds from the start of its timeline)."""

    at: float
    effect: Effect


class EffectHandler(ABC):
    """A consumer of effects: one method per effect type."""

    @abstractmethod
    def head_pan(self, effect: HeadPan, at: float) -> Any: ...

    @abstractmethod
    def head_nod(self, effect: HeadNod, at: float) -> Any: ...

    @abstractmethod
    def set_enabled(self, effect: SetEnabled, at: float) -> Any: ...

    @abstractmethod
    def follow(self, effect: SetFollowing, at: float) -> Any: ...

    @abstractmethod
    def exit(self, effect: ShutDown, at: float) -> Any: ...

    @abstractmethod
    def speech(self, effect: Speech, at: float) -> Any: ...


class RobotStatus(NamedTuple):
    """What the robot would be doing at a time, beyond the screen."""

    enabled: Optional[bool] = None  # None: nothing said so yet
    following: Optional[str] = None  # "human", "face", "left arm", "right arm" or None
    follow_dynamic: bool = False
    nodding_until: float = float("-inf")
    exited: bool = False
    saying: str = ""  # the text being said, until `saying_until`
    saying_until: float = float("-inf")

    def nodding(self, t: float) -> bool:
        return t < self.nodding_until

    def speaking(self, t: float) -> Optional[str]:
        """What is being said at t, or None."""
        return self.saying if t < self.saying_until else None


class StatusFold(EffectHandler):
    """Folds effects, in time order, into the robot's status."""

    def __init__(self, status: Optional[RobotStatus] = None) -> None:
        self.status = status or RobotStatus()

    def head_pan(self, effect: HeadPan, at: float) -> None:
        pass  # the head's angle is part of the face state, not of the status

    def head_nod(self, effect: HeadNod, at: float) -> None:
        self.status = self.status._replace(nodding_until=at + effect.duration)

    def set_enabled(self, effect: SetEnabled, at: float) -> None:
        self.status = self.status._replace(enabled=effect.enabled)

    def follow(self, effect: SetFollowing, at: float) -> None:
        self.status = self.status._replace(following=effect.target, follow_dynamic=effect.dynamic)

    def exit(self, effect: ShutDown, at: float) -> None:
        self.status = self.status._replace(exited=True)

    def speech(self, effect: Speech, at: float) -> None:
        self.status = self.status._replace(saying=effect.utterance.said, saying_until=at + effect.duration)


def fold_status(cues: Sequence[Cue], t: float, start: Optional[RobotStatus] = None) -> RobotStatus:
    """The robot's status at `t`: `start` with every cue (in time order) up to `t` folded in."""
    fold = StatusFold(start)
    for cue in cues:
        if cue.at > t:
            break
        cue.effect.visit(fold, cue.at)
    return fold.status


class EffectWords(EffectHandler):
    """Each effect in words, for `explain`."""

    def head_pan(self, effect: HeadPan, at: float) -> str:
        to = radians_and_degrees(effect.target, "+")
        return f"head pan to {to} over {effect.duration:g} s (speed {effect.speed:.2f} rad/s)"

    def head_nod(self, effect: HeadNod, at: float) -> str:
        return "nod"

    def set_enabled(self, effect: SetEnabled, at: float) -> str:
        return "enable" if effect.enabled else "disable"

    def follow(self, effect: SetFollowing, at: float) -> str:
        return f"follow {effect.target or 'off'}" + (" dynamic" if effect.dynamic else "")

    def exit(self, effect: ShutDown, at: float) -> str:
        return "exit: the face node shuts down"

    def speech(self, effect: Speech, at: float) -> str:
        u = effect.utterance
        if u.recording is not None:
            words = f" text {quoted(u.text)}" if u.text else ""
            return f"say file {quoted(u.recording.name)}{words} ({u.duration:.2f} s, {u.recording.method})"
        return f"say {quoted(u.text)} ({u.duration:.2f} s, voice {u.voice}, {u.rate} words a minute)"
