"""A theme fitted to one screen: its layers scaled, placed and cut into sprites for the renderer."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Dict, List, NamedTuple, Optional, Tuple

import numpy as np
from PIL import Image

from . import artwork
from .compositing import Sprite, alike_rows, split_columns, sprite_from_rgba
from .theme_manifest import FULL_SCREEN_KINDS, OPTIONAL, Key, Placed, Size

if TYPE_CHECKING:
    from .drawn_parts import DrawnParts


class ThemeLayers(NamedTuple):
    """A theme fitted to one screen size, ready for the renderer (B, G, R order)."""

    size: Size
    scale: float  # screen pixels per face pixel
    background: np.ndarray  # (h, w, 3) uint8
    eyes: List[Sprite]  # one per eye, at rest
    lids: List[Sprite]  # one per eye, closed
    lid_bands: List[Tuple[int, int]]  # rows [a, b) of each lid that are all alike
    lid_travel: int  # pixels from closed to open
    skins: Dict[int, Sprite]
    mouths: Dict[str, Sprite]
    brows: Dict[str, Sprite]
    # The default theme draws its parts from the expression's numbers (then skins, mouths and
    # brows are its PartBooks); a theme of pictures has None here.
    drawn: Optional[DrawnParts] = None


def face_scale(size: Size) -> float:
    return min(size[0] / artwork.FACE_SIZE[0], size[1] / artwork.FACE_SIZE[1])


def face_origin(size: Size) -> Tuple[float, float]:
    s = face_scale(size)
    return (size[0] - artwork.FACE_SIZE[0] * s) / 2.0, (size[1] - artwork.FACE_SIZE[1] * s) / 2.0


def resample(placed: Placed, kind: str, native: Size, size: Size) -> Placed:
    k = face_scale(size) / face_scale(native)
    (nx, ny), (tx, ty) = face_origin(native), face_origin(size)
    image = placed.image
    w, h = max(1, round(image.width * k)), max(1, round(image.height * k))
    # Resize premultiplied, so transparent pixels do not bleed dark fringes.
    scaled = image.convert("RGBa").resize((w, h), Image.LANCZOS).convert("RGBA")
    x = round(tx + (placed.anchor[0] - nx) * k)
    y = round(ty + (placed.anchor[1] - ny) * k)
    if kind in FULL_SCREEN_KINDS:  # fill any letterbox with the edge colours
        canvas = np.asarray(scaled)
        pad = ((max(0, y), max(0, size[1] - y - h)), (max(0, x), max(0, size[0] - x - w)), (0, 0))
        full = np.pad(canvas, pad, mode="edge")[: size[1], : size[0]]
        return Placed(Image.fromarray(np.ascontiguousarray(full), "RGBA"), (0, 0))
    return Placed(scaled, (x, y))


def _full_canvas(placed: Placed, size: Size) -> np.ndarray:
    """The layer on a transparent screen-sized RGBA array, clipped to the screen."""
    out = np.zeros((size[1], size[0], 4), np.uint8)
    image = np.asarray(placed.image)
    x, y = placed.anchor
    x0, y0 = max(0, x), max(0, y)
    x1, y1 = min(size[0], x + image.shape[1]), min(size[1], y + image.shape[0])
    if x0 < x1 and y0 < y1:
        out[y0:y1, x0:x1] = image[y0 - y : y1 - y, x0 - x : x1 - x]
    return out


def _sprite(placed: Placed, size: Size) -> Sprite:
    sprite = sprite_from_rgba(_full_canvas(placed, size))
    if sprite is None:  # an empty layer: one transparent pixel keeps the code simple
        zero = np.zeros((1, 1, 3), np.uint16)
        return Sprite(0, 0, zero, np.full((1, 1, 3), 255, np.uint16))
    return sprite


def prepare_layers(placed: Dict[Key, Placed], size: Size, lid_travel: float) -> ThemeLayers:
    scale = face_scale(size)
    background = _full_canvas(placed[("background", "background")], size)[..., 2::-1].copy()
    eyes = split_columns(_sprite(placed[("eyes", "eyes")], size))
    lids = split_columns(_sprite(placed[("eyelids", "eyelids")], size))
    return ThemeLayers(
        size=size,
        scale=scale,
        background=background,
        eyes=eyes,
        lids=lids,
        lid_bands=[alike_rows(lid) for lid in lids],
        lid_travel=int(math.floor(lid_travel * scale + 0.5)),
        skins={int(n): _sprite(p, size) for (k, n), p in placed.items() if k == "skin"},
        mouths=with_stand_ins({n: _sprite(p, size) for (k, n), p in placed.items() if k == "mouth"}),
        brows={n: _sprite(p, size) for (k, n), p in placed.items() if k == "brows"},
    )


def with_stand_ins(mouths: Dict[str, Sprite]) -> Dict[str, Sprite]:
    """Every mouth the renderer may be asked for: a speech mouth the theme lacks is the
    mouth face_constants.VISEMES gives for it (the same sprite, shared)."""
    for (_, name), (_, other) in OPTIONAL.items():
        if name not in mouths and other in mouths:
            mouths[name] = mouths[other]
    return mouths
