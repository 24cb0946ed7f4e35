"""`Face`: the face as a Python object, for any program or ROS node.

from baxterface_cli import Face
face = Face()
face.set_emotion("happy")
face.look_at(40, -20)
frame = face.frame()        # (600, 1024, 3) uint8, B, G, R: ready for cv_bridge
"""

from __future__ import annotations

import math
import random
import sys
from pathlib import Path
from typing import List, Mapping, Optional, Tuple, Union

import numpy as np
from PIL import Image

from ..core.expression import Expression
from ..core.face_constants import BROWS, EMOTIONS, MOUTHS, SKINS
from ..core.face_state import FaceState
from ..core.geometry import clamp_pan, clamp_to_ellipse
from ..core.presets import mood_weights
from ..engine.compiler import compile_script
from ..language import syntax_tree as n
from ..language.diagnostics import did_you_mean
from .renderer import Renderer
from .theme import Theme, resolve
from .theme_manifest import check_size


def finished(state: FaceState, *statements: n.Statement) -> FaceState:
    """`state` as these statements leave it, run by the engine that runs scripts, with cuts for
    crossfades: the face a script would show once they are done."""
    timeline = compile_script(n.Script(tuple(statements)), start=state, crossfade=0.0)
    return timeline.sample(timeline.duration)


def emotion_variants(name: str) -> List[Tuple[str, str]]:
    """The (mouth, brows) pairs of emotion `name`, in the order `set_emotion`'s `variant` counts them."""
    return list(EMOTIONS[_check(name.replace("_", " "), tuple(EMOTIONS), "emotion")].variants)


def _check(value: str, choices: Tuple[str, ...], what: str) -> str:
    name = str(value).lower()
    if name not in choices:
        hint = did_you_mean(name, choices) or f"; use one of {', '.join(choices)}"
        raise ValueError(f"unknown {what} {value!r}{hint}")
    return name


def _finite(value: float, what: str) -> float:
    number = float(value)
    if not math.isfinite(number):
        raise ValueError(f"{what} must be a finite number, not {value!r}")
    return number


