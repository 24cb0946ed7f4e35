"""Text -> syntax tree -> AST, with every local check done on the way.

The grammar (grammar/face.lark) gives the shape; `_Builder` turns each rule
lark reduces into `nodes` dataclasses as it parses (no tree is built first),
converting numbers with their units and checking names and ranges where the
tokens are, so each diagnostic points at the exact column. Whole-script
checks (definitions, recursion, length) are in `checker`.
"""

from __future__ import annotations

import bisect
import itertools
import math
import re
import threading
from functools import lru_cache
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Set, Tuple, Union

from lark import Lark, Token, Transformer
from lark.exceptions import UnexpectedCharacters, UnexpectedInput, UnexpectedToken, VisitError
from lark.lexer import PatternStr

from . import nodes as n
from .checker import check
from .diagnostics import Diagnostic, Hints, ScriptError, did_you_mean, keep_first, one_of
from .easing import EASINGS
from .geometry import clamp_to_ellipse, inside_ellipse
from .resources import resource
from .tables import BROWS, DIRECTIONS, HEAD_PAN_LIMIT, LIMITS, MOUTHS, SKINS, UNITS
from .vocabulary import BARE_WORDS, LEGACY_USAGE, LEGACY_WORDS
from .voices import RATES, known_voice, voice_names

_ESCAPE = re.compile(r"\\(.)", re.S)
_NUMBER = re.compile(r"([-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+))(.*)", re.S)
_LEGACY_NUMBER = re.compile(r"_([-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+))")


@lru_cache(maxsize=1)
def grammar() -> Lark:
    """The one grammar, built once, giving lark trees (for tools and tests)."""
    return Lark(_grammar_text(), parser="lalr", maybe_placeholders=False)


@lru_cache(maxsize=1)
def _grammar_text() -> str:
    return resource("grammar/face.lark").read_text(encoding="utf-8")


class _Parser:
    """A thread's parser, with the builder lark calls as it reduces.

    Building while parsing skips making and walking a tree: a third of the
    time of a big script. The builder holds one parse's state, so each
    thread has its own.
    """

    def __init__(self) -> None:
        self.builder = _Builder()
        self.lark = Lark(_grammar_text(), parser="lalr", maybe_placeholders=False, transformer=self.builder)


def parse(text: str, filename: str = "<script>") -> n.Script:
    """Parse and check a script; raise one ScriptError carrying the diagnostics.

    At most `LIMITS.max_shown` diagnostics are kept (errors first); the rest
    are counted, so a flood of problems stays cheap to report.
    """
    diagnostics: List[Diagnostic] = []
    body: Tuple[Any, ...] = ()
    legacy = False
    size = _size(text)
    if size > LIMITS.max_bytes:
        message = f"script is too large ({size} bytes; the limit is {LIMITS.max_bytes})"
        diagnostics.append(Diagnostic(0, 0, message))
    else:
        too_long = _past_piece_limit(text)
        if too_long is not None:
            diagnostics.append(too_long)
        else:
            body, legacy = _build(text, diagnostics)
    shown, more_errors, more_warnings = keep_first(diagnostics)
    if more_errors or any(d.severity == "error" for d in shown):
        raise ScriptError(shown, filename, text, more_errors, more_warnings)
    return n.Script(body, filename, tuple(shown), text, legacy, more_warnings)


def _size(text: str) -> int:
    """The text's size in UTF-8 bytes, encoding it only when that could matter."""
    if len(text) * 4 <= LIMITS.max_bytes:  # no character takes more than 4 bytes
        return len(text)
    return len(text.encode("utf-8", "surrogatepass"))


_PIECE = re.compile(r"[^\s;{}#]+|[;{}]|\n\s*|#[^\n]*")


def _past_piece_limit(text: str) -> Optional[Diagnostic]:
    """An error at the first piece past `LIMITS.max_pieces`, or None; found at regex speed."""
    if len(text) <= LIMITS.max_pieces:  # every piece takes a character at least
        return None
    beyond = next(itertools.islice(_PIECE.finditer(text), LIMITS.max_pieces, None), None)
    if beyond is None:
        return None
    message = (
        f"script is too long to read: more than {LIMITS.max_pieces} words, numbers and "
        "separators; split it into smaller scripts"
    )
    return _diagnostic_at(text, beyond.start(), message)._replace(kind="semantic")


