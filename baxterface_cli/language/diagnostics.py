"""Diagnostics: what is wrong with a script, where, and how it is printed.

A diagnostic prints as a compiler's would::

    show.face:3:7: error: unknown mouth 'smil'; did you mean 'smile'?
        mouth smil
              ^
"""

from __future__ import annotations

import difflib
import re
from functools import lru_cache
from typing import Iterable, List, NamedTuple, Optional, Sequence, Tuple

from ..core.face_constants import LIMITS


class Diagnostic(NamedTuple):
    line: int  # from 1; 0 when the problem has no place in the text
    column: int  # from 1
    message: str
    severity: str = "error"  # or "warning"
    kind: str = "semantic"  # "syntax" for what the grammar rejects

    def render(self, filename: str, text: Optional[str] = None) -> str:
        head = self.head(filename)
        excerpt = _excerpt(text, self.line, self.column)
        if excerpt is None:
            return head
        source, column = excerpt
        # Keep the tabs of the line's prefix so the caret lines up however
        # the terminal expands them.
        prefix = "".join(c if c == "\t" else " " for c in source[: column - 1])
        return f"{head}\n    {source}\n    {prefix}^"

    def head(self, filename: str) -> str:
        """The first line of the rendering, without the source excerpt."""
        where = f"{filename}:{self.line}:{self.column}" if self.line else filename
        return f"{where}: {self.severity}: {self.message}"


class ScriptError(Exception):
    """A script that cannot run; carries its first diagnostics and counts the rest.

    At most `LIMITS.max_shown` diagnostics are kept, errors first;
    `more_errors` and `more_warnings` count those left out.
    """

    def __init__(
        self,
        diagnostics: Sequence[Diagnostic],
        filename: str = "<script>",
        text: Optional[str] = None,
        more_errors: int = 0,
        more_warnings: int = 0,
    ) -> None:
        self.diagnostics = list(diagnostics)
        self.filename = filename
        self.text = text
        self.more_errors = more_errors
        self.more_warnings = more_warnings
        super().__init__(filename)

    def __str__(self) -> str:  # rendered when asked for, not when raised
        return self.render()

    @property
    def errors(self) -> List[Diagnostic]:
        return [d for d in self.diagnostics if d.severity == "error"]

    def render(self) -> str:
        return render_all(self.diagnostics, self.filename, self.text, self.more_errors, self.more_warnings)

    def summary(self) -> str:
        """One line for a log: the first error and how many more problems there are."""
        if not self.diagnostics:
            return f"{self.filename}: error: bad script"
        first = (self.errors or self.diagnostics)[0]
        more = len(self.diagnostics) - 1 + self.more_errors + self.more_warnings
        tail = f" (and {_count(more, 'more problem')})" if more else ""
        return first.head(self.filename) + tail


def keep_first(diagnostics: Sequence[Diagnostic]) -> Tuple[List[Diagnostic], int, int]:
    """The diagnostics to show, errors first and then in text order, and how
    many errors and warnings are left out."""
    errors = [d for d in diagnostics if d.severity == "error"][: LIMITS.max_shown]
    warnings = [d for d in diagnostics if d.severity != "error"][: LIMITS.max_shown - len(errors)]
    shown = sorted(errors + warnings, key=_place)
    more_errors = sum(d.severity == "error" for d in diagnostics) - len(errors)
    return shown, more_errors, len(diagnostics) - len(shown) - more_errors


def _place(d: Diagnostic) -> Tuple[float, int]:
    return (d.line or float("inf"), d.column)


def render_all(
    diagnostics: Iterable[Diagnostic],
    filename: str,
    text: Optional[str],
    more_errors: int = 0,
    more_warnings: int = 0,
) -> str:
    lines = [d.render(filename, text) for d in diagnostics]
    more = [
        _count(k, f"more {what}") for k, what in ((more_errors, "error"), (more_warnings, "warning")) if k
    ]
    if more:
        lines.append(f"{filename}: ... and {' and '.join(more)}")
    return "\n".join(lines)


def _count(k: int, what: str) -> str:
    return f"{k} {what}" + ("" if k == 1 else "s")


class Hints:
    """`did_you_mean` for the first few problems only.

    Only the first problems are shown, and a flood of misspellings must stay
    cheap: each suggestion compares the word with every choice.
    """

    def __init__(self, limit: int = LIMITS.max_shown) -> None:
        self.left = limit

    def __call__(self, word: str, choices: Iterable[str]) -> str:
        if self.left <= 0:
            return ""
        self.left -= 1
        return did_you_mean(word, choices)


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
    starts = _line_starts(text)
    if line > len(starts):
        return None
    end = starts[line] - 1 if line < len(starts) else len(text)
    source = text[starts[line - 1] : end].rstrip("\r")
    if len(source) > _WINDOW:
        start = max(0, column - 1 - _WINDOW // 2)
        source = source[start : start + _WINDOW]
        column -= start
    # Control characters could drive the terminal; show them as '?'.
    shown = "".join("?" if (ord(c) < 32 and c != "\t") or ord(c) == 127 else c for c in source)
    return shown, column


@lru_cache(maxsize=4)
def _line_starts(text: str) -> List[int]:
    """Where each line begins: found once per text, not once per diagnostic."""
    return [0] + [m.end() for m in re.finditer("\n", text)]


def shortened(text: str, most: int = 40) -> str:
    """Text as a message shows it: a 300 KB word or reason would fill the terminal, the log."""
    return text if len(text) <= most else text[:most] + "..."
