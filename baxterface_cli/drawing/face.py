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
from pathlib import Path
from typing import List, Optional, Tuple, Union

import numpy as np
from PIL import Image

from ..core.face_state import FaceState
from ..core.geometry import clamp_pan, clamp_to_ellipse
from ..core.tables import BROWS, EMOTIONS, MOUTHS, SKINS
from ..language.diagnostics import did_you_mean
from .renderer import Renderer
from .theme import Theme, resolve
from .theme_manifest import check_size


def emotion_state(state: FaceState, name: str, variant: int) -> FaceState:
    """`state` showing emotion `name` with its `variant`-th (mouth, brows) pair."""
    spec = EMOTIONS[name]
    mouth, brows = spec.variants[variant]
    return state.replace(skin=spec.skin, mouth=mouth, brows=brows, eyelids=spec.eyelids, fade_from=None)


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

    Setters take effect at once (animation is the timeline engine's job);
    `frame()` draws the current state, redrawing only what changed since the
    last frame.
    """

    def __init__(
        self, theme: Union[None, str, Path, Theme] = None, size: Tuple[int, int] = (1024, 600)
    ) -> None:
        self.theme = resolve(theme)
        self.size = (int(size[0]), int(size[1]))
        check_size(self.size)
        self._renderer = Renderer(self.theme.layers(self.size))
        self.state = FaceState()

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
        self.state = emotion_state(self.state, key, variant)

    def set_skin(self, index: int) -> None:
        if isinstance(index, bool) or index not in SKINS:
            raise ValueError(f"skin must be from {min(SKINS)} to {max(SKINS)}, not {index}")
        self.state = self.state.replace(skin=int(index))

    def set_mouth(self, name: str) -> None:
        self.state = self.state.replace(mouth=_check(name, MOUTHS, "mouth"))

    def set_brows(self, name: str) -> None:
        self.state = self.state.replace(brows=_check(name, BROWS, "brows"))

    # -- drawing

    def frame(self) -> np.ndarray:
        """The current face as a new (h, w, 3) uint8 array, bytes in B, G, R order."""
        return self._renderer.render(self.state).copy()

    def frame_rgb(self) -> np.ndarray:
        """The current face as a new (h, w, 3) uint8 array in R, G, B order."""
        return np.ascontiguousarray(self._renderer.render(self.state)[..., ::-1])

    def image(self) -> Image.Image:
        """The current face as a PIL image (RGB)."""
        return Image.fromarray(self.frame_rgb(), "RGB")