def _build(text: str, diagnostics: List[Diagnostic]) -> Tuple[Tuple[Any, ...], bool]:
    """The AST and whether it is legacy spelling; every problem goes to `diagnostics`."""
    braces, closed, virtual = _close_braces(text)
    diagnostics.extend(braces)
    if virtual is None:
        return (), False
    found: List[Diagnostic] = []
    builder = _parser().builder
    builder.begin(closed, lambda line: _unshifted(line, virtual) or line)
    statements = _parse_recovering(closed, found)
    for d in found:
        line = _unshifted(d.line, virtual) if d.line else 0
        if line is not None:  # None: on a '}' we added, so the user's text is not at fault
            diagnostics.append(d._replace(line=line))
    if statements is None:
        return (), False
    body = tuple(statements)
    diagnostics.extend(check(body))
    return body, builder.legacy_spelling(body)


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


# -- unclosed blocks ------------------------------------------------------

# Strings first, so that a '{' or '#' inside one is text, not a block or a comment.
_STRING = re.compile(r'"(?:\\.|[^"\\\n])*"?')
_BRACES = re.compile(_STRING.pattern + r"|[{}]|#[^\n]*")


def _close_braces(text: str) -> Tuple[List[Diagnostic], str, Optional[List[int]]]:
    """Diagnostics for blocks never closed, and the text to parse.

    Each unclosed block is closed by a '}' on a line of its own, added before
    the next line that is indented no deeper than the block's first line (or
    at the end), so the rest of the script is still checked. Returns the
    added lines' numbers in the new text, or None when blocks nest too deeply
    to parse at all.
    """
    opened: List[int] = []
    for m in _BRACES.finditer(text):
        if m.group() == "{":
            opened.append(m.start())
            if len(opened) > LIMITS.max_depth:
                message = f"blocks nest too deeply (the limit is {LIMITS.max_depth} levels)"
                return [_diagnostic_at(text, m.start(), message)], text, None
        elif m.group() == "}" and opened:
            opened.pop()
    if not opened:
        return [], text, []
    diagnostics = [_diagnostic_at(text, at, "this '{' is never closed") for at in opened]
    closed, added = _add_closings(text, set(opened))
    return diagnostics, closed, added


def _add_closings(text: str, unclosed: Set[int]) -> Tuple[str, List[int]]:
    lines: List[str] = []
    added: List[int] = []
    stack: List[Tuple[int, int]] = []  # each open '{': its offset, its line's indentation
    offset = 0
    for line in text.split("\n"):
        code = _STRING.sub(lambda m: " " * len(m.group()), line).split("#", 1)[0]
        indent = len(code) - len(code.lstrip())
        if code.strip():
            # Only an unclosed block on top can end here: any '}' later
            # closes a block opened after it.
            while stack and stack[-1][0] in unclosed and indent <= stack[-1][1]:
                stack.pop()
                lines.append("}")
                added.append(len(lines))
        lines.append(line)
        for m in re.finditer("[{}]", code):
            if m.group() == "{":
                stack.append((offset + m.start(), indent))
            elif stack:
                stack.pop()
        offset += len(line) + 1
    for _ in stack:
        lines.append("}")
        added.append(len(lines))
    return "\n".join(lines), added


def _unshifted(line: int, added: List[int]) -> Optional[int]:
    """A line of the text with closings added, as a line of the user's text; None for an added line."""
    before = bisect.bisect_left(added, line)
    if before < len(added) and added[before] == line:
        return None
    return line - before


def _diagnostic_at(text: str, at: int, message: str) -> Diagnostic:
    line = text.count("\n", 0, at) + 1
    column = at - (text.rfind("\n", 0, at) + 1) + 1
    return Diagnostic(line, column, message, kind="syntax")


# -- syntax errors ---------------------------------------------------------

_MAX_SYNTAX_ERRORS = 10
_RECOVERY_BUDGET = 256 * 1024  # characters re-parsed in all, so recovery stays fast
_CHUNK = 8 * 1024  # characters parsed at a time, so a syntax error costs one chunk to re-parse


def _parse_recovering(text: str, diagnostics: List[Diagnostic]) -> Optional[List[Any]]:
    """The top-level statements' trees; after a syntax error, blank the broken statement and go on.

    The text is parsed in chunks of whole top-level statements, each after a
    filler that keeps lines and columns, so recovering from an error
    re-parses its chunk, not the whole text. Blanking keeps every other
    character where it was, so later diagnostics point at the user's own
    text. Returns None if recovery gave up.
    """
    statements: List[Any] = []
    budget = _RECOVERY_BUDGET
    errors = 0
    parser = _parser()
    builder = parser.builder
    for start, end in _chunks(text):
        chunk = _filler(text, start) + text[start:end]
        while True:
            built: List[Diagnostic] = []  # dropped if this try fails: the retry builds again
            builder.diagnostics = built
            try:
                tree = parser.lark.parse(chunk)
            except VisitError as e:  # a bug of ours, not the user's: let it show
                raise e.orig_exc from e
            except UnexpectedInput as e:
                diagnostics.append(_syntax_diagnostic(e, chunk))
                errors += 1
                budget -= (_offset(e) or end) - start
                if errors >= _MAX_SYNTAX_ERRORS or budget < 0:
                    diagnostics.append(
                        Diagnostic(0, 0, f"stopped after {errors} syntax errors", kind="syntax")
                    )
                    return None
                repaired = _blank_statement(chunk, e, lambda word: _stands_alone(parser, word))
                if repaired is None:
                    return None
                chunk = repaired
            else:
                diagnostics.extend(built)
                statements.extend(tree)
                break
    return statements


