"""The builder's rules for the continuous face: intensities and blends, mood, winks, controls.

A mixin of the builder (builder.py), which gives it `_error`, `_number`, `_known`, `_pos` and
`hints`; lark calls these as it reduces the grammar's `feeling`, `mood`, `wink` and `side`
rules, and the skin, mouth, brows and eyelids rules' numeric forms.
"""

from __future__ import annotations

from typing import Any, List

from lark import Token

from ..core.expression import CONTROLS
from ..core.tables import EMOTIONS, MOUTHS
from . import syntax_tree as n
from .diagnostics import shortened
from .vocabulary import BARE_WORDS, KEYWORDS

# The emotions as a script writes them (`wake_up`), each with its table name ("wake up").
EMOTION_WORDS = {name.replace(" ", "_"): name for name in EMOTIONS}


class ExpressionRules:
    """Rules of the builder for the continuous face (see the module's docstring)."""

    def _wants_number(self, part: str, name: Token) -> bool:
        """A control named without its number (`mouth curve`): said so, not as an unknown part."""
        control = str(name).lower()
        if (part, control) not in CONTROLS or control in MOUTHS:
            return False
        spec = CONTROLS[(part, control)]
        self._error(name, f"'{part} {control}' takes a number from {spec.low:g} to {spec.high:g}")
        return True

    def _adjust(self, part: str, children: List[Any], side: str = "") -> n.Adjust:
        """`mouth curve 0.5 in 1s`: one number of the expression, checked against CONTROLS."""
        at, name, amount, *rest = children
        controls = [c for p, c in CONTROLS if p == part]
        control = "" if name is None else self._known(name, controls, f"{part} control")
        spec = CONTROLS.get((part, control))
        value = self._number(amount, "openness", f"{part} {control}".strip())
        if spec is not None and value is not None and not spec.low <= value <= spec.high:
            what = f"{part} {control}".strip()
            self._error(amount, f"{what} must be from {spec.low:g} to {spec.high:g}, not {amount}")
        if spec is not None and side not in spec.sides:
            self._error(at, f"{part} {control} takes no side: it is one number for the whole face")
        return n.Adjust(part, control, value or 0.0, side, rest[0] if rest else n.Timing(), pos=self._pos(at))

    def pupils(self, children: List[Any]) -> n.Adjust:
        return self._sized("pupils", children)

    def eyes(self, children: List[Any]) -> n.Adjust:
        return self._sized("eyes", children)

    def _sized(self, part: str, children: List[Any]) -> n.Adjust:
        """`pupils 1.3`, `eyes left 0.9 in 1s`: a size, of both or one side."""
        at, *rest = children
        side = rest.pop(0) if not isinstance(rest[0], Token) else ""
        return self._adjust(part, [at, None, *rest], side)

    def side(self, children: List[Token]) -> str:
        return str(children[0]).lower()

    def feeling(self, children: List[Any]) -> Any:
        timing = children.pop() if isinstance(children[-1], n.Timing) else None
        at = children[0]
        weights = []
        amounts = children[1::2] or [None]  # `sad in 1.5s`: full strength
        for name, amount in zip(children[::2], amounts):
            word = str(name).lower()
            if word in EMOTION_WORDS:
                emotion = EMOTION_WORDS[word]
            elif name is at:  # `wiat 2` is more likely a mistyped command than an emotion
                known = list(EMOTION_WORDS) + list(BARE_WORDS) + list(KEYWORDS)
                self._error(name, f"unknown command '{shortened(word)}'{self.hints(word, known)}")
                emotion = "default"
            else:
                emotion = EMOTION_WORDS.get(self._known(name, EMOTION_WORDS, "emotion"), "default")
            weight = 1.0 if amount is None else self._number(amount, "openness", "an intensity")
            if word in EMOTION_WORDS and weight is not None and not 0.0 <= weight <= 1.0:
                self._error(amount, f"an intensity must be from 0 to 1, not {amount}")
            weights.append((emotion, weight or 0.0))
        if len(weights) > 1 and sum(w for _, w in weights) > 1.0 + 1e-9:
            self._error(children[1], "the intensities of a blend add up to at most 1")
        if timing is None and len(weights) == 1 and weights[0][1] in (0.0, 1.0):
            # `happy 1` is `happy`, and `happy 0` the face with no emotion: `default`.
            return n.Emotion(weights[0][0] if weights[0][1] == 1.0 else "default", pos=self._pos(at))
        return n.Feeling(tuple(weights), timing or n.Timing(), pos=self._pos(at))

    def mood(self, children: List[Any]) -> n.Mood:
        at, valence_token, arousal_token, *rest = children
        numbers = []
        for token, what in ((valence_token, "valence"), (arousal_token, "arousal")):
            value = self._number(token, "count", what)
            if value is not None and not -1.0 <= value <= 1.0:
                self._error(token, f"{what} must be from -1 to 1, not {token}")
            numbers.append(value or 0.0)
        return n.Mood(numbers[0], numbers[1], rest[0] if rest else n.Timing(), pos=self._pos(at))

    def wink(self, children: List[Any]) -> n.Wink:
        at, side = children
        return n.Wink(side, pos=self._pos(at))
