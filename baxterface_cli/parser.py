"""Text -> syntax tree -> AST, with every local check done on the way.

The grammar (grammar/face.lark) gives the shape; `_Builder` turns lark's tree
into `nodes` dataclasses, converting numbers with their units and checking
names and ranges where the tokens are, so each diagnostic points at the exact
column. Whole-script checks (definitions, recursion, length) are in
`checker`.
"""

from __future__ import annotations

import math
import re
from functools import lru_cache
from pathlib import Path
from typing import Any, List, Optional, Tuple, Union

from lark import Lark, Token, Transformer, v_args
from lark.exceptions import UnexpectedCharacters, UnexpectedInput, UnexpectedToken, VisitError
from lark.lexer import PatternStr

from . import nodes as n
from .checker import check
from .diagnostics import Diagnostic, ScriptError, did_you_mean, one_of
from .easing import EASINGS
from .geometry import clamp_to_ellipse, inside_ellipse
from .resources import resource
from .tables import BROWS, DIRECTIONS, HEAD_PAN_LIMIT, LIMITS, MOUTHS, SKINS, UNITS
from .vocabulary import BARE_WORDS, LEGACY_USAGE, LEGACY_WORDS

_NUMBER = re.compile(r"([-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+))(.*)", re.S)
_LEGACY_NUMBER = re.compile(r"_([-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+))")


@lru_cache(maxsize=1)
def grammar() -> Lark:
    """The one grammar, built once."""
    text = resource("grammar/face.lark").read_text(encoding="utf-8")
    return Lark(text, parser="lalr", propagate_positions=True, maybe_placeholders=False)


def parse(text: str, filename: str = "<script>") -> n.Script:
    """Parse and check a script; raise one ScriptError carrying every diagnostic."""
    diagnostics: List[Diagnostic] = []
    body: Tuple[Any, ...] = ()
    legacy = False
    if len(text) > LIMITS.max_bytes:
        diagnostics.append(
            Diagnostic(0, 0, f"script is too large ({len(text)} characters; the limit is {LIMITS.max_bytes})")
        )
    else:
        diagnostics.extend(_check_braces(text))
    if not diagnostics:
        tree = _parse_recovering(text, diagnostics)
        if tree is not None:
            try:
                body = _Builder(diagnostics).transform(tree)
                legacy = _legacy_spelling(tree)
            except VisitError as e:  # a bug of ours, not the user's: let it show
                raise e.orig_exc from e
            diagnostics.extend(check(body))
    diagnostics.sort(key=lambda d: (d.line or math.inf, d.column))
    if any(d.severity == "error" for d in diagnostics):
        raise ScriptError(diagnostics, filename, text)
    return n.Script(body, filename, tuple(diagnostics), text, legacy)


def _legacy_spelling(tree: Any) -> bool:
    """Is every statement one of the old node's commands, as it typed them?"""
    statements = tree.children
    return bool(statements) and all(
        s.data == "legacy" or (s.data == "word" and str(s.children[0]).lower() in LEGACY_WORDS)
        for s in statements
    )


def parse_file(path: Union[str, Path, Any], display_name: Optional[str] = None) -> n.Script:
    """Read a script file or binary stream (UTF-8, bounded in size) and parse it."""
    name = display_name or str(path)
    text = decode(read_bounded(path, name), name)
    return parse(text, name)


def read_bounded(source: Union[str, Path, Any], name: str) -> bytes:
    """Read at most the size limit (and one byte more, to notice) from a path or a binary stream."""
    try:
        if isinstance(source, (str, Path)):
            with open(source, "rb") as f:
                data = f.read(LIMITS.max_bytes + 1)
        else:
            data = source.read(LIMITS.max_bytes + 1)
    except OSError as e:
        reason = e.strerror or str(e)
        raise ScriptError([Diagnostic(0, 0, f"cannot read: {reason}")], name) from None
    if len(data) > LIMITS.max_bytes:
        raise ScriptError(
            [Diagnostic(0, 0, f"script is too large (more than {LIMITS.max_bytes} bytes)")], name
        )
    return data