def _chunks(text: str) -> List[Tuple[int, int]]:
    """Spans of about _CHUNK characters, each ending after a newline outside any block."""
    spans: List[Tuple[int, int]] = []
    start = gap = depth = 0
    for m in itertools.chain(_BRACES.finditer(text), [None]):
        stop = len(text) if m is None else m.start()
        while depth == 0:  # [gap, stop) is outside every block
            cut = text.find("\n", max(gap, start + _CHUNK), stop)
            if cut < 0:
                break
            spans.append((start, cut + 1))
            start = cut + 1
        if m is not None:
            if m.group() == "{":
                depth += 1
            elif m.group() == "}":
                depth = max(0, depth - 1)
            gap = m.end()
    if start < len(text) or not spans:
        spans.append((start, len(text)))
    return spans


def _filler(text: str, start: int) -> str:
    """As many characters as text[:start], as many newlines, and nothing to parse."""
    newlines = text.count("\n", 0, start)
    last = text.rfind("\n", 0, start)
    return " " * (last + 1 - newlines) + "\n" * newlines + " " * (start - last - 1)


def _offset(e: UnexpectedInput) -> Optional[int]:
    if isinstance(e, UnexpectedCharacters):
        return e.pos_in_stream
    return getattr(e.token, "start_pos", None)


_SEPARATORS = ";\n{}"


_LEADING_WORD = re.compile(r"[ \t]*([A-Za-z][\w-]*)(?=[ \t])")


def _blank_statement(text: str, e: UnexpectedInput, stands_alone: Callable[[str], bool]) -> Optional[str]:
    """`text` with the statement around the error blanked out, or None.

    A first word that is a statement by itself (`wink` of `wink left`) is
    kept, so that the checker still says what is wrong with it: one run shows
    every problem of the line.
    """
    at = _offset(e)
    if at is None or at >= len(text):  # the end of the text: nothing after it to save
        return None
    start = max(text.rfind(c, 0, at) for c in _SEPARATORS) + 1
    if start > at:
        start = at
    kept = _LEADING_WORD.match(text, start, at)
    if kept is not None and stands_alone(kept.group(1)):
        start = kept.end()
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
    if kept is None and len(filler) >= 5 and "\n" not in filler[:5]:
        filler = "blink" + filler[5:]
    return text[:start] + filler + text[end:]


def _stands_alone(parser: _Parser, word: str) -> bool:
    """Does `word` parse as a whole statement (a command with no arguments)?"""
    builder = parser.builder
    kept, builder.diagnostics = builder.diagnostics, []
    try:
        parser.lark.parse(word)
    except UnexpectedInput:
        return False
    finally:
        builder.diagnostics = kept
    return True


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


_TERMINAL_NAMES = {
    "QUANTITY": "a number",
    "NAME": "a name",
    "STRING": "a string in double quotes",
    "_NL": "a new line",
    "$END": "end of script",
}


def _describe_terminal(name: str) -> str:
    if name in _TERMINAL_NAMES:
        return _TERMINAL_NAMES[name]
    for terminal in _parser().lark.terminals:  # the parser at hand: no second grammar to build
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
        spaced = _spaced_unit(text, e.pos_in_stream, char)
        string = _STRING.match(text, e.pos_in_stream) if char == '"' else None
        if string is not None and not _closed_string(string.group()):
            message = "unterminated string: it needs a closing '\"' on the same line"
        elif string is not None:
            message = f"unexpected string; expected {expected}"
        elif spaced:
            message = f"unexpected {shown} {spaced}"
        else:
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
        spaced = _spaced_unit(text, token.start_pos, str(token)) if token.type == "NAME" else ""
        if spaced:
            message = f"unexpected {found} {spaced}"
        elif token.type not in ("$END", "_NL") and keywords:
            message += did_you_mean(str(token.value), keywords)
    else:  # pragma: no cover - lark's LALR parser raises only the two above
        message = "cannot parse this"
    if not isinstance(line, int) or line < 1:
        line, column = _end_of(text)
    return Diagnostic(line, column, message, kind="syntax")


