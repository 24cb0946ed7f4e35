"""The face at one instant: an immutable value that the renderer turns into a frame."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Dict, NamedTuple, Optional, Tuple

from .expression import Expression


class Parts(NamedTuple):
    """The parts that change by swapping, not by moving."""

    skin: int = 2
    mouth: str = "smile"
    brows: str = "normal"


@dataclass(frozen=True)
class FaceState:
    """Everything a frame depends on, plus the head pan the robot shows.

    Eye coordinates are pixels of the 1024x600 face (x right, y down), eyelid
    openness runs from 0 (closed) to 1 (open), for both eyes (`expression` may give each eye a
    share of it). During a crossfade, `fade_from`
    holds the parts being left and `fade` how far the change has gone (0..1).
    `emotion` names the emotion the face shows from the moment it was asked
    for (its lids move first, its parts follow).
    """

    skin: int = 2
    mouth: str = "smile"
    brows: str = "normal"
    eye_x: float = 0.0
    eye_y: float = 0.0
    eyelids: float = 1.0
    head_pan: float = 0.0
    fade_from: Optional[Parts] = None
    fade: float = 1.0
    emotion: Optional[str] = None  # the emotion last asked for, if any: a label, not drawn
    # The shape the default theme draws (core/expression.py). None: the named parts' presets,
    # crossfaded as `fade` says; themes of pictures show the named parts either way.
    expression: Optional[Expression] = None
    mood: Tuple[float, float] = (0.0, 0.0)  # (valence, arousal) of the last `mood`: the idle life's pace

    @property
    def parts(self) -> Parts:
        return Parts(self.skin, self.mouth, self.brows)

    def with_parts(self, parts: Parts) -> FaceState:
        return replace(self, skin=parts.skin, mouth=parts.mouth, brows=parts.brows)

    def replace(self, **changes: Any) -> FaceState:
        return replace(self, **changes)

    def as_record(self) -> Dict[str, Any]:
        """The state as JSON-ready values, rounded once for every reader: `explain --json`,
        the node's `~state` and the studio's preview all report the face through this."""
        return {
            "skin": self.skin,
            "mouth": self.mouth,
            "brows": self.brows,
            "eye_x": round(self.eye_x, 4),
            "eye_y": round(self.eye_y, 4),
            "eyelids": round(self.eyelids, 4),
            "head_pan": round(self.head_pan, 4),
            "fade_from": list(self.fade_from) if self.fade_from else None,
            "fade": round(self.fade, 4),
            "emotion": self.emotion,
            "expression": None if self.expression is None else self.expression.as_record(),
            "mood": [round(v, 4) for v in self.mood],
        }
