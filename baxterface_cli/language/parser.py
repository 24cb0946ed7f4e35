"""Text -> syntax tree, with every check done on the way: `parse` and `parse_file`.

The text is read and held to its limits (source.py), parsed by the grammar
(grammar/face.lark) with a builder that makes the syntax tree's dataclasses as
lark reduces (builder.py), recovering from syntax errors so that one run shows
every problem (recovery.py), then checked as a whole (checker.py).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Dict, List, Optional, Tuple, Union

from ..core.face_constants import LIMITS
from . import syntax_tree as n
from .borrowing import Borrowing, Gesture, borrowed, gesture_library, top_level_only
from .builder import grammar, thread_parser
from .checker import check
from .diagnostics import Diagnostic, ScriptError, keep_first
from .recovery import close_braces, parse_recovering, unshifted
from .source import decode, past_piece_limit, read_bounded, utf8_size

__all__ = ["grammar", "grammar_words", "gestures", "parse", "parse_file", "read_bounded", "decode"]
Folder = Union[None, str, Path, Borrowing]


def parse(text: str, filename: str = "<script>", folder: Folder = None) -> n.Script:
    """Parse and check a script; raise one ScriptError carrying the diagnostics.

    The script may call the face's gestures, and its `use`s are read from `folder` (the script's
    own; None refuses them: language/borrowing.py). At most `LIMITS.max_shown` diagnostics are
    kept (errors first); the rest are counted, so a flood of problems stays cheap to report.
    """
    diagnostics: List[Diagnostic] = []
    body: Tuple[Any, ...] = ()
    legacy = False
    size = utf8_size(text)
    if size > LIMITS.max_bytes:
        message = f"script is too large ({size} bytes; the limit is {LIMITS.max_bytes})"
        diagnostics.append(Diagnostic(0, 0, message))
    else:
        too_long = past_piece_limit(text)
        if too_long is not None:
            diagnostics.append(too_long)
        else:
            borrowing = folder if isinstance(folder, Borrowing) else Borrowing.in_folder(_name(folder))
            body, legacy = _build(text, diagnostics, borrowing)
    shown, more_errors, more_warnings = keep_first(diagnostics)
    if more_errors or any(d.severity == "error" for d in shown):
        raise ScriptError(shown, filename, text, more_errors, more_warnings)
    return n.Script(body, filename, tuple(shown), text, legacy, more_warnings)


def _name(folder: Union[None, str, Path]) -> Optional[str]:
    return None if folder is None else str(folder)


def _build(text: str, diagnostics: List[Diagnostic], borrowing: Borrowing) -> Tuple[Tuple[Any, ...], bool]:
    """The AST and whether it is legacy spelling; every problem goes to `diagnostics`."""
    braces, closed, virtual = close_braces(text)
    diagnostics.extend(braces)
    if virtual is None:
        return (), False
    found: List[Diagnostic] = []
    builder = thread_parser().builder
    builder.begin(closed, lambda line: unshifted(line, virtual) or line)
    statements = parse_recovering(closed, found)
    for d in found:
        line = unshifted(d.line, virtual) if d.line else 0
        if line is not None:  # None: on a '}' we added, so the user's text is not at fault
            diagnostics.append(d._replace(line=line))
    if statements is None:
        return (), False
    own = tuple(statements)
    top_level_only(own, diagnostics)
    body = own + borrowed(own, borrowing, read_script, diagnostics)
    known = gesture_library(read_script) if borrowing.gestures else {}
    diagnostics.extend(check(body, known))
    return body, builder.legacy_spelling(own)


def parse_file(path: Union[str, Path, Any], display_name: Optional[str] = None) -> n.Script:
    """Read a script file or binary stream (UTF-8, bounded in size) and parse it; its `use`s are
    read from its folder (a stream's: the current folder)."""
    name = display_name or str(path)
    text = decode(read_bounded(path, name), name)
    folder = os.path.dirname(os.path.abspath(path)) if isinstance(path, (str, Path)) else "."
    return parse(text, name, folder)


def read_script(path: str, name: str, borrowing: Borrowing) -> n.Script:
    """A file a script uses (or the gestures' library), parsed as `name`, borrowing as told."""
    return parse(decode(read_bounded(path, name), name), name, borrowing)


def gestures() -> Dict[str, Gesture]:
    """The face's gestures by name (data/gestures.face), each with its length and what it does."""
    return gesture_library(read_script)


def grammar_words() -> List[str]:
    """Every word the grammar spells out (`look`, `in`, `voice`, ...), for editors to colour."""
    from lark.lexer import PatternStr

    patterns = (terminal.pattern for terminal in grammar().terminals)
    return sorted({p.value.lower() for p in patterns if isinstance(p, PatternStr) and p.value.isalpha()})
