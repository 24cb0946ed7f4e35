"""Diagnostics: what is wrong with a script, where, and how it is printed.

A diagnostic prints as a compiler's would::

    show.face:3:7: error: unknown mouth 'smil'; did you mean 'smile'?
        mouth smil
              ^
"""

from __future__ import annotations

import difflib
from typing import Iterable, List, NamedTuple, Optional, Sequence, Tuple


class Diagnostic(NamedTuple):
    line: int  # from 1; 0 when the problem has no place in the text
    column: int  # from 1
    message: str
    severity: str = "error"  # or "warning"
    kind: str = "semantic"  # "syntax" for what the grammar rejects

    def render(self, filename: str, text: Optional[str] = None) -> str:
        where = f"{filename}:{self.line}:{self.column}" if self.line else filename
        head = f"{where}: {self.severity}: {self.message}"
        excerpt = _excerpt(text, self.line, self.column)
        if excerpt is None:
            return head
        source, column = excerpt
        # Keep the tabs of the line's prefix so the caret lines up however
        # the terminal expands them.
        prefix = "".join(c if c == "\t" else " " for c in source[: column - 1])
        return f"{head}\n    {source}\n    {prefix}^"


class ScriptError(Exception):
    """A script that cannot run; carries every diagnostic found in it."""

    def __init__(
        self,
        diagnostics: Sequence[Diagnostic],
        filename: str = "<script>",
        text: Optional[str] = None,
    ) -> None:
        self.diagnostics = list(diagnostics)
        self.filename = filename
        self.text = text
        super().__init__(self.render())

    @property
    def errors(self) -> List[Diagnostic]:
        return [d for d in self.diagnostics if d.severity == "error"]

    def render(self) -> str:
        return render_all(self.diagnostics, self.filename, self.text)


def render_all(diagnostics: Iterable[Diagnostic], filename: str, text: Optional[str]) -> str:
    return "\n".join(d.render(filename, text) for d in diagnostics)


def did_you_mean(word: str, choices: Iterable[str]) -> str:
    """`; did you mean 'x'?` for the closest choice, or nothing."""
    close = difflib.get_close_matches(word.lower(), sorted(set(choices)), n=1, cutoff=0.6)
    return f"; did you mean '{close[0]}'?" if close else ""


def one_of(choices: Iterable[str]) -> str:
    """`'a', 'b' or 'c'`."""
    quoted = [f"'{c}'" for c in choices]
    if len(quoted) <= 1:
        return "".join(quoted)
    return ", ".join(quoted[:-1]) + " or " + quoted[-1]


_WINDOW = 100  # characters of a long source line shown around the column


def _excerpt(text: Optional[str], line: int, column: int) -> Optional[Tuple[str, int]]:
    """The source line to show under a message, and the caret's column in it."""
    if text is None or line < 1:
        return None
    lines = text.split("\n")
    if line > len(lines):
        return None
    source = lines[line - 1].rstrip("\r")
    if len(source) > _WINDOW:
        start = max(0, column - 1 - _WINDOW // 2)
        source = source[start : start + _WINDOW]
        column -= start
    # Control characters could drive the terminal; show them as '?'.
    shown = "".join("?" if (ord(c) < 32 and c != "\t") or ord(c) == 127 else c for c in source)
    return shown, column