_UNIT_WORDS = frozenset(unit for units in UNITS.values() for unit in units if unit)
_NUMBER_BEFORE = re.compile(r"(?<![\w.])([-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+))[ \t]+$")


def _spaced_unit(text: str, at: int, word: str) -> str:
    """For a unit written apart from its number (`0.5 s`), how to write it; or ''."""
    if word.lower() not in _UNIT_WORDS:
        return ""
    m = _NUMBER_BEFORE.search(text, max(0, at - 40), at)
    if m is None:
        return ""
    number = m.group(1)
    return f"in '{number} {word}': write the unit straight after the number, as in '{number}{word}'"


def _closed_string(string: str) -> bool:
    """Does a `_STRING` match end with its closing quote? (It takes escaped quotes whole.)"""
    return len(string) >= 2 and string.endswith('"')


def _end_of(text: str) -> Tuple[int, int]:
    """Just after the last thing written: where a missing piece belongs."""
    body = text.rstrip()
    line = body.count("\n") + 1
    return line, len(body) - (body.rfind("\n") + 1) + 1


# -- tree -> AST ---------------------------------------------------------


class _Builder(Transformer):
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

    def block(self, children: List[Any]) -> Tuple[Any, ...]:
        return tuple(children)

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

    def easing(self, children: List[Token]) -> str:
        (token,) = children
        spaced = _spaced_unit(self.text, token.start_pos, str(token))
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

    def skin(self, children: List[Token]) -> n.Skin:
        at, index = children
        return n.Skin(self._skin(index), pos=self._pos(at))

    def _skin(self, token: Token) -> int:
        return self._whole(token, "index", "a skin", min(SKINS), max(SKINS))

    def mouth(self, children: List[Token]) -> n.Mouth:
        at, name = children
        return n.Mouth(self._known(name, MOUTHS, "mouth"), pos=self._pos(at))

    def brows(self, children: List[Token]) -> n.Brows:
        at, name = children
        return n.Brows(self._known(name, BROWS, "brows"), pos=self._pos(at))

    def eyelids(self, children: List[Any]) -> n.Eyelids:
        at, amount, *rest = children
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

    def follow_target(self, children: List[Token]) -> Optional[str]:
        kind = children[0].type
        return {"HUMAN": "human", "FACE": "face", "OFF": None, "LEFT": "left arm", "RIGHT": "right arm"}[kind]

    def say(self, children: List[Any]) -> n.Say:
        at, string, *options = children
        text = self._string(string)
        if text is not None and not text.strip():
            self._error(string, "nothing to say: the text is empty")
        elif text is not None and len(text) > LIMITS.max_say:
            self._error(
                string, f"too much to say at once ({len(text)} characters; the limit is {LIMITS.max_say})"
            )
        voice = rate = None
        for kind, value in options:
            if kind == "voice":
                voice = value if voice is None else self._twice(at, "voice")
            else:
                rate = value if rate is None else self._twice(at, "rate")
        return n.Say(text or "", voice, rate, pos=self._pos(at))

    def _twice(self, at: Token, what: str) -> None:
        self._error(at, f"'say' takes one '{what}'")

    def _string(self, token: Token) -> Optional[str]:
        """A string token's text, escapes undone; None after an error."""
        body = str(token)[1:-1]
        for m in _ESCAPE.finditer(body):
            if m.group(1) not in '"\\':
                column = token.column + 1 + m.start()
                self.diagnostics.append(
                    Diagnostic(token.line, column, f"unknown escape '\\{m.group(1)}'; write \\\" or \\\\")
                )
                return None
        return _ESCAPE.sub(r"\1", body)

    def voice(self, children: List[Token]) -> Tuple[str, Optional[str]]:
        _, token = children
        name = str(token).lower()
        if not known_voice(name):
            hint = self.hints(name, voice_names()) or "; 'baxterface voices' lists them"
            self._error(token, f"unknown voice '{token}'{hint}")
            return "voice", None
        return "voice", name

    def rate(self, children: List[Token]) -> Tuple[str, Optional[int]]:
        _, token = children
        low, high = RATES
        return "rate", self._whole(token, "rate", "a speech rate", low, high)

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

    def _body(self, at: Token, what: str, body: Tuple[Any, ...]) -> Tuple[Any, ...]:
        if not body:
            self._error(at, f"empty block: '{what}' needs at least one statement")
        return body


class _Direction(tuple):
    """A named direction's point, marked so that it is never warned about."""


_LOCAL = threading.local()


def _parser() -> _Parser:
    """This thread's parser, made on first use."""
    parser = getattr(_LOCAL, "parser", None)
    if parser is None:
        parser = _LOCAL.parser = _Parser()
    return parser
