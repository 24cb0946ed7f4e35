"""The face at one instant: an immutable value that the renderer turns into a frame."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any, Dict, Optional, Tuple

from .expression import Expression
from .presets import DEFAULT_FACE, Parts, from_parts, nearest_parts

__all__ = ["FaceState", "Parts"]

# Fields that `__init__` stores as given, whatever the others: a look changes only these.
_PLAIN = frozenset({"eye_x", "eye_y", "eyelids", "head_pan", "emotion", "mood"})


@dataclass(frozen=True, init=False)
class FaceState:
    """Everything a frame depends on, plus the head pan the robot shows.

    Eye coordinates are pixels of the 1024x600 face (x right, y down), eyelid
    openness runs from 0 (closed) to 1 (open), for both eyes (`expression` may give each eye a
    share of it). `expression` is what the face looks like (core/expression.py), the one model
    of it; `emotion` names the emotion the face shows from the moment it was asked for (its lids
    move first, its parts follow).

    The named parts (`parts`, `skin`, `mouth`, `brows`) are a view of numbers: the pictures
    nearest them, which a theme made of pictures shows. Those numbers are `pictured`, where a
    move of the skin, mouth or brows is heading (the pictures change as it begins), or else
    `expression`; during a crossfade the pictures fade from those nearest `pictured_from`
    (`fade_from`), `fade` of the way (0..1).

    Built by hand, a state may still name its parts (`FaceState(mouth="teeth")`,
    `state.replace(fade_from=parts)`, in the order the fields always had): they are turned into
    their numbers, and without an `expression` the drawn face shows them too.
    """

    eye_x: float
    eye_y: float
    eyelids: float
    head_pan: float
    fade: float
    emotion: Optional[str]  # the emotion last asked for, if any: a label, not drawn
    expression: Expression
    mood: Tuple[float, float]  # (valence, arousal) of the last `mood`: the idle life's pace
    pictured: Optional[Expression]  # None: `expression` itself
    pictured_from: Optional[Expression]  # None: no crossfade

    def __init__(
        self,
        skin: Optional[int] = None,
        mouth: Optional[str] = None,
        brows: Optional[str] = None,
        eye_x: float = 0.0,
        eye_y: float = 0.0,
        eyelids: float = 1.0,
        head_pan: float = 0.0,
        fade_from: Optional[Parts] = None,
        fade: float = 1.0,
        emotion: Optional[str] = None,
        expression: Optional[Expression] = None,
        mood: Tuple[float, float] = (0.0, 0.0),
        *,
        pictured: Optional[Expression] = None,
        pictured_from: Optional[Expression] = None,
    ) -> None:
        named = {k: v for k, v in (("skin", skin), ("mouth", mouth), ("brows", brows)) if v is not None}
        if named:
            shown = nearest_parts(pictured or expression) if pictured or expression else Parts()
            pictured = from_parts(shown._replace(**named))
        if fade_from is not None:
            pictured_from = from_parts(Parts(*fade_from))
        if expression is None:  # the numbers of the named parts, as far into their crossfade as it is
            expression = pictured or DEFAULT_FACE
            if pictured_from is not None and fade < 1.0:
                expression = pictured_from.mix(expression, max(0.0, fade))
        if pictured == expression:
            pictured = None
        for name, value in (
            ("eye_x", eye_x),
            ("eye_y", eye_y),
            ("eyelids", eyelids),
            ("head_pan", head_pan),
            ("fade", fade),
            ("emotion", emotion),
            ("expression", expression),
            ("mood", mood),
            ("pictured", pictured),
            ("pictured_from", pictured_from),
        ):
            object.__setattr__(self, name, value)

    @property
    def parts(self) -> Parts:
        """The named parts a theme of pictures shows: the ones nearest the numbers."""
        return nearest_parts(self.expression if self.pictured is None else self.pictured)

    @property
    def fade_from(self) -> Optional[Parts]:
        """The named parts a theme of pictures crossfades from, if it does."""
        return None if self.pictured_from is None else nearest_parts(self.pictured_from)

    @property
    def skin(self) -> int:
        return self.parts.skin

    @property
    def mouth(self) -> str:
        return self.parts.mouth

    @property
    def brows(self) -> str:
        return self.parts.brows

    def replace(self, **changes: Any) -> FaceState:
        if changes.keys() <= _PLAIN:  # nothing is worked out from these: the state copied as is
            state = object.__new__(type(self))
            state.__dict__.update(self.__dict__, **changes)
            return state
        return dataclasses.replace(self, **changes)

    def as_record(self) -> Dict[str, Any]:
        """The state as JSON-ready values, rounded once for every reader: `explain --json`,
        the node's `~state` and the studio's preview all report the face through this."""
        parts, fade_from = self.parts, self.fade_from
        return {
            "skin": parts.skin,
            "mouth": parts.mouth,
            "brows": parts.brows,
            "eye_x": round(self.eye_x, 4),
            "eye_y": round(self.eye_y, 4),
            "eyelids": round(self.eyelids, 4),
            "head_pan": round(self.head_pan, 4),
            "fade_from": list(fade_from) if fade_from else None,
            "fade": round(self.fade, 4),
            "emotion": self.emotion,
            "expression": self.expression.as_record(),
            "mood": [round(v, 4) for v in self.mood],
        }
