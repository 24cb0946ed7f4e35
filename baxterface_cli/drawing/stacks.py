"""The face's two stacks, and `compose`: the plain full recomposite the renderer is held to.

A frame is the bottom stack (background, pupils moved by the eye position, lids moved by their
openness) under the top stack (skin, mouth, brows), which is opaque but in the eye sockets.
`compose(layers, state)` builds both from scratch for every pixel, with the same arithmetic as
renderer.py's kept canvases; the tests hold the renderer to its exact pixels.
"""

from __future__ import annotations

from typing import List, NamedTuple, Optional

import numpy as np

from ..core.face_state import FaceState, Parts
from ..core.presets import expression_of
from .compositing import Rect, Sprite, div255, div255_inplace, finish, intersect, lay
from .drawn_parts import EYE_STEPS
from .pose import Pose, eye_sprite, lid_sprite, lower_lid_sprite, pose
from .theme_fitting import ThemeLayers


class TopStack(NamedTuple):
    """Skin, mouth and brows composited: premultiplied colour and 255 - alpha."""

    prem: np.ndarray  # (h, w, 3) uint16 (uint8 in a kept skin stack)
    inv: np.ndarray  # (h, w, 3) uint16 (h, w, 1 uint8 in a kept skin stack)


def top_stack(
    layers: ThemeLayers, parts: Parts, rect: Optional[Rect] = None, skin: Optional[TopStack] = None
) -> TopStack:
    """The top stack over `rect` (the whole screen by default).

    `skin`, if given, is the skin alone already stacked over the whole screen
    (see `skin_stack`); the result is the same, the work smaller.
    """
    w, h = layers.size
    rect = rect or (0, 0, w, h)
    shape = (rect[3] - rect[1], rect[2] - rect[0])
    sprites = [layers.mouths[parts.mouth], layers.brows[parts.brows]]
    if skin is not None:
        x0, y0, x1, y1 = rect
        prem = skin.prem[y0:y1, x0:x1].astype(np.uint16)
        inv = np.repeat(skin.inv[y0:y1, x0:x1], 3, axis=2).astype(np.uint16)
    else:
        prem = np.zeros(shape + (3,), np.uint16)
        inv = np.full(shape + (3,), 255, np.uint16)
        sprites.insert(0, layers.skins[parts.skin])
    return _stack(rect, sprites, prem, inv)


def _stack(rect: Rect, sprites: List[Sprite], prem: np.ndarray, inv: np.ndarray) -> TopStack:
    """Lay `sprites` in order over the top stack (prem, inv) that covers `rect`."""
    for sprite in sprites:
        hit = intersect(rect, sprite.rect())
        if hit is None:
            continue
        lay(prem, rect, sprite)
        x0, y0, x1, y1 = hit
        src = (slice(y0 - sprite.y, y1 - sprite.y), slice(x0 - sprite.x, x1 - sprite.x))
        out = (slice(y0 - rect[1], y1 - rect[1]), slice(x0 - rect[0], x1 - rect[0]))
        inv[out] = div255(inv[out] * sprite.inv[src])
    return TopStack(prem, inv)


def skin_stack(layers: ThemeLayers, skin: int) -> TopStack:
    """A skin alone as a top stack over the whole screen, kept as uint8 (it fits)."""
    w, h = layers.size
    prem, inv = np.zeros((h, w, 3), np.uint16), np.full((h, w, 3), 255, np.uint16)
    top = _stack((0, 0, w, h), [layers.skins[skin]], prem, inv)
    # Kept as uint8, and with one alpha channel: this is the big cache.
    return TopStack(top.prem.astype(np.uint8), top.inv[..., :1].astype(np.uint8))


def bottom_stack(layers: ThemeLayers, at: Pose, rect: Rect) -> np.ndarray:
    """Background, pupils and lids over `rect`, as uint16 colour."""
    x0, y0, x1, y1 = rect
    under = layers.background[y0:y1, x0:x1].astype(np.uint16)
    for i, size in enumerate(at.sizes):
        if size != EYE_STEPS:  # a white shaded to the rim of a socket of another size
            box, white = layers.drawn.white(i, size)  # type: ignore[union-attr]
            hit = intersect(rect, box)
            if hit is not None:
                a0, b0, a1, b1 = hit
                under[b0 - y0 : b1 - y0, a0 - x0 : a1 - x0] = white[
                    b0 - box[1] : b1 - box[1], a0 - box[0] : a1 - box[0]
                ]
    for i in range(len(layers.eyes)):
        lay(under, rect, eye_sprite(layers, at, i), at.eye_dx, at.eye_dy)
    for i, dy in enumerate(at.lower_dy):
        lay(under, rect, lower_lid_sprite(layers, at, i)[0], 0, dy)
    for i, dy in enumerate(at.lid_dy):
        lay(under, rect, lid_sprite(layers, at, i)[0], 0, dy)
    return under


def compose(layers: ThemeLayers, state: FaceState) -> np.ndarray:
    """The plain full recomposite: every layer, every pixel, nothing kept."""
    full = (0, 0) + layers.size
    if layers.drawn is not None:  # a drawn face morphs its numbers: no frames to crossfade
        top = top_stack(layers, layers.drawn.keys(expression_of(state)))
        return finish(top.prem, top.inv, bottom_stack(layers, pose(layers, state), full))

    def frame(parts: Parts) -> np.ndarray:
        top = top_stack(layers, parts)  # every layer from scratch
        return finish(top.prem, top.inv, bottom_stack(layers, pose(layers, state), full))

    if state.fade_from is None or state.fade >= 1.0:
        return frame(state.parts)
    if state.fade <= 0.0:
        return frame(state.fade_from)
    return crossfade(frame(state.fade_from), frame(state.parts), state.fade)


def crossfade(a: np.ndarray, b: np.ndarray, fade: float, out: Optional[np.ndarray] = None) -> np.ndarray:
    """`fade` of the way from frame a to frame b, in 1/255 steps."""
    w = int(fade * 255 + 0.5)
    mixed = a.astype(np.uint16)
    mixed *= np.uint16(255 - w)
    other = b.astype(np.uint16)
    other *= np.uint16(w)
    mixed += other
    div255_inplace(mixed)
    if out is None:
        return mixed.astype(np.uint8)
    np.copyto(out, mixed, casting="unsafe")
    return out


def socket_boxes(inv: np.ndarray) -> List[Rect]:
    """Boxes round the see-through parts of a top stack, one per socket.

    Outside them the top stack is opaque, so nothing below ever shows there.
    """
    see_through = inv[..., 0] > 0
    cols = see_through.any(axis=0)
    boxes, start = [], None
    for x, on in enumerate(list(cols) + [False]):
        if on and start is None:
            start = x
        elif not on and start is not None:
            rows = np.flatnonzero(see_through[:, start:x].any(axis=1))
            boxes.append((start, int(rows[0]), x, int(rows[-1]) + 1))
            start = None
    return boxes