class Face:
    """A face you set part by part and draw on demand.

    Setters take effect at once: an emotion, a blend or a named part is the statement a script
    would write, run to its end by the same engine (animation is the timeline's job);
    `frame()` draws the current state, redrawing only what changed since the last frame.
    """

    def __init__(
        self, theme: Union[None, str, Path, Theme] = None, size: Tuple[int, int] = (1024, 600)
    ) -> None:
        self.theme = resolve(theme)
        self.size = (int(size[0]), int(size[1]))
        check_size(self.size)
        self._renderer = Renderer(self.theme.layers(self.size))
        self.state = FaceState()
        self._kept: Optional[np.ndarray] = None  # the last frame given, and the render it is
        self._kept_at = -1
        probe = np.empty(0)
        self._alone = sys.getrefcount(probe)  # the count of an array held by one name only

    # -- moving

    def look_at(self, x: float, y: float) -> Tuple[float, float]:
        """Put the eyes at (x, y), clamped to the eye ellipse; returns where they went."""
        x, y = clamp_to_ellipse(_finite(x, "x"), _finite(y, "y"))
        self.state = self.state.replace(eye_x=x, eye_y=y)
        return x, y

    def set_eyelids(self, openness: float) -> None:
        """0 closed .. 1 open."""
        if not 0.0 <= _finite(openness, "eyelid openness") <= 1.0:
            raise ValueError(f"eyelid openness must be from 0 to 1, not {openness}")
        self.state = self.state.replace(eyelids=float(openness))

    def set_head_pan(self, radians: float) -> None:
        """Record the head pan, clamped to +-1.5 rad (the robot turns; the screen does not show it)."""
        pan = _finite(radians, "head pan")
        self.state = self.state.replace(head_pan=clamp_pan(pan))

    # -- parts

    def set_emotion(
        self, name: str, variant: Optional[int] = None, rng: Optional[random.Random] = None
    ) -> None:
        """Show an emotion (or "sleep", "wake up"); `variant` picks its mouth and brows, else `rng` does."""
        key = _check(name.replace("_", " "), tuple(EMOTIONS), "emotion")
        choices = EMOTIONS[key].variants
        if variant is None:
            variant = (rng or random).randrange(len(choices))
        if not 0 <= variant < len(choices):
            raise ValueError(f"{key} has {len(choices)} variants (0 to {len(choices) - 1}), not {variant}")
        self.state = finished(self.state, n.Emotion(key, variant=variant + 1))

    def set_skin(self, index: int) -> None:
        if isinstance(index, bool) or index not in SKINS:
            raise ValueError(f"skin must be from {min(SKINS)} to {max(SKINS)}, not {index}")
        self.state = finished(self.state, n.Skin(int(index)))

    def set_mouth(self, name: str) -> None:
        self.state = finished(self.state, n.Mouth(_check(name, MOUTHS, "mouth")))

    def set_brows(self, name: str) -> None:
        self.state = finished(self.state, n.Brows(_check(name, BROWS, "brows")))

    # -- the continuous face

    @property
    def expression(self) -> Expression:
        """The numbers the face is drawn from (core/expression.py), whatever set them."""
        return self.state.expression

    def set_expression(self, expression: Optional[Expression] = None, **numbers: float) -> None:
        """Draw the face from these numbers: an `Expression`, and/or fields of one by name
        (`set_expression(mouth_curve=-0.5, brow_left_angle=0.6)` changes those, keeps the rest).
        Themes of pictures show the nearest named parts (`face.state.parts`)."""
        unknown = sorted(set(numbers) - set(Expression._fields))
        if unknown:
            raise ValueError(
                f"unknown expression number {unknown[0]!r}{did_you_mean(unknown[0], Expression._fields)}"
            )
        shown = (expression or self.expression)._replace(**{k: _finite(v, k) for k, v in numbers.items()})
        self.state = self.state.replace(expression=shown, pictured=None, pictured_from=None, fade=1.0)

    def blend(self, weights: Mapping[str, float], variant: int = 0) -> None:
        """Show emotions at intensities, blended: `face.blend({"happy": 0.6, "confused": 0.4})`.
        One emotion at weight w is that emotion at intensity w; weight 0 is the default face."""
        named = []
        for name, weight in weights.items():
            key = _check(name.replace("_", " "), tuple(EMOTIONS), "emotion")
            if not 0.0 <= _finite(weight, f"{key}'s weight") <= 1.0:
                raise ValueError(f"a weight must be from 0 to 1, not {weight}")
            named.append((key, float(weight)))
        if sum(w for _, w in named) > 1.0 + 1e-9:
            raise ValueError("the weights of a blend add up to at most 1")
        if not named:
            named = [("default", 1.0)]  # weight 0: the default face
        variants = tuple(min(variant, len(EMOTIONS[k].variants) - 1) + 1 for k, _ in named)
        self.state = finished(self.state, n.Feeling(tuple(named), variants=variants))  # a wink stays

    def set_emotion_intensity(self, name: str, intensity: float, variant: int = 0) -> None:
        """An emotion part of the way from the default face: 1 is `set_emotion`, 0 `default`."""
        self.blend({name: intensity}, variant)

    def set_mood(self, valence: float, arousal: float, variant: int = 0) -> None:
        """A place on the mood circle, each -1..1: the two nearest emotions blended, stronger
        toward the edge (see docs/language.md, "Mood")."""
        for value, what in ((valence, "valence"), (arousal, "arousal")):
            if not -1.0 <= _finite(value, what) <= 1.0:
                raise ValueError(f"{what} must be from -1 to 1, not {value}")
        self.blend(dict(mood_weights(float(valence), float(arousal))) or {"default": 1.0}, variant)
        self.state = self.state.replace(mood=(float(valence), float(arousal)))

    def wink(self, side: Optional[str] = "left") -> None:
        """Shut one eye, the robot's `left` (the viewer's right) or `right`; None opens both."""
        if side is None:
            self.set_expression(lid_left=1.0, lid_right=1.0)
            return
        self.set_expression(**{f"lid_{_check(side, ('left', 'right'), 'side')}": 0.0})

    # -- drawing

    def frame(self) -> np.ndarray:
        """The current face as an (h, w, 3) uint8 array, bytes in B, G, R order: read-only, and
        yours: the face never changes it while you hold it (`frame().copy()` to draw on it).

        The array of the frame before is used again once nothing holds it, and then only what
        changed since is copied into it, not the whole screen."""
        renderer = self._renderer
        drawn = renderer.render(self.state)
        kept, self._kept = self._kept, None
        if kept is None or sys.getrefcount(kept) > self._alone or kept.flags.writeable:
            kept = drawn.copy()  # the one before is still held (or was made writable): a new one
        else:
            kept.flags.writeable = True
            if renderer.changed is None or renderer.renders != self._kept_at + 1:
                np.copyto(kept, drawn)
            else:
                for x0, y0, x1, y1 in renderer.changed:
                    kept[y0:y1, x0:x1] = drawn[y0:y1, x0:x1]
        kept.flags.writeable = False
        self._kept, self._kept_at = kept, renderer.renders
        return kept

    def frame_rgb(self) -> np.ndarray:
        """The current face as a new (h, w, 3) uint8 array in R, G, B order."""
        return np.ascontiguousarray(self._renderer.render(self.state)[..., ::-1])

    def image(self) -> Image.Image:
        """The current face as a PIL image (RGB)."""
        return Image.fromarray(self.frame_rgb(), "RGB")