def decode(data: bytes, name: str) -> str:
    """UTF-8 text, or a diagnostic at the first byte that is not."""
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        column = e.start - (data.rfind(b"\n", 0, e.start) + 1) + 1
        bad = data[e.start]
        message = f"not a UTF-8 text file (byte 0x{bad:02x})"
        raise ScriptError([Diagnostic(line, column, message, kind="syntax")], name) from None


# -- syntax errors ---------------------------------------------------------

_MAX_SYNTAX_ERRORS = 10
_RECOVERY_BUDGET = 512 * 1024  # characters re-parsed in all, so recovery stays fast


def _parse_recovering(text: str, diagnostics: List[Diagnostic]) -> Any:
    """Parse; after a syntax error, blank the broken statement and go on.

    Blanking keeps every other character where it was, so later diagnostics
    point at the user's own text. Returns the tree of the repaired text (its
    meaning is only used to find more errors), or None if recovery gave up.
    """
    budget = _RECOVERY_BUDGET
    while True:
        try:
            tree = grammar().parse(text)
        except UnexpectedInput as e:
            diagnostics.append(_syntax_diagnostic(e, text))
            budget -= len(text)
            repaired = _blank_statement(text, e)
            errors = sum(d.kind == "syntax" for d in diagnostics)
            if errors >= _MAX_SYNTAX_ERRORS:
                diagnostics.append(Diagnostic(0, 0, f"stopped after {errors} syntax errors", kind="syntax"))
                return None
            if repaired is None or budget < len(text):
                return None
            text = repaired
        else:
            return tree


_SEPARATORS = ";\n{}"


def _blank_statement(text: str, e: UnexpectedInput) -> Optional[str]:
    """`text` with the statement around the error blanked out, or None."""
    at = e.pos_in_stream if isinstance(e, UnexpectedCharacters) else getattr(e.token, "start_pos", None)
    if at is None or at >= len(text):  # the end of the text: nothing after it to save
        return None
    start = max(text.rfind(c, 0, at) for c in _SEPARATORS) + 1
    if start > at:
        start = at
    end = at
    while end < len(text) and text[end] not in _SEPARATORS:
        end += 1
    if end < len(text) and text[end] == "{":  # a broken block header: drop its block too
        end = _matching_brace(text, end)
    region = text[start:end]
    if not region.strip():
        return None
    filler = "".join(c if c in "\r\n" else " " for c in region)
    # A placeholder statement keeps a block that held only this one from
    # being reported as empty as well.
    if len(filler) >= 5 and "\n" not in filler[:5]:
        filler = "blink" + filler[5:]
    return text[:start] + filler + text[end:]


def _matching_brace(text: str, opening: int) -> int:
    depth = 0
    for i in range(opening, len(text)):
        if text[i] == "{":
            depth += 1
        elif text[i] == "}":
            depth -= 1
            if depth == 0:
                return i + 1
    return len(text)


def _check_braces(text: str) -> List[Diagnostic]:
    """Unclosed or too deeply nested blocks, found before the parser runs."""
    opened: List[Tuple[int, int]] = []
    line, column, in_comment = 1, 0, False
    for char in text:
        column += 1
        if char == "\n":
            line, column, in_comment = line + 1, 0, False
        elif in_comment:
            continue
        elif char == "#":
            in_comment = True
        elif char == "{":
            opened.append((line, column))
            if len(opened) > LIMITS.max_depth:
                message = f"blocks nest too deeply (the limit is {LIMITS.max_depth} levels)"
                return [Diagnostic(line, column, message, kind="syntax")]
        elif char == "}" and opened:
            opened.pop()
    if opened:
        line, column = opened[-1]
        return [Diagnostic(line, column, "this '{' is never closed", kind="syntax")]
    return []


_TERMINAL_NAMES = {
    "QUANTITY": "a number",
    "NAME": "a name",
    "_NL": "a new line",
    "$END": "end of script",
}


