"""A script's text before parsing: read within the size limit, decoded, and held to the piece limit.

Each limit is checked at regex speed before the parser sees the text, so a
huge or hostile script costs little to refuse.
"""

from __future__ import annotations

import itertools
import re
from pathlib import Path
from typing import Any, Optional, Union

from ..core.face_constants import LIMITS
from .diagnostics import Diagnostic, ScriptError


def utf8_size(text: str) -> int:
    """The text's size in UTF-8 bytes, encoding it only when that could matter."""
    if len(text) * 4 <= LIMITS.max_bytes:  # no character takes more than 4 bytes
        return len(text)
    return len(text.encode("utf-8", "surrogatepass"))


PIECE = re.compile(r"[^\s;{}#]+|[;{}]|\n\s*|#[^\n]*")


def past_piece_limit(text: str) -> Optional[Diagnostic]:
    """An error at the first piece past `LIMITS.max_pieces`, or None; found at regex speed."""
    if len(text) <= LIMITS.max_pieces:  # every piece takes a character at least
        return None
    beyond = next(itertools.islice(PIECE.finditer(text), LIMITS.max_pieces, None), None)
    if beyond is None:
        return None
    message = (
        f"script is too long to read: more than {LIMITS.max_pieces} words, numbers and "
        "separators; split it into smaller scripts"
    )
    return diagnostic_at(text, beyond.start(), message)._replace(kind="semantic")


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


def diagnostic_at(text: str, at: int, message: str) -> Diagnostic:
    line = text.count("\n", 0, at) + 1
    column = at - (text.rfind("\n", 0, at) + 1) + 1
    return Diagnostic(line, column, message, kind="syntax")
