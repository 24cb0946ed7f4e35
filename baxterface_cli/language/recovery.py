"""Syntax errors, each reported where it is, and recovery from them so that one run shows every problem.

Unclosed blocks are closed where their indentation ends; a broken statement
is blanked (keeping lines and columns) and its chunk parsed again.
"""

from __future__ import annotations

import bisect
import itertools
import re
from typing import Any, Callable, List, Optional, Set, Tuple

from lark.exceptions import UnexpectedCharacters, UnexpectedInput, UnexpectedToken, VisitError
from lark.lexer import PatternStr

from ..core.face_constants import LIMITS
from .builder import ThreadParser, spaced_unit, thread_parser
from .diagnostics import Diagnostic, did_you_mean
from .events import POLICIES
from .source import diagnostic_at

# -- unclosed blocks ------------------------------------------------------

# Strings first, so that a '{' or '#' inside one is text, not a block or a comment.
_STRING = re.compile(r'"(?:\\.|[^"\\\n])*"?')
_BRACES = re.compile(_STRING.pattern + r"|[{}]|#[^\n]*")


def close_braces(text: str) -> Tuple[List[Diagnostic], str, Optional[List[int]]]:
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
                return [diagnostic_at(text, m.start(), message)], text, None
        elif m.group() == "}" and opened:
            opened.pop()
    if not opened:
        return [], text, []
    diagnostics = [diagnostic_at(text, at, "this '{' is never closed") for at in opened]
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


def unshifted(line: int, added: List[int]) -> Optional[int]:
    """A line of the text with closings added, as a line of the user's text; None for an added line."""
    before = bisect.bisect_left(added, line)
    if before < len(added) and added[before] == line:
        return None
    return line - before


# -- syntax errors ---------------------------------------------------------

_MAX_SYNTAX_ERRORS = 10
_RECOVERY_BUDGET = 256 * 1024  # characters re-parsed in all, so recovery stays fast
_CHUNK = 8 * 1024  # characters parsed at a time, so a syntax error costs one chunk to re-parse


def parse_recovering(text: str, diagnostics: List[Diagnostic]) -> Optional[List[Any]]:
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
    parser = thread_parser()
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


_SEPARATORS = ";\n{}|"  # "|" parts the choices of a `one of`


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
    # Never after a block's '}' on its line: a statement cannot stand there either, and the
    # placeholder would be the next error, again and again.
    if kept is None and not _after_block(text, start) and len(filler) >= 5 and "\n" not in filler[:5]:
        filler = "blink" + filler[5:]
    return text[:start] + filler + text[end:]


def _stands_alone(parser: ThreadParser, word: str) -> bool:
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
    for terminal in thread_parser().lark.terminals:  # the parser at hand: no second grammar to build
        if terminal.name == name and isinstance(terminal.pattern, PatternStr):
            return f"'{terminal.pattern.value.lower()}'"
    return name.lower().replace("_", " ")


def _expected(names: Any) -> Tuple[str, List[str]]:
    """A phrase for what the parser wanted, and the keywords among it."""
    # A `one of`'s '|' and an `ask`'s answers (a string, `else`, `nothing`): the parser offers
    # them after any block's statement, where they are seldom what was meant.
    names = set(names) - {"BAR", "ELSE", "NOTHING"} - ({"STRING"} if "RBRACE" in names else set())
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
        spaced = spaced_unit(text, e.pos_in_stream, char)
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
        spaced = spaced_unit(text, token.start_pos, str(token)) if token.type == "NAME" else ""
        if _policy_after_block(text, token):
            option = f"{token} 5s" if str(token).lower() == "cooldown" else str(token)
            message = (
                f"unexpected {found}: a handler's policy goes before its block: on EVENT {option} {{ ... }}"
            )
        elif spaced:
            message = f"unexpected {found} {spaced}"
        elif token.type not in ("$END", "_NL") and keywords:
            message += did_you_mean(str(token.value), keywords)
    else:  # pragma: no cover - lark's LALR parser raises only the two above
        message = "cannot parse this"
    if not isinstance(line, int) or line < 1:
        line, column = _end_of(text)
    return Diagnostic(line, column, message, kind="syntax")


def _policy_after_block(text: str, token: Any) -> bool:
    """`on touch { happy } queue`: a policy, or a cooldown, written after the block it is for."""
    word = str(token.value).lower()
    return word in POLICIES + ("cooldown",) and _after_block(text, token.start_pos)


def _after_block(text: str, at: int) -> bool:
    """Does a block's '}' come just before `at`, on its line?"""
    return text[:at].rstrip(" \t").endswith("}")


def _closed_string(string: str) -> bool:
    """Does a `_STRING` match end with its closing quote? (It takes escaped quotes whole.)"""
    return len(string) >= 2 and string.endswith('"')


def _end_of(text: str) -> Tuple[int, int]:
    """Just after the last thing written: where a missing piece belongs."""
    body = text.rstrip()
    line = body.count("\n") + 1
    return line, len(body) - (body.rfind("\n") + 1) + 1