def _describe_terminal(name: str) -> str:
    if name in _TERMINAL_NAMES:
        return _TERMINAL_NAMES[name]
    for terminal in grammar().terminals:
        if terminal.name == name and isinstance(terminal.pattern, PatternStr):
            return f"'{terminal.pattern.value.lower()}'"
    return name.lower().replace("_", " ")


def _expected(names: Any) -> Tuple[str, List[str]]:
    """A phrase for what the parser wanted, and the keywords among it."""
    names = set(names)
    if "LEGACY" in names:  # the start of a statement: too many to list
        rest = sorted(_describe_terminal(x) for x in names if x in ("RBRACE", "$END"))
        return " or ".join(["a command"] + rest), []
    described = sorted(_describe_terminal(x) for x in names)
    keywords = [d.strip("'") for d in described if d.startswith("'")]
    if len(described) > 1:
        return ", ".join(described[:-1]) + " or " + described[-1], keywords
    return described[0] if described else "something else", keywords


def _syntax_diagnostic(e: UnexpectedInput, text: str) -> Diagnostic:
    line, column = e.line, e.column
    if isinstance(e, UnexpectedCharacters):
        char = text[e.pos_in_stream]
        shown = repr(char) if not char.isprintable() or char in "'\"" else f"'{char}'"
        expected, keywords = _expected(e.allowed or ())
        message = f"unexpected character {shown}; expected {expected}"
    elif isinstance(e, UnexpectedToken):
        token = e.token
        expected, keywords = _expected(e.expected)
        if token.type == "$END":
            line, column = _end_of(text)
            found = "end of script"
        elif token.type == "_NL":
            found = "end of line"
        else:
            found = f"'{token.value}'"
        message = f"unexpected {found}; expected {expected}"
        if token.type not in ("$END", "_NL") and keywords:
            message += did_you_mean(str(token.value), keywords)
    else:  # pragma: no cover - lark's LALR parser raises only the two above
        message = "cannot parse this"
    if not isinstance(line, int) or line < 1:
        line, column = _end_of(text)
    return Diagnostic(line, column, message, kind="syntax")


def _end_of(text: str) -> Tuple[int, int]:
    """Just after the last thing written: where a missing piece belongs."""
    body = text.rstrip()
    line = body.count("\n") + 1
    return line, len(body) - (body.rfind("\n") + 1) + 1


# -- tree -> AST ---------------------------------------------------------


def _pos(meta_or_token: Any) -> n.Pos:
    return n.Pos(meta_or_token.line, meta_or_token.column)


