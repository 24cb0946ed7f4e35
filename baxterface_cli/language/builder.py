"""The grammar, and the builder lark calls as it reduces: text to syntax-tree dataclasses in one pass.

Numbers are converted with their units and names and ranges checked where
the tokens are, so each diagnostic points at the exact column.
"""

from __future__ import annotations

import math
import re
import sys
import threading
from functools import lru_cache
from typing import Any, Callable, Dict, List, Optional, Tuple

from lark import Lark, Token, Transformer

from ..core.easing import EASINGS
from ..core.face_constants import (
    BROWS,
    DIRECTIONS,
    HEAD_PAN_LIMIT,
    LIMITS,
    MOUTHS,
    SKINS,
    UNITS,
    FollowTarget,
)
from ..core.geometry import clamp_to_ellipse, inside_ellipse
from ..core.user_cache import made_cache_folder
from ..resources import resource
from . import syntax_tree as n
from .diagnostics import Diagnostic, Hints, one_of
from .expression_rules import ExpressionRules, _is_name
from .reaction_rules import ReactionRules
from .speech_rules import SpeechRules
from .vocabulary import BARE_WORDS, LEGACY_USAGE, LEGACY_WORDS

_NUMBER = re.compile(r"([-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+))(.*)", re.S)
_LEGACY_NUMBER = re.compile(r"_([-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+))")


@lru_cache(maxsize=1)
def grammar() -> Lark:
    """The one grammar, built once, giving lark trees (for tools and tests)."""
    return _lark()


def _lark(**options: Any) -> Lark:
    """The grammar's LALR parser; lark keeps its tables in the user's cache folder, fingerprinted
    (building them takes a seventh of a second, most of a `check`; loading them, milliseconds)."""
    folder = made_cache_folder("grammar")
    cache = str(folder / f"face-{sys.version_info[0]}.{sys.version_info[1]}.lark") if folder else False
    return Lark(_grammar_text(), parser="lalr", maybe_placeholders=False, cache=cache, **options)


@lru_cache(maxsize=1)
def _grammar_text() -> str:
    return resource("grammar/face.lark").read_text(encoding="utf-8")


class ThreadParser:
    """A thread's parser, with the builder lark calls as it reduces.

    Building while parsing skips making and walking a tree: a third of the
    time of a big script. The builder holds one parse's state, so each
    thread has its own.
    """

    def __init__(self) -> None:
        self.builder = _Builder()
        self.lark = _lark(transformer=self.builder)


_UNIT_WORDS = frozenset(unit for units in UNITS.values() for unit in units if unit)
_NUMBER_BEFORE = re.compile(r"(?<![\w.])([-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+))[ \t]+$")


def spaced_unit(text: str, at: int, word: str) -> str:
    """For a unit written apart from its number (`0.5 s`), how to write it; or ''."""
    if word.lower() not in _UNIT_WORDS:
        return ""
    m = _NUMBER_BEFORE.search(text, max(0, at - 40), at)
    if m is None:
        return ""
    number = m.group(1)
    return f"in '{number} {word}': write the unit straight after the number, as in '{number}{word}'"


# -- tree -> AST ---------------------------------------------------------


