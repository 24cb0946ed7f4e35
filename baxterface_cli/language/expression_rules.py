"""The builder's rules for the continuous face: intensities and blends, mood, winks, controls.

A mixin of the builder (builder.py), which gives it `_error`, `_number`, `_known`, `_pos` and
`hints`; lark calls these as it reduces the grammar's `feeling`, `mood`, `wink` and `side`
rules, and the skin, mouth, brows and eyelids rules' numeric forms.
"""

from __future__ import annotations

from typing import Any, List, Optional

from lark import Token

from ..core.expression import CONTROLS
from ..core.face_constants import EMOTIONS, MOUTHS
from . import syntax_tree as n
from .diagnostics import one_of, shortened
from .statements import KEYWORDS
from .vocabulary import BARE_WORDS


class _Variant:
    """`variant N` after an emotion's name, for `feeling` to read."""

    def __init__(self, token: Token) -> None:
        self.token = token


SIDES = ("left", "right")


def _is_name(child: Any) -> bool:
    return isinstance(child, Token) and child.type == "NAME"


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
        control = "" if name is None else self._control(part, name, controls, side)
        spec = CONTROLS.get((part, control))
        value = self._number(amount, "openness", f"{part} {control}".strip())
        if spec is not None and value is not None and not spec.low <= value <= spec.high:
            what = f"{part} {control}".strip()
            self._error(amount, f"{what} must be from {spec.low:g} to {spec.high:g}, not {amount}")
        if spec is not None and side not in spec.sides:
            self._error(at, f"{part} {control} takes no side: it is one number for the whole face")
        return n.Adjust(part, control, value or 0.0, side, rest[0] if rest else n.Timing(), pos=self._pos(at))

    def _mistyped_side(self, part: str, rest: List[Any]) -> None:
        """`brows lft raised`: drop the word where a side belongs, and say what it should be."""
        token = rest.pop(0)
        word = str(token).lower()
        if word == "both":
            self._error(token, f"'both' is not a side: leave the side out for both {part}")
        else:
            hint = self.hints(word, SIDES) or f"; use {one_of(SIDES)}, or no side for both {part}"
            self._error(token, f"unknown side '{shortened(word)}'{hint}")

    def _control(self, part: str, name: Token, controls: List[str], side: str) -> str:
        """A control's name; a word that is none, reported with a hint (a side's, `eyelids lft 0.5`)."""
        word = str(name).lower()
        if word in controls:
            return word
        named = [c for c in controls if c]
        sides = list(SIDES) if part in ("brows", "eyelids") and not side else []
        hint = self.hints(word, named + sides) or f"; use {one_of(named + sides)}"
        self._error(name, f"unknown {part} control '{shortened(word)}'{hint}")
        return word

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

    def variant(self, children: List[Token]) -> _Variant:
        return _Variant(children[1])

    def feeling(self, children: List[Any]) -> Any:
        timing = children.pop() if isinstance(children[-1], n.Timing) else None
        at = children[0]
        # Each emotion as (its name, its `variant N` or None, its intensity or None: full strength).
        written: List[List[Any]] = []
        for child in children:
            if isinstance(child, _Variant):
                if written[-1][1] is not None:
                    self._error(child.token, "an emotion takes one 'variant'")
                written[-1][1] = child.token
            elif child.type == "QUANTITY":
                written[-1][2] = child
            else:
                written.append([child, None, None])
        weights, variants = [], []
        for name, variant, amount in written:
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
            variants.append(
                None if variant is None else self._variant(variant, emotion, word in EMOTION_WORDS)
            )
        if len(weights) > 1 and sum(w for _, w in weights) > 1.0 + 1e-9:
            self._error(written[0][2], "the intensities of a blend add up to at most 1")
        chosen = tuple(variants) if any(v is not None for v in variants) else ()
        if timing is None and len(weights) == 1 and weights[0][1] in (0.0, 1.0):
            # `happy 1` is `happy`, and `happy 0` the face with no emotion: `default`.
            if weights[0][1] == 0.0:
                return n.Emotion("default", pos=self._pos(at))
            return n.Emotion(weights[0][0], pos=self._pos(at), variant=variants[0])
        return n.Feeling(tuple(weights), timing or n.Timing(), pos=self._pos(at), variants=chosen)

    def _variant(self, token: Token, emotion: str, known: bool) -> Optional[int]:
        """`variant N`'s N, checked against the emotion's variants; None after an error."""
        count = len(EMOTIONS[emotion].variants)
        value = self._number(token, "count", "a variant")
        if value is None or not known:
            return None
        if value != int(value) or not 1 <= value <= count:
            word = emotion.replace(" ", "_")
            choices = {1: "only variant 1", 2: "variants 1 and 2"}.get(count, f"variants 1 to {count}")
            self._error(token, f"'{word}' has {choices}, not {token}")
            return None
        return int(value)

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