@v_args(meta=True)
class _Builder(Transformer):
    """Builds AST nodes, recording a diagnostic for each bad value it meets."""

    def __init__(self, diagnostics: List[Diagnostic]) -> None:
        super().__init__()
        self.diagnostics = diagnostics

    # -- helpers

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
            hint = did_you_mean(unit, allowed) if allowed else ""
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
            hint = did_you_mean(name, choices) or f"; use {one_of(choices)}"
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

    def start(self, meta: Any, children: List[Any]) -> Tuple[Any, ...]:
        return tuple(children)

    def block(self, meta: Any, children: List[Any]) -> Tuple[Any, ...]:
        return tuple(children)

    def word(self, meta: Any, children: List[Token]) -> Any:
        (token,) = children
        name = str(token).lower()
        factory = BARE_WORDS.get(name)
        if factory is not None:
            return factory(pos=_pos(meta))
        return n.Call(name, pos=_pos(meta))

    def wake_up(self, meta: Any, children: List[Any]) -> n.Emotion:
        return n.Emotion("wake up", pos=_pos(meta))

    def legacy(self, meta: Any, children: List[Token]) -> Any:
        (token,) = children
        text = str(token).lower()
        numbers = list(_LEGACY_NUMBER.finditer(text))
        command = text[: numbers[0].start()]
        counts, usage = LEGACY_USAGE[command]
        pos = _pos(meta)
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

    def look(self, meta: Any, children: List[Any]) -> n.Look:
        dynamic = isinstance(children[0], Token) and children[0].type == "DYNAMIC"
        if dynamic:
            children = children[1:]
        (x, y), rest = children[0], children[1:]
        if not isinstance(children[0], _Direction):
            self._eye_target(meta, x, y)
        return n.Look(x, y, rest[0] if rest else n.Timing(), dynamic, pos=_pos(meta))

    def point(self, meta: Any, children: List[Token]) -> Tuple[float, float]:
        return self._point(children)

    def direction(self, meta: Any, children: List[Token]) -> Tuple[float, float]:
        (token,) = children
        name = self._known(token, DIRECTIONS, "direction")
        return _Direction(DIRECTIONS.get(name, (0.0, 0.0)))

    def timing(self, meta: Any, children: List[Any]) -> n.Timing:
        duration = None
        if isinstance(children[0], Token):
            duration = self._seconds(children[0], "a duration")
            children = children[1:]
        return n.Timing(duration, children[0] if children else "linear")

    def easing(self, meta: Any, children: List[Token]) -> str:
        return self._known(children[0], EASINGS, "easing")

    def wait(self, meta: Any, children: List[Token]) -> n.Wait:
        return n.Wait(self._seconds(children[0], "a wait"), pos=_pos(meta))

    def wobble(self, meta: Any, children: List[Any]) -> n.Wobble:
        angle = self._angle(children[0], meta)
        return n.Wobble(angle, children[1] if len(children) > 1 else n.Timing(), pos=_pos(meta))

    def skin(self, meta: Any, children: List[Token]) -> n.Skin:
        return n.Skin(self._skin(children[0]), pos=_pos(meta))

    def _skin(self, token: Token) -> int:
        return self._whole(token, "index", "a skin", min(SKINS), max(SKINS))

    def mouth(self, meta: Any, children: List[Token]) -> n.Mouth:
        return n.Mouth(self._known(children[0], MOUTHS, "mouth"), pos=_pos(meta))

    def brows(self, meta: Any, children: List[Token]) -> n.Brows:
        return n.Brows(self._known(children[0], BROWS, "brows"), pos=_pos(meta))

    def eyelids(self, meta: Any, children: List[Any]) -> n.Eyelids:
        openness = self._number(children[0], "openness", "eyelid openness")
        if openness is None:
            openness = 1.0
        elif not 0.0 <= openness <= 1.0:
            self._error(
                children[0], f"eyelid openness must be from 0 (closed) to 1 (open), not {children[0]}"
            )
        return n.Eyelids(openness, children[1] if len(children) > 1 else n.Timing(), pos=_pos(meta))

    def follow(self, meta: Any, children: List[Any]) -> n.Follow:
        target = children[0]
        dynamic = len(children) > 1
        if target is None and dynamic:
            self._error(children[1], "'follow off' takes no 'dynamic'")
        return n.Follow(target, dynamic, pos=_pos(meta))

    def follow_target(self, meta: Any, children: List[Token]) -> Optional[str]:
        kind = children[0].type
        return {"HUMAN": "human", "OFF": None, "LEFT": "left arm", "RIGHT": "right arm"}[kind]

    def repeat(self, meta: Any, children: List[Any]) -> n.Repeat:
        count = self._whole(children[0], "count", "a repeat count", 1, LIMITS.max_repeat)
        return n.Repeat(count, self._body(meta, "repeat", children[1]), pos=_pos(meta))

    def together(self, meta: Any, children: List[Any]) -> n.Together:
        return n.Together(self._body(meta, "together", children[0]), pos=_pos(meta))

    def define(self, meta: Any, children: List[Any]) -> n.Define:
        name, body = children
        return n.Define(str(name).lower(), self._body(meta, "define", body), pos=_pos(meta))

    def _body(self, meta: Any, what: str, body: Tuple[Any, ...]) -> Tuple[Any, ...]:
        if not body:
            self._error(meta, f"empty block: '{what}' needs at least one statement")
        return body


class _Direction(tuple):
    """A named direction's point, marked so that it is never warned about."""