class _Builder(ExpressionRules, SpeechRules, ReactionRules, Transformer):
    """Builds AST nodes, recording a diagnostic for each bad value it meets."""

    def begin(self, text: str, line: Callable[[int], int]) -> None:
        """Start on a new text (lines as the parser sees them, mapped by `line`)."""
        self.diagnostics: List[Diagnostic] = []
        self.text = text
        self.line = line  # the user's line for a line of `text`
        self.hints = Hints()
        # Statements spelled as the old node's commands, by id; holding them
        # keeps an id from being reused by a statement built later.
        self._legacy: Dict[int, Any] = {}

    def legacy_spelling(self, body: Tuple[Any, ...]) -> bool:
        """Is every top-level statement one of the old node's commands, as it typed them?"""
        return bool(body) and all(id(s) in self._legacy for s in body)

    def _old(self, node: Any) -> Any:
        self._legacy[id(node)] = node
        return node

    # -- helpers

    def _pos(self, meta_or_token: Any) -> n.Pos:
        return n.Pos(self.line(meta_or_token.line), meta_or_token.column)

    def _error(self, at: Any, message: str, column_offset: int = 0) -> None:
        self.diagnostics.append(Diagnostic(at.line, at.column + column_offset, message))

    def _warn(self, at: Any, message: str) -> None:
        self.diagnostics.append(Diagnostic(at.line, at.column, message, severity="warning"))

    def _number(self, token: Token, meaning: str, what: str) -> Optional[float]:
        """The token's value in the base unit of `meaning`; None after an error."""
        number, unit = _NUMBER.fullmatch(str(token)).groups()  # type: ignore[union-attr]
        scale = UNITS[meaning].get(unit.lower())
        if scale is None:
            allowed = [u for u in UNITS[meaning] if u]
            usage = f"; {what} takes {one_of(allowed)}" if allowed else f"; {what} takes a plain number"
            hint = self.hints(unit, allowed) if allowed else ""
            self._error(token, f"unknown unit '{unit}' for {what}{hint or usage}", len(number))
            return None
        value = float(number) * scale
        if not math.isfinite(value):
            self._error(token, f"{what} is too large")
            return None
        return value

    def _seconds(self, token: Token, what: str) -> float:
        value = self._number(token, "seconds", what)
        if value is not None and value < 0:
            self._error(token, f"{what} cannot be negative")
        return value or 0.0

    def _whole(self, token: Token, meaning: str, what: str, low: int, high: int) -> int:
        value = self._number(token, meaning, what)
        if value is None:
            return low
        if value != int(value) or not low <= value <= high:
            self._error(token, f"{what} must be a whole number from {low} to {high}, not {token}")
            return low
        return int(value)

    def _point(self, tokens: List[Token]) -> Tuple[float, float]:
        x, y = (self._number(t, "pixels", "an eye coordinate") for t in tokens)
        return (x or 0.0, y or 0.0)

    def _angle(self, token: Token, at: Any) -> float:
        angle = self._number(token, "radians", "a head angle") or 0.0
        if abs(angle) > HEAD_PAN_LIMIT:
            self._warn(at, f"head angle {angle:g} rad is beyond +-{HEAD_PAN_LIMIT}; it will be clamped")
        return angle

    def _known(self, token: Token, choices: Any, what: str) -> str:
        name = str(token).lower()
        if name not in choices:
            hint = self.hints(name, choices) or f"; use {one_of(choices)}"
            self._error(token, f"unknown {what} '{token}'{hint}")
        return name

    def _eye_target(self, at: Any, x: float, y: float) -> None:
        if not inside_ellipse(x, y):
            cx, cy = clamp_to_ellipse(x, y)
            self._warn(
                at,
                f"eye target ({x:g}, {y:g}) is outside the eye ellipse (80 x 120); "
                f"it will be clamped to ({cx:.0f}, {cy:.0f})",
            )

    # -- statements
    # Each statement's first child is its keyword's token (or its one token):
    # where the statement is, without lark's costly position propagation.

    def start(self, children: List[Any]) -> Tuple[Any, ...]:
        return tuple(children)

    block = start

    def word(self, children: List[Token]) -> Any:
        (token,) = children
        name = str(token).lower()
        factory = BARE_WORDS.get(name)
        node = factory(pos=self._pos(token)) if factory is not None else n.Call(name, pos=self._pos(token))
        return self._old(node) if name in LEGACY_WORDS else node

    def wake_up(self, children: List[Token]) -> n.Emotion:
        return n.Emotion("wake up", pos=self._pos(children[0]))

    def legacy(self, children: List[Token]) -> Any:
        return self._old(self._legacy_command(children))

    def _legacy_command(self, children: List[Token]) -> Any:
        (token,) = children
        text = str(token).lower()
        numbers = list(_LEGACY_NUMBER.finditer(text))
        command = text[: numbers[0].start()]
        counts, usage = LEGACY_USAGE[command]
        pos = self._pos(token)
        if len(numbers) not in counts:
            self._error(token, f"'{token}' takes {' or '.join(map(str, counts))} numbers: {usage}")
            return n.Wait(0.0, pos=pos)  # a stand-in, so no second error names it
        # Each number becomes a token of its own so a diagnostic points at it.
        args = [
            Token("QUANTITY", m.group(1), line=token.line, column=token.column + m.start(1)) for m in numbers
        ]
        if command in ("look", "dynamic_look"):
            x, y = self._point(args[:2])
            duration = self._seconds(args[2], "a duration") if len(args) == 3 else None
            self._eye_target(token, x, y)
            return n.Look(x, y, n.Timing(duration), dynamic=command == "dynamic_look", pos=pos)
        if command == "wobble":
            return n.Wobble(self._angle(args[0], token), pos=pos)
        return n.Skin(self._skin(args[0]), pos=pos)

    def look(self, children: List[Any]) -> n.Look:
        at = children[0]
        dynamic = at.type == "DYNAMIC"
        children = children[2:] if dynamic else children[1:]
        (x, y), rest = children[0], children[1:]
        if not isinstance(children[0], _Direction):
            self._eye_target(at, x, y)
        return n.Look(x, y, rest[0] if rest else n.Timing(), dynamic, pos=self._pos(at))

    def point(self, children: List[Token]) -> Tuple[float, float]:
        return self._point(children)

    def direction(self, children: List[Token]) -> Tuple[float, float]:
        (token,) = children
        name = self._known(token, DIRECTIONS, "direction")
        return _Direction(DIRECTIONS.get(name, (0.0, 0.0)))

    def timing(self, children: List[Any]) -> n.Timing:
        duration = None
        if isinstance(children[0], Token):
            duration = self._seconds(children[0], "a duration")
            children = children[1:]
        return n.Timing(duration, children[0] if children else "linear")

    morph = timing  # `sad in 1.5s ease-in-out`: the same words as a move's timing

    def easing(self, children: List[Token]) -> str:
        (token,) = children
        spaced = spaced_unit(self.text, token.start_pos, str(token))
        if spaced:
            self._error(token, f"unknown easing '{token}' {spaced}")
            return "linear"
        return self._known(token, EASINGS, "easing")

    def wait(self, children: List[Token]) -> n.Wait:
        at, seconds = children
        return n.Wait(self._seconds(seconds, "a wait"), pos=self._pos(at))

    def wobble(self, children: List[Any]) -> n.Wobble:
        at, angle_token, *rest = children
        angle = self._angle(angle_token, at)
        return n.Wobble(angle, rest[0] if rest else n.Timing(), pos=self._pos(at))

    def skin(self, children: List[Any]) -> Any:
        if len(children) == 2:
            at, index = children
            return n.Skin(self._skin(index), pos=self._pos(at))
        return self._adjust("skin", children)

    def _skin(self, token: Token) -> int:
        return self._whole(token, "index", "a skin", min(SKINS), max(SKINS))

    def mouth(self, children: List[Any]) -> Any:
        if len(children) == 2:
            at, name = children
            named = "smile" if self._wants_number("mouth", name) else self._known(name, MOUTHS, "mouth")
            return n.Mouth(named, pos=self._pos(at))
        return self._adjust("mouth", children)

    def brows(self, children: List[Any]) -> Any:
        at, *rest = children
        if len(rest) > 1 and _is_name(rest[0]) and _is_name(rest[1]):
            self._mistyped_side("brows", rest)
        side = rest.pop(0) if isinstance(rest[0], str) and not isinstance(rest[0], Token) else ""
        if len(rest) == 1:
            named = "normal" if self._wants_number("brows", rest[0]) else self._known(rest[0], BROWS, "brows")
            return n.Brows(named, side, pos=self._pos(at))
        return self._adjust("brows", [at, *rest], side)

    def eyelids(self, children: List[Any]) -> Any:
        at, *rest = children
        if len(rest) > 2 and _is_name(rest[0]) and _is_name(rest[1]):
            self._mistyped_side("eyelids", rest)
        side = rest.pop(0) if not isinstance(rest[0], Token) else ""
        if len(rest) > 1 and isinstance(rest[1], Token):  # a control's name: `eyelids left angle 0.5`
            return self._adjust("eyelids", [at, *rest], side)
        if side:  # one eye's share of the lids' openness
            return self._adjust("eyelids", [at, None, *rest], side)
        amount, *rest = rest
        openness = self._number(amount, "openness", "eyelid openness")
        if openness is None:
            openness = 1.0
        elif not 0.0 <= openness <= 1.0:
            self._error(amount, f"eyelid openness must be from 0 (closed) to 1 (open), not {amount}")
        return n.Eyelids(openness, rest[0] if rest else n.Timing(), pos=self._pos(at))

    def follow(self, children: List[Any]) -> n.Follow:
        at, target, *rest = children
        dynamic = bool(rest)
        if target is None and dynamic:
            self._error(rest[0], "'follow off' takes no 'dynamic'")
        return n.Follow(target, dynamic, pos=self._pos(at))

    def follow_target(self, children: List[Token]) -> Optional[FollowTarget]:
        return _FOLLOW_TARGETS[children[0].type]

    def repeat(self, children: List[Any]) -> n.Repeat:
        at, count_token, body = children
        count = self._whole(count_token, "count", "a repeat count", 1, LIMITS.max_repeat)
        return n.Repeat(count, self._body(at, "repeat", body), pos=self._pos(at))

    def together(self, children: List[Any]) -> n.Together:
        at, body = children
        return n.Together(self._body(at, "together", body), pos=self._pos(at))

    def define(self, children: List[Any]) -> n.Define:
        at, name, body = children
        return n.Define(str(name).lower(), self._body(at, "define", body), pos=self._pos(at))

    def use(self, children: List[Token]) -> n.Use:
        at, string = children
        path = self._string(string)
        if path is not None and not path.strip():
            self._error(string, "'use' needs a file name: use \"my-gestures.face\"")
        return n.Use(path or "", pos=self._pos(at))

    def _body(self, at: Token, what: str, body: Tuple[Any, ...]) -> Tuple[Any, ...]:
        if not body:
            self._error(at, f"empty block: '{what}' needs at least one statement")
        return body


_FOLLOW_TARGETS = {
    "HUMAN": FollowTarget.HUMAN,
    "FACE": FollowTarget.FACE,
    "LEFT": FollowTarget.LEFT_ARM,
    "RIGHT": FollowTarget.RIGHT_ARM,
    "OFF": None,
}


class _Direction(tuple):
    """A named direction's point, marked so that it is never warned about."""


_LOCAL = threading.local()


def thread_parser() -> ThreadParser:
    """This thread's parser, made on first use."""
    parser = getattr(_LOCAL, "parser", None)
    if parser is None:
        parser = _LOCAL.parser = ThreadParser()
    return parser
