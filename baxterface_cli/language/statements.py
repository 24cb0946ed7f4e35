"""What each statement is, in one place: its node, its words, how long it takes, how it is said.

Everything else reads this table: the grammar's keywords (`KEYWORDS`, offered in "did you
mean" and reserved from definition names), the bare words that are whole statements
(vocabulary.py), a statement's length (the checker, the compiler, `explain`) and its words in
`explain`. The engine finds each node's compile step by the node's `name`
(`_Compiler.do_<name>`, engine/compiler.py), and fails to import without one.

To add a statement: its dataclass (syntax_tree.py), its grammar rule (grammar/face.lark) and
the builder's method of that rule's name, one `Kind` here, and `do_<name>` in the compiler;
tests/engine/test_statements.py fails until all of them are there.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any, Callable, Dict, Optional, Tuple

from ..core.face_constants import EMOTIONS, TIMING
from ..core.voices import DEFAULT_RATE
from . import syntax_tree as n
from .durations import speech_bound
from .events import in_words as event_words


@dataclass(frozen=True)
class Kind:
    """One statement of the language (see the module's docstring)."""

    node: type  # its syntax-tree class
    # How long it takes on the script's clock, for a statement that is not a block. A move
    # timed with `in T` gives `move` (its length without one) and leaves this out.
    seconds: Optional[Callable[[Any], float]] = None
    words: Tuple[str, ...] = ()  # the grammar's keywords that write it
    bare: str = ""  # the word that alone is the whole statement (`blink`)
    move: Optional[float] = None
    in_words: Callable[[Any], str] = lambda s: type(s).__name__.lower()  # as `explain` lists it

    @property
    def name(self) -> str:
        """`wait_until` for `WaitUntil`: the node's name as the compiler's step is named."""
        return re.sub(r"(?<!^)(?=[A-Z])", "_", self.node.__name__).lower()

    def statement_seconds(self, statement: Any) -> float:
        if self.move is not None:
            return self.move_seconds(statement)
        return 0.0 if self.seconds is None else self.seconds(statement)

    def move_seconds(self, statement: Any) -> float:
        duration = statement.timing.duration
        return self.move if duration is None else duration  # type: ignore[return-value]


def statement_seconds(statement: Any) -> float:
    """How long one simple (not block) statement takes on the script's clock."""
    return kind_of(statement).statement_seconds(statement)


def move_seconds(statement: Any) -> float:
    """A timed move's duration: its own `in T`, or its kind's default."""
    return KINDS[type(statement)].move_seconds(statement)


def describe(statement: Any) -> str:
    """A statement in words, as `explain` lists it: `look 40 -20 in 0.5s`."""
    return kind_of(statement).in_words(statement)


def radians_and_degrees(angle: float, sign: str = "") -> str:
    """An angle as the robot takes it and as people picture it: `0.349 rad (20 deg)`."""
    return f"{angle:{sign}.2f} rad ({math.degrees(angle):{sign}.3g} deg)"


def quoted(text: str) -> str:
    """Text as a script writes it: in double quotes, with \\ and \" escaped."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _timed(s: Any) -> str:
    seconds = statement_seconds(s) if isinstance(s, n.Feeling) else move_seconds(s)
    return f" in {seconds:g}s" + ("" if s.timing.easing == "linear" else f" {s.timing.easing}")


def _lasts(seconds: float) -> Callable[[Any], float]:
    return lambda s: seconds


def _feeling_seconds(s: n.Feeling) -> float:
    # Timed, a morph of that length; else a morph as long as the slowest emotion's lids take.
    if s.timing.duration is not None:
        return s.timing.duration
    return max(EMOTIONS[name].lid_seconds for name, _ in s.weights)


def _feeling_words(s: n.Feeling) -> str:
    variants = list(s.variants) + [None] * (len(s.weights) - len(s.variants))
    blend = " + ".join(
        name.replace(" ", "_")
        + ("" if variant is None else f" variant {variant}")
        + ("" if len(s.weights) == 1 and weight == 1 else f" {weight:g}")
        for (name, weight), variant in zip(s.weights, variants)
    )
    return blend + (_timed(s) if s.timing.duration is not None else "")


def _say_seconds(s: n.Say) -> float:
    if s.file is not None:  # read from its header where the file is read (checker.check_length)
        return 0.0
    return speech_bound(s.text, s.rate or DEFAULT_RATE)


def _say_words(s: n.Say) -> str:
    if s.file is not None:
        text = f" text {quoted(s.text)}" if s.text else ""
        return f"say file {quoted(s.file)}{text}" + (f" language {s.language}" if s.language else "")
    return (
        f"say {quoted(s.text)}"
        + (f" voice {s.voice}" if s.voice else "")
        + (f" rate {s.rate}" if s.rate else "")
    )


def _follow_words(s: n.Follow) -> str:
    if s.target is None:
        return "follow off"
    return f"follow {s.target}" + (" dynamic" if s.dynamic else "")


# In the order their words are offered; the bare words' order is vocabulary.BARE_WORDS's.
_ALL = (
    Kind(
        n.Look,
        words=("look", "dynamic"),
        move=TIMING.look,
        in_words=lambda s: f"{'dynamic look' if s.dynamic else 'look'} {s.x:g} {s.y:g}{_timed(s)}",
    ),
    Kind(
        n.Emotion,
        lambda s: EMOTIONS[s.name].lid_seconds,
        words=("wake",),
        in_words=lambda s: s.name + ("" if s.variant is None else f" variant {s.variant}"),
    ),
    Kind(n.Wait, lambda s: s.duration, words=("wait",), in_words=lambda s: f"wait {s.duration:g}s"),
    Kind(
        n.Wobble,
        words=("wobble",),
        move=TIMING.wobble,
        in_words=lambda s: f"wobble {radians_and_degrees(s.angle)}{_timed(s)}",
    ),
    Kind(n.Skin, words=("skin",), in_words=lambda s: f"skin {s.index}"),
    Kind(n.Mouth, words=("mouth",), in_words=lambda s: f"mouth {s.name}"),
    Kind(n.Brows, words=("brows",), in_words=lambda s: f"brows {s.side + ' ' if s.side else ''}{s.name}"),
    Kind(
        n.Eyelids,
        words=("eyelids",),
        move=TIMING.eyelids,
        in_words=lambda s: f"eyelids {s.openness:g}{_timed(s)}",
    ),
    Kind(n.Follow, words=("follow",), in_words=_follow_words),
    Kind(n.Repeat, words=("repeat",)),
    Kind(n.Together, words=("together",)),
    Kind(n.Define, words=("define",)),
    Kind(n.Use, words=("use",), in_words=lambda s: f"use {quoted(s.path)}"),
    Kind(n.Say, _say_seconds, words=("say",), in_words=_say_words),
    Kind(
        n.Mood,
        words=("mood",),
        move=TIMING.mood,
        in_words=lambda s: f"mood {s.valence:g} {s.arousal:g}{_timed(s)}",
    ),
    Kind(
        n.Wink,
        _lasts(TIMING.wink_close + TIMING.wink_hold + TIMING.wink_open),
        words=("wink",),
        in_words=lambda s: f"wink {s.side}",
    ),
    Kind(
        n.Adjust,
        words=("pupils", "eyes"),  # and a part's own word: `mouth curve 0.5`
        move=TIMING.adjust,
        in_words=lambda s: " ".join(w for w in (s.part, s.side, s.control) if w) + f" {s.value:g}{_timed(s)}",
    ),
    Kind(n.Feeling, _feeling_seconds, words=("variant",), in_words=_feeling_words),
    Kind(n.Blink, _lasts(TIMING.blink_close + TIMING.blink_open), bare="blink"),
    Kind(n.Nod, _lasts(TIMING.nod), bare="nod"),
    Kind(n.Enable, bare="enable"),
    Kind(n.Disable, bare="disable"),
    Kind(n.Exit, bare="exit"),
    Kind(n.Call),  # a `define`d name: the script's own word
)

KINDS: Dict[type, Kind] = {kind.node: kind for kind in _ALL}


def _on_words(s: n.On) -> str:
    policy = "" if s.policy == "drop" else f" {s.policy}"
    return f"on {event_words(s.event)}{policy}" + (f" cooldown {s.cooldown:g}s" if s.cooldown else "")


# The statements the live session runs (engine/live_session.py), not the compiler: they wait on
# the world, raise events, or choose. `Runner._step` in engine/session_program.py tells each apart
# by its node (an `on` is installed by engine/session_handlers.py beforehand); the session compiles
# the statements between them as any script's.
_SESSION = (
    Kind(n.On, words=("on",), in_words=_on_words),
    Kind(n.Forever, words=("forever",), in_words=lambda s: "forever"),
    Kind(
        n.WaitUntil,
        lambda s: 0.0,  # as long as the world takes; a timeout bounds it, not the script's length
        words=("wait", "until"),
        in_words=lambda s: (
            f"wait until {event_words(s.event)}" + ("" if s.timeout is None else f" timeout {s.timeout:g}s")
        ),
    ),
    Kind(n.Signal, words=("signal",), in_words=lambda s: f"signal {s.name}"),
    Kind(n.OneOf, words=("one", "of"), in_words=lambda s: "one of"),
    Kind(n.State, words=("state",), in_words=lambda s: f"state {s.name}"),
    Kind(n.Go, words=("go",), in_words=lambda s: f"go {s.name}"),
    Kind(n.Ask, words=("ask", "else", "nothing"), in_words=lambda s: f"ask {quoted(s.question.text)}"),
)
SESSION_KINDS: Dict[type, Kind] = {kind.node: kind for kind in _SESSION}

# The grammar's keywords (kept equal to grammar/face.lark by a test).
KEYWORDS: Tuple[str, ...] = tuple(dict.fromkeys(word for kind in _ALL + _SESSION for word in kind.words))


def kind_of(statement: Any) -> Kind:
    """The statement's `Kind`, the compiler's or the session's."""
    return KINDS.get(type(statement)) or SESSION_KINDS[type(statement)]
