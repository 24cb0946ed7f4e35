"""The builder's rules for speech: `say "..." voice en-gb rate 150` and `say file "..." text "..."`.

A mixin of the builder (builder.py), which gives it `_error`, `_whole`, `_pos` and `hints`;
lark calls these as it reduces the grammar's `say` rule and its options.
"""

from __future__ import annotations

import re
from typing import Any, Dict, List, Optional, Tuple

from lark import Token

from ..core.face_constants import LIMITS
from ..core.voices import RATES, known_voice, natural, say_voice_names
from . import syntax_tree as n
from .diagnostics import Diagnostic

_ESCAPE = re.compile(r"\\(.)", re.S)


class SpeechRules:
    """Rules of the builder for `say` (see the module's docstring)."""

    def say(self, children: List[Any]) -> n.Say:
        at, *rest = children
        recorded = rest[0] if rest[0].type == "FILE" else None
        string, *options = rest[1:] if recorded is not None else rest
        said: Dict[str, Any] = {}
        for kind, value, token in options:
            if kind in said:
                self._error(at, f"'say' takes one '{kind}'")
            elif recorded is None and kind in ("text", "language"):
                self._error(token, f"'{kind}' is for a recording: say file \"NAME\" {kind} ...")
            elif recorded is not None and kind in ("voice", "rate"):
                self._error(token, f"a recording has its own voice and rate: 'say file' takes no '{kind}'")
            said[kind] = value
        if recorded is not None:
            return self._say_file(at, string, said)
        text = self._string(string)
        self._check_text(string, text)
        return n.Say(text or "", said.get("voice"), said.get("rate"), pos=self._pos(at))

    def _say_file(self, at: Token, string: Token, said: Dict[str, Any]) -> n.Say:
        path = self._string(string)
        if path is not None and not path.strip():
            self._error(string, "no recording named: the file name is empty")
        elif path is not None and "\0" in path:
            self._error(string, "a file name cannot hold a NUL character")
        text = said.get("text")
        return n.Say(
            text or "",
            pos=self._pos(at),
            file=path or "",
            language=said.get("language"),
            file_pos=self._pos(string),
        )

    def _check_text(self, string: Token, text: Optional[str], limit: int = LIMITS.max_say) -> None:
        if text is not None and not text.strip():
            self._error(string, "nothing to say: the text is empty")
        elif text is not None and len(text) > limit:
            self._error(string, f"too much to say at once ({len(text)} characters; the limit is {limit})")

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

    def voice(self, children: List[Token]) -> Tuple[str, Optional[str], Token]:
        keyword, token = children
        return "voice", self._voice_name(token, "voice"), keyword

    def language(self, children: List[Token]) -> Tuple[str, Optional[str], Token]:
        keyword, token = children
        return "language", self._voice_name(token, "language"), keyword

    def _voice_name(self, token: Token, what: str) -> Optional[str]:
        """A voice's name (a language is named as espeak-ng's voices for it are); None if unknown."""
        name = str(token).lower()
        if what == "language" and natural(name):
            self._error(token, f"'{token}' is a voice, not a language; 'baxterface voices' lists them")
            return None
        if not known_voice(name):
            hint = self.hints(name, say_voice_names()) or "; 'baxterface voices' lists them"
            self._error(token, f"unknown {what} '{token}'{hint}")
            return None
        return name

    def rate(self, children: List[Token]) -> Tuple[str, Optional[int], Token]:
        keyword, token = children
        low, high = RATES
        return "rate", self._whole(token, "rate", "a speech rate", low, high), keyword

    def words(self, children: List[Token]) -> Tuple[str, Optional[str], Token]:
        keyword, token = children
        text = self._string(token)
        self._check_text(token, text, LIMITS.max_recorded_text)
        return "text", text, keyword
