"""The script's syntax tree: small frozen dataclasses.

Every node carries its source position (line and column, both from 1), but
positions take no part in equality: `look_40_-20_0.5` and
`look 40 -20 in 0.5s` are equal nodes because they mean the same thing.
A timed move's duration and easing are one `Timing` value; a duration left
to the default is None, so a legacy command and its script spelling stay
equal whatever the default is.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any, Dict, Optional, Tuple

from ..core.face_constants import FollowTarget


class Pos:
    """Where a node starts in its source text."""

    __slots__ = ("line", "column")

    def __init__(self, line: int = 0, column: int = 0) -> None:
        self.line = line
        self.column = column

    def __repr__(self) -> str:
        return f"{self.line}:{self.column}"


NOWHERE = Pos()


def _pos() -> Any:
    return field(default=NOWHERE, compare=False, repr=False)


class Statement:
    """A statement of the language; every statement node is one. Blocks hold statements."""

    __slots__ = ()
    pos: Pos


class Block(Statement):
    """A statement that holds others: `repeat`, `together`, `define`."""

    __slots__ = ()
    body: Tuple[Statement, ...]


@dataclass(frozen=True)
class Timing:
    """How a move is timed: `in T` (None leaves the statement's default) and its easing.

    `statements.move_seconds` resolves the default, for the compiler, the
    checker and `explain` alike.
    """

    duration: Optional[float] = None
    easing: str = "linear"


@dataclass(frozen=True)
class Emotion(Statement):
    """An emotion, `sleep` or `wake up`: lids first, then skin, mouth and brows. `variant` is
    the (mouth, brows) pair written (`sad variant 2`), from 1; None picks one at random."""

    name: str
    pos: Pos = _pos()
    variant: Optional[int] = None


@dataclass(frozen=True)
class Feeling(Statement):
    """Emotions at intensities, blended, and perhaps timed: `happy 0.4`,
    `happy 0.6 + confused 0.4`, `sad in 1.5s ease-in-out`. The face morphs to the blend; without
    `in T` the lids move first and the rest follows, as after a bare emotion."""

    weights: Tuple[Tuple[str, float], ...]  # (emotion, weight), as written
    timing: Timing = Timing()
    pos: Pos = _pos()
    # Each emotion's variant as written (from 1), None where none is: then its usual one
    # (face_constants.USUAL_VARIANT). Empty when the script names none.
    variants: Tuple[Optional[int], ...] = ()


@dataclass(frozen=True)
class Mood(Statement):
    """`mood 0.6 -0.2 in 2s`: valence and arousal, each -1..1, as a place on the mood circle."""

    valence: float
    arousal: float
    timing: Timing = Timing()
    pos: Pos = _pos()


@dataclass(frozen=True)
class Wink(Statement):
    """`wink left`: one eye (the robot's left, as `look left`) shuts and opens."""

    side: str
    pos: Pos = _pos()


@dataclass(frozen=True)
class Adjust(Statement):
    """One number of the expression (core/expression.py's CONTROLS): `mouth curve 0.5 in 1s`,
    `brows left angle -0.6`, `eyelids right 0.3`. `side` is "" for both sides."""

    part: str
    control: str
    value: float
    side: str = ""
    timing: Timing = Timing()
    pos: Pos = _pos()


@dataclass(frozen=True)
class Look(Statement):
    """Move the eyes (and with `dynamic`, the head) toward x, y."""

    x: float
    y: float
    timing: Timing = Timing()
    dynamic: bool = False
    pos: Pos = _pos()


@dataclass(frozen=True)
class Blink(Statement):
    pos: Pos = _pos()


@dataclass(frozen=True)
class Wait(Statement):
    duration: float
    pos: Pos = _pos()


@dataclass(frozen=True)
class Wobble(Statement):
    """Pan the head to `angle` radians."""

    angle: float
    timing: Timing = Timing()
    pos: Pos = _pos()


@dataclass(frozen=True)
class Nod(Statement):
    pos: Pos = _pos()


@dataclass(frozen=True)
class Enable(Statement):
    pos: Pos = _pos()


@dataclass(frozen=True)
class Disable(Statement):
    pos: Pos = _pos()


@dataclass(frozen=True)
class Exit(Statement):
    pos: Pos = _pos()


@dataclass(frozen=True)
class Skin(Statement):
    index: int
    pos: Pos = _pos()


@dataclass(frozen=True)
class Mouth(Statement):
    name: str
    pos: Pos = _pos()


@dataclass(frozen=True)
class Brows(Statement):
    """A named pair of brows; with a side, that brow alone takes its shape."""

    name: str
    side: str = ""
    pos: Pos = _pos()


@dataclass(frozen=True)
class Eyelids(Statement):
    """Move the lids to `openness`: 0 closed .. 1 open."""

    openness: float
    timing: Timing = Timing()
    pos: Pos = _pos()


@dataclass(frozen=True)
class Follow(Statement):
    """Start following `target` ("human", "face", "left arm", "right arm"); None stops."""

    target: Optional[FollowTarget]
    dynamic: bool = False
    pos: Pos = _pos()


@dataclass(frozen=True)
class Say(Statement):
    """Speak `text`; None leaves the voice or rate (words a minute) to the default.

    With `file`, play that recording (its path as written) instead, the mouth
    found in its sound; `text` is then its words ("" if not given), to align
    to it, and `language` what it speaks (None: English).
    """

    text: str
    voice: Optional[str] = None
    rate: Optional[int] = None
    pos: Pos = _pos()
    file: Optional[str] = None
    language: Optional[str] = None
    file_pos: Pos = _pos()  # where the file's name is written, for what is wrong with the file


@dataclass(frozen=True)
class Repeat(Block):
    count: int
    body: Tuple[Statement, ...]
    pos: Pos = _pos()


@dataclass(frozen=True)
class Together(Block):
    """Run the children in parallel; lasts as long as the longest."""

    body: Tuple[Statement, ...]
    pos: Pos = _pos()


@dataclass(frozen=True)
class Define(Block):
    name: str
    body: Tuple[Statement, ...]
    pos: Pos = _pos()


@dataclass(frozen=True)
class Call(Statement):
    """Run a `define`d block by name."""

    name: str
    pos: Pos = _pos()


@dataclass(frozen=True)
class Event:
    """What a handler or a `wait until` waits for (language/events.py): `kind` is one of
    events.KINDS ("face seen", "button", "word", ...); `arg` what it names ("ok", "left ok", the
    words "hello there", "left eye", a signal's name; "" for none); `seconds` an `every` or
    `idle`'s period. Not a statement: a part of one."""

    kind: str
    arg: str = ""
    seconds: float = 0.0
    pos: Pos = _pos()


@dataclass(frozen=True)
class On(Block):
    """`on face seen queue cooldown 5s { ... }`: a handler, at the top level only. `policy` is
    what an event does while a handler runs: "drop", "queue" or "interrupt"."""

    event: Event
    body: Tuple[Statement, ...]
    policy: str = "drop"
    cooldown: float = 0.0
    pos: Pos = _pos()


@dataclass(frozen=True)
class Forever(Block):
    """Run the body again and again, for as long as the face runs."""

    body: Tuple[Statement, ...]
    pos: Pos = _pos()


@dataclass(frozen=True)
class OneOf(Block):
    """`one of { a | b; c }`: one of the choices, drawn from the seed's random stream."""

    choices: Tuple[Tuple[Statement, ...], ...]
    pos: Pos = _pos()

    @property
    def body(self) -> Tuple[Statement, ...]:  # type: ignore[override]
        """Every choice's statements, one after another: what the checks look through."""
        return tuple(s for choice in self.choices for s in choice)


@dataclass(frozen=True)
class State(Block):
    """`state asleep { sleep; on button wheel { go awake } }`: its body runs when the face enters
    it, and its own handlers are live only while the face is in it."""

    name: str
    body: Tuple[Statement, ...]
    pos: Pos = _pos()


@dataclass(frozen=True)
class Go(Statement):
    """`go awake`: leave the state the face is in (what it does stops, as an `interrupt` stops it)
    and enter `awake`; `go back` (name "back") returns to the state the face came from."""

    name: str
    pos: Pos = _pos()


@dataclass(frozen=True)
class Answer:
    """One answer of an `ask`: the phrases that choose it, and what the face does then."""

    phrases: Tuple[str, ...]
    body: Tuple[Statement, ...]
    pos: Pos = _pos()


@dataclass(frozen=True)
class Ask(Block):
    """`ask "Shall we play?" { "yes" | "sure" { ... } else { ... } nothing 5s { ... } }`: say the
    question, then listen from when it ends and run the first answer heard; `otherwise` (`else`)
    for speech heard that is none of them, `nothing` (its seconds and body) when nobody spoke."""

    question: Say
    answers: Tuple[Answer, ...]
    otherwise: Optional[Tuple[Statement, ...]] = None
    nothing: Optional[Tuple[float, Tuple[Statement, ...]]] = None
    pos: Pos = _pos()

    @property
    def phrases(self) -> Tuple[str, ...]:
        """Every answer's phrases, in order: what the `ask` listens for."""
        return tuple(p for answer in self.answers for p in answer.phrases)

    @property
    def body(self) -> Tuple[Statement, ...]:  # type: ignore[override]
        """Every branch's statements, one after another: what the checks look through."""
        branches = [a.body for a in self.answers] + [self.otherwise or ()]
        return tuple(s for branch in branches for s in branch) + (self.nothing[1] if self.nothing else ())


@dataclass(frozen=True)
class WaitUntil(Statement):
    """`wait until face seen timeout 5s`: hold here until the event comes (or the timeout,
    None for none, passes)."""

    event: Event
    timeout: Optional[float] = None
    pos: Pos = _pos()


@dataclass(frozen=True)
class Signal(Statement):
    """`signal poke`: raise the event `signal poke`, for the handlers and waits on it."""

    name: str
    pos: Pos = _pos()


@dataclass(frozen=True)
class Use(Statement):
    """`use "my-gestures.face"`: another file's `define`s, read when the script is parsed."""

    path: str
    pos: Pos = _pos()


@dataclass(frozen=True)
class Script:
    body: Tuple[Statement, ...]
    filename: str = field(default="<script>", compare=False)
    warnings: Tuple[Any, ...] = field(default=(), compare=False, repr=False)
    source: str = field(default="", compare=False, repr=False)
    # Written wholly in the old node's commands (`happy`, `look_40_-20_0.5`):
    # played the way the old node played them, with hard cuts.
    legacy: bool = field(default=False, compare=False)
    # Warnings beyond the first few (see `Limits.max_shown`): only counted.
    more_warnings: int = field(default=0, compare=False, repr=False)

    @property
    def definitions(self) -> Dict[str, Define]:
        return {s.name: s for s in self.body if isinstance(s, Define)}

    @property
    def states(self) -> Dict[str, State]:
        return {s.name: s for s in self.body if isinstance(s, State)}


BLOCKS = tuple(
    Block.__subclasses__()
)  # Repeat, Together, Define, On, Forever, OneOf: every node that holds others


def to_json(node: Any) -> Any:
    """A JSON-ready view of a node: `type`, its fields, `line` and `column`."""
    if isinstance(node, tuple):
        return [to_json(child) for child in node]
    if not dataclasses.is_dataclass(node):
        return node
    out: Dict[str, Any] = {"type": type(node).__name__}
    for f in dataclasses.fields(node):
        if f.name in ("pos", "file_pos", "warnings", "source", "legacy", "more_warnings"):
            continue
        if f.name in ("variant", "variants") and not getattr(node, f.name):
            continue  # only where written, so that scripts without variants print as they always have
        out[f.name] = to_json(getattr(node, f.name))
    pos = getattr(node, "pos", None)
    if pos is not None:
        out["line"] = pos.line
        out["column"] = pos.column
    return out
