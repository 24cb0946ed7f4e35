"""An `ask` listening for its answers: what a run's wait holds from when its question ends.

The answers are phrases, as `on word` listens for (`event` is the `word` event of all of them, so
the ears listen for each). A `word` heard that is one of them chooses its answer; a whole
utterance heard (`heard "yes please"`: a recogniser's, or an events file's) chooses the first
answer one of whose phrases it holds as whole words, else `else` if the `ask` has one. Nothing
within the `nothing` time runs `nothing`'s body; without one, it listens until an answer comes.
"""

from __future__ import annotations

from typing import NamedTuple, Optional, Tuple

from ..language import syntax_tree as n
from ..language.events import ALTERNATIVES
from ..language.statements import quoted
from .session_program import Runner


class Chosen(NamedTuple):
    said: str  # the log's words for it: what was heard, and where it went
    body: Tuple[n.Statement, ...]


class Answering:
    """See the module's docstring."""

    def __init__(self, ask: n.Ask) -> None:
        self.ask = ask
        self.event = n.Event("word", ALTERNATIVES.join(dict.fromkeys(ask.phrases)))
        self.timeout: Optional[float] = ask.nothing[0] if ask.nothing is not None else None
        self.asked = f"line {ask.pos.line} 'ask {quoted(ask.question.text)}'"  # as the log names it

    def answer(self, event: n.Event) -> Optional[Chosen]:
        """What `event` chooses, or None if it answers nothing."""
        asked = self.asked
        if event.kind == "word":
            for answer in self.ask.answers:
                if event.arg in answer.phrases:
                    return Chosen(
                        f"{asked} answered {quoted(event.arg)} (line {answer.pos.line})", answer.body
                    )
        if event.kind == "heard":
            words = f" {event.arg} "
            for answer in self.ask.answers:
                found = next((p for p in answer.phrases if f" {p} " in words), None)
                if found is not None:
                    return Chosen(f"{asked} answered {quoted(found)} in {quoted(event.arg)}", answer.body)
            if self.ask.otherwise is not None:
                return Chosen(
                    f"{asked} answered none of its answers: {quoted(event.arg)}", self.ask.otherwise
                )
        return None

    def take(self, runner: Runner, event: Optional[n.Event] = None) -> Optional[str]:
        """The answer `event` gives (None: the `nothing` time passed), its body first in `runner`,
        and the log's words for it; None if `event` answers nothing."""
        chosen = self.unanswered() if event is None else self.answer(event)
        if chosen is not None:
            runner.then(chosen.body)
        return None if chosen is None else chosen.said

    def unanswered(self) -> Chosen:
        """The `nothing` time passed and nobody spoke."""
        body = self.ask.nothing[1] if self.ask.nothing is not None else ()
        return Chosen(f"{self.asked}: nothing heard within {self.timeout:g} s", body)
