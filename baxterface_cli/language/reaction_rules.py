"""The builder's rules for reacting: `on`, `wait until`, `signal`, `forever`, `one of`, states and `ask`.

A mixin of builder.py's `_Builder`, which gives it `_error`, `_pos`, `_seconds`, `_string`,
`_body` and `hints`. The grammar reads an event and its options as plain words; what they mean
is decided here (with events.py), so a misspelled event or option is named where it is written.
"""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Tuple

from lark import Token

from . import syntax_tree as n
from .diagnostics import one_of
from .events import (
    PLACES,
    POLICIES,
    in_words,
    not_a_phrase,
    option_words,
    phrase_of,
    read_event,
    written_zero,
)


class ReactionRules:
    """Builder methods of the grammar's reacting rules (see the module's docstring)."""

    _error: Any
    _pos: Any
    _seconds: Any
    _string: Any
    _body: Any
    hints: Any

    def _event(self, tokens: List[Token]) -> Tuple[Optional[n.Event], List[Token]]:
        event, rest = read_event(tokens, self._error, self._seconds, self._string, self.hints)
        if event is not None:
            event = n.Event(event.kind, event.arg, event.seconds, self._pos(tokens[0]))
        return event, rest

    def on(self, children: List[Any]) -> n.On:
        at, *words, body = children
        event, rest = self._event(words)
        options = self._options(rest, event, "on", ("policy", "cooldown"))
        event = event or n.Event("signal", "?")
        return n.On(
            event,
            self._body(at, "on", body),
            options.get("policy", "drop"),
            options.get("cooldown", 0.0),
            pos=self._pos(at),
        )

    def wait_until(self, children: List[Any]) -> n.WaitUntil:
        at, _until, *words = children
        event, rest = self._event(words)
        if event is not None and event.kind == "every":
            self._error(words[0], f"'wait until' cannot wait for 'every'; write 'wait {event.seconds:g}s'")
        options = self._options(rest, event, "wait until", ("timeout",))
        return n.WaitUntil(event or n.Event("signal", "?"), options.get("timeout"), pos=self._pos(at))

    def _options(
        self, tokens: List[Token], event: Optional[n.Event], statement: str, fitting: Tuple[str, ...]
    ) -> Dict[str, Any]:
        """The options after an event: a policy, `cooldown T`, `timeout T`, each at most once."""
        found: Dict[str, Any] = {}
        if event is None:  # its error is said; what follows it cannot be read for sure
            return found
        written = f"'{statement} {in_words(event)}'"
        i = 0
        while i < len(tokens):
            token = tokens[i]
            word = str(token).lower()
            option = "policy" if word in POLICIES else word
            if token.type != "NAME" or option not in ("policy", "cooldown", "timeout"):
                self._error(token, self._unknown(token, event, written, fitting))
                return found
            if option not in fitting:
                where = "'on'" if option in ("policy", "cooldown") else "'wait until'"
                self._error(token, f"'{word}' fits {where}, not {written}")
                return found
            if option in found:
                self._error(token, f"{written} has its {'policy' if option == 'policy' else option} already")
                return found
            if option == "policy":
                found[option] = word
                i += 1
                continue
            if i + 1 >= len(tokens) or tokens[i + 1].type != "QUANTITY":
                self._error(token, f"'{word}' needs a time: '{word} 5s'")
                return found
            seconds = self._seconds(tokens[i + 1], f"a {word}")
            if option == "timeout" and seconds == 0 and written_zero(tokens[i + 1]):  # not a bad number
                self._error(tokens[i + 1], "a timeout must be more than 0 s")
            found[option] = seconds
            i += 2
        return found

    def _unknown(self, token: Token, event: n.Event, written: str, fitting: Tuple[str, ...]) -> str:
        halves = [p for p in PLACES if " " in p and p.split()[0] == str(token).lower()]
        if event.kind == "touch" and token.type == "NAME" and halves:  # `touch left`: which left?
            return f"'{token}' alone is not a place on the face; write 'touch {halves[0]}'"
        hint = self.hints(str(token).lower(), option_words(event)) if token.type == "NAME" else ""
        if hint:
            return f"unknown option '{token}' for {written}{hint}"
        takes = one_of(POLICIES + ("cooldown T",)) if "policy" in fitting else "'timeout T'"
        if event.kind == "touch" and token.type == "NAME":
            places = one_of(PLACES)
            return f"unknown place or option '{token}' for {written}; it takes a place ({places}) and {takes}"
        return f"unexpected '{token}' after {written}; it takes {takes}"

    def signal(self, children: List[Token]) -> n.Signal:
        at, name = children
        return n.Signal(str(name).lower(), pos=self._pos(at))

    def state(self, children: List[Any]) -> n.State:
        at, name, body = children
        return n.State(str(name).lower(), self._body(at, "state", body), pos=self._pos(at))

    def go(self, children: List[Token]) -> n.Go:
        at, name = children
        return n.Go(str(name).lower(), pos=self._pos(at))

    def ask(self, children: List[Any]) -> n.Ask:
        at, string, *rest = children
        text = self._string(string)
        self._check_text(string, text)  # type: ignore[attr-defined]
        said: Dict[str, Any] = {}
        answers: List[n.Answer] = []
        otherwise: Optional[Tuple[Any, ...]] = None
        nothing: Optional[Tuple[float, Tuple[Any, ...]]] = None
        for part in rest:
            if isinstance(part, n.Answer):
                answers.append(part)
            elif part[0] in ("voice", "rate"):
                kind, value, token = part
                if kind in said:
                    self._error(token, f"'ask' takes one '{kind}'")
                said[kind] = value
            elif part[0] in ("text", "language"):
                self._error(part[2], f"'{part[0]}' is for a recording: say file \"NAME\" {part[0]} ...")
            elif part[0] == "else":
                if otherwise is not None:
                    self._error(part[2], "'ask' takes one 'else'")
                otherwise = part[1]
            else:
                if nothing is not None:
                    self._error(part[2], "'ask' takes one 'nothing'")
                nothing = part[1]
        if not answers:
            self._error(at, '\'ask\' needs an answer to listen for: ask "Ready?" { "yes" { happy } }')
        question = n.Say(text or "", said.get("voice"), said.get("rate"), pos=self._pos(at))
        return n.Ask(question, tuple(answers), otherwise, nothing, pos=self._pos(at))

    def answer(self, children: List[Any]) -> n.Answer:
        *strings, body = children
        found: List[str] = []
        for token in (t for t in strings if t.type == "STRING"):
            text = self._string(token)
            phrase = phrase_of(text) if text is not None else None
            if phrase is None:
                if text is not None:
                    self._error(token, not_a_phrase("an answer is", text))
            elif phrase not in found:
                found.append(phrase)
        return n.Answer(tuple(found), self._body(strings[0], "answer", body), pos=self._pos(strings[0]))

    def otherwise(self, children: List[Any]) -> Tuple[str, Tuple[Any, ...], Token]:
        at, body = children
        return "else", self._body(at, "else", body), at

    def nothing(self, children: List[Any]) -> Tuple[str, Tuple[float, Tuple[Any, ...]], Token]:
        at, time, body = children
        seconds = self._seconds(time, "a 'nothing' time")
        if seconds <= 0 and not written_zero(time):
            seconds = 0.0
        elif seconds <= 0:
            self._error(time, f"a 'nothing' time must be more than 0 s, not {time}")
        return "nothing", (seconds, self._body(at, "nothing", body)), at

    def forever(self, children: List[Any]) -> n.Forever:
        at, body = children
        return n.Forever(self._body(at, "forever", body), pos=self._pos(at))

    def one_of(self, children: List[Any]) -> n.OneOf:
        at, _of, *choices = children
        return n.OneOf(tuple(c for c in choices if not isinstance(c, Token)), pos=self._pos(at))

    def choice(self, children: List[Any]) -> Tuple[Any, ...]:
        return tuple(children)
