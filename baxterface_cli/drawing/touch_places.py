"""Where on the face a tap lands, for `touch left eye`, `touch mouth`, `touch brows`.

Found from the face as it is drawn at that moment, in the renderer's own layers: the mouth and
the brows where their sprites have ink near the tap (a finger is wide, so within `REACH`), an
eye within its socket (where its lid closes) or where its pupil has moved to. The robot's left
eye is the one on the screen's right, as `wink left` says. A page sends only where it was tapped.
"""

from __future__ import annotations

from typing import Optional

from ..core.face_state import FaceState
from ..core.presets import expression_of
from .compositing import Sprite
from .pose import pose
from .theme_fitting import ThemeLayers

REACH = 0.03  # of the screen's height: how near a tap must come to a stroke of the mouth or brows


def touched_place(layers: ThemeLayers, state: FaceState, x: float, y: float) -> str:
    """The place (events.PLACES) at (x, y), fractions of the frame's width and height; "" for
    anywhere else (the skin, the bars around the face)."""
    return TouchMap(layers, state).place(x, y)


class TouchMap:
    """The places of the face as drawn for one state: made where the frame is drawn (reading the
    renderer's parts), read anywhere after (it holds what it needs, and changes nothing)."""

    def __init__(self, layers: ThemeLayers, state: FaceState) -> None:
        self.size = layers.size
        parts = layers.drawn.keys(expression_of(state)) if layers.drawn is not None else state.parts
        self.mouth, self.brows = layers.mouths[parts.mouth], layers.brows[parts.brows]
        self.reach = max(1, round(REACH * self.size[1]))
        at = pose(layers, state)
        self.eyes = []  # (the rects where it is, which eye)
        for i, lid in enumerate(layers.lids):
            eye: Optional[Sprite] = layers.eyes[i] if i < len(layers.eyes) else None
            rects = [lid.rect()] + ([eye.rect(at.eye_dx, at.eye_dy)] if eye is not None else [])
            self.eyes.append((rects, "right eye" if lid.x + lid.width / 2 < self.size[0] / 2 else "left eye"))

    def place(self, x: float, y: float) -> str:
        """The place at (x, y), as `touched_place` says."""
        if not (0.0 <= x <= 1.0 and 0.0 <= y <= 1.0):  # off the frame (NaN too): on no place of it
            return ""
        px, py = x * self.size[0], y * self.size[1]
        if _inked(self.mouth, px, py, self.reach):
            return "mouth"
        if _inked(self.brows, px, py, self.reach):
            return "brows"
        for rects, which in self.eyes:
            if any(x0 <= px < x1 and y0 <= py < y1 for x0, y0, x1, y1 in rects):
                return which
        return ""


def _inked(sprite: Sprite, px: float, py: float, reach: int) -> bool:
    """Does `sprite` draw anything within `reach` pixels of (px, py)?"""
    x0, y0 = int(px) - reach - sprite.x, int(py) - reach - sprite.y
    x1, y1 = x0 + 2 * reach + 1, y0 + 2 * reach + 1
    x0, y0 = max(0, x0), max(0, y0)
    x1, y1 = min(sprite.width, x1), min(sprite.height, y1)
    if x0 >= x1 or y0 >= y1:
        return False
    return bool((sprite.inv[y0:y1, x0:x1, 0] < 255).any())
