"""Face state -> frame: an (h, w, 3) uint8 array in B, G, R order.

A frame is the bottom stack (background, pupils moved by the eye position,
lids moved by their openness) under the top stack (skin, mouth, brows). The
top stack is opaque except in the eye sockets, so:

- the top stack is composited once per combination of parts and kept;
- each combination keeps a canvas, the whole frame as last drawn;
- a new state redraws only the rectangles, inside the sockets, that the
  pupils or the lids could have changed.

`compose(layers, state)` (stacks.py) is the plain full recomposite, with the
same arithmetic; the tests hold the cached path to its exact pixels.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from typing import Any, List, Optional, Tuple

import numpy as np

from ..core.face_state import FaceState, Parts
from ..core.presets import expression_of
from .compositing import Rect, Sprite, finish, intersect
from .pose import (
    LOWER_TRAVEL,
    LidPose,
    Pose,
    eye_sprite,
    lid_pose,
    lid_sprite,
    looking,
    lower_lid_sprite,
    round_half_away,
)
from .stacks import TopStack, bottom_stack, crossfade, skin_stack, socket_boxes, top_stack
from .theme_fitting import ThemeLayers

PARTS_KEPT = 12  # part combinations kept: every emotion's, with room to spare
SKINS_KEPT = 8  # skins kept, each a whole screen: every named one, and some between


class _Canvas:
    """One part combination's frame as last drawn, and what it needs to redraw.

    Built from its skin's stack: outside the sockets, the mouth and the brows
    that stack already holds the final pixels, so only those are composited.
    """

    def __init__(
        self, layers: ThemeLayers, parts: Parts, at: Pose, skin: TopStack, boxes: List[Rect]
    ) -> None:
        self.frame = skin.prem.copy()
        self._paint(layers, parts, at, skin, boxes)

    def reskin(self, layers: ThemeLayers, parts: Parts, at: Pose, skin: TopStack, boxes: List[Rect]) -> None:
        """Become `parts` on another skin, at `at`: drawn as a new canvas is, into this one's frame
        (a morph changes its skin frame after frame; a new frame each time was a whole screen
        allocated and written)."""
        self.frame.flags.writeable = True
        np.copyto(self.frame, skin.prem)
        self._paint(layers, parts, at, skin, boxes)

    def _paint(self, layers: ThemeLayers, parts: Parts, at: Pose, skin: TopStack, boxes: List[Rect]) -> None:
        """Draw the sockets, the mouth and the brows of `parts` over the skin in the frame."""
        w, h = layers.size
        self.skin = skin
        self.boxes = boxes
        self.parts = parts
        self.tops = [top_stack(layers, parts, box, skin) for box in boxes]
        self._showing: List[Optional[np.ndarray]] = [None] * len(boxes)
        for box, top in zip(boxes, self.tops):
            _finish_into(self.frame, box, top, bottom_stack(layers, at, box))
        for sprite in (layers.mouths[parts.mouth], layers.brows[parts.brows]):
            rect = intersect(sprite.rect(), (0, 0, w, h))
            if rect is not None:
                top = top_stack(layers, parts, rect, skin)
                _finish_into(self.frame, rect, top, bottom_stack(layers, at, rect))
        self.frame.flags.writeable = False
        self.at = at

    def repaint(self, layers: ThemeLayers, parts: Parts) -> List[Rect]:
        """Become `parts`, whose skin is this canvas's: redraw where the old or the new mouth
        and brows reach, and the sockets' stacks they touch; returns where the frame changed."""
        screen = (0, 0) + layers.size
        rects = []
        for book, old, new in (
            (layers.mouths, self.parts.mouth, parts.mouth),
            (layers.brows, self.parts.brows, parts.brows),
        ):
            if old != new:
                a, b = book[old].rect(), book[new].rect()
                union = intersect(
                    (min(a[0], b[0]), min(a[1], b[1]), max(a[2], b[2]), max(a[3], b[3])), screen
                )
                if union is not None:
                    rects.append(union)
        self.parts = parts
        self.frame.flags.writeable = True
        for i, box in enumerate(self.boxes):
            if any(intersect(rect, box) is not None for rect in rects):
                self.tops[i] = top_stack(layers, parts, box, self.skin)
                self._showing[i] = None
        for rect in rects:
            _finish_into(
                self.frame,
                rect,
                top_stack(layers, parts, rect, self.skin),
                bottom_stack(layers, self.at, rect),
            )
        self.frame.flags.writeable = False
        return rects

    def clear(self, i: int, rect: Rect) -> bool:
        """Whether socket i's top stack is wholly see-through over `rect` (inside its box):
        there a frame is the bottom stack as it is (div255(under * 255) + 0 is under)."""
        table = self._showing[i]
        if table is None:  # a summed-area table of the pixels where the top stack shows
            top = self.tops[i]
            shows = (top.inv != 255).any(axis=2) | (top.prem != 0).any(axis=2)
            table = np.zeros((shows.shape[0] + 1, shows.shape[1] + 1), np.int32)
            np.cumsum(np.cumsum(shows, axis=0, dtype=np.int32), axis=1, out=table[1:, 1:])
            self._showing[i] = table
        box = self.boxes[i]
        a0, b0, a1, b1 = rect[0] - box[0], rect[1] - box[1], rect[2] - box[0], rect[3] - box[1]
        return int(table[b1, a1] - table[b0, a1] - table[b1, a0] + table[b0, a0]) == 0


def _finish_into(frame: np.ndarray, rect: Rect, top: TopStack, under: np.ndarray) -> None:
    x0, y0, x1, y1 = rect
    finish(top.prem, top.inv, under, out=frame[y0:y1, x0:x1])


def _slid(before: Sprite, lid: Sprite, band: Tuple[int, int], was: int, now: int) -> List[Rect]:
    """Rectangles outside which a lid that slid from `was` to `now` (and maybe became `lid`)
    changes no pixel."""
    if before is not lid:  # another lid: wherever either reaches
        p, q = before.rect(0, was), lid.rect(0, now)
        return [(min(p[0], q[0]), min(p[1], q[1]), max(p[2], q[2]), max(p[3], q[3]))]
    if was == now:
        return []
    low, high = sorted((was, now))
    a, b = band
    # Rows inside the lid's band of identical rows, at both offsets, show the same colours:
    # only the two stretches outside change.
    top, bottom = lid.y + high + a, lid.y + low + b
    x0, x1 = lid.x, lid.x + lid.width
    if top < bottom:
        return [(x0, lid.y + low, x1, top), (x0, bottom, x1, lid.y + high + lid.height)]
    return [(x0, lid.y + low, x1, lid.y + high + lid.height)]


class Renderer:
    """Turns face states into frames, redrawing only what moved.

    `render` returns a read-only view of a buffer the renderer reuses: it is
    valid until the next call. Copy it (`frame.copy()`) to keep it. After a
    render, `changed` says where its frame differs from the one the render
    before returned, when both are the same buffer: rectangles outside which no
    pixel changed ([] for none); None where that is not known (another buffer,
    or the whole screen). `renders` counts the renders.
    """

    def __init__(self, layers: ThemeLayers) -> None:
        self.layers = layers
        self._canvases: OrderedDict[Parts, _Canvas] = OrderedDict()
        self._skins: OrderedDict[Any, Tuple[TopStack, List[Rect]]] = OrderedDict()
        self._mix: Optional[np.ndarray] = None
        self._moving: Optional[_Canvas] = None  # the drawn face between its presets
        self._sockets: OrderedDict[Any, List[Rect]] = OrderedDict()  # by the eyes' sizes
        self.renders = 0
        self.changed: Optional[List[Rect]] = None
        self._dirty: Optional[List[Rect]] = None  # where this render has drawn, as it goes
        self._last: Optional[np.ndarray] = None  # what the render before returned
        self._lids: Tuple[Any, LidPose] = (None, ())  # the last state's eyelids and expression, their lids

    @property
    def size(self) -> Tuple[int, int]:
        return self.layers.size

    def prepare_in_background(self, after: float = 5.0) -> None:
        """Make, off this thread and `after` seconds from now, what the drawn face's first skin
        between two named ones and its first eye of another size need (palettes: two seconds
        of work the first time, then loaded from the user's cache, palette_store.py): a live
        face's first mood or `eyes 1.1` then shows at once. Later rather than at once, so that
        starting a face stays quick; until then, the first asks for them."""
        drawn = self.layers.drawn
        if drawn is not None:

            def prepare() -> None:
                drawn.palette()
                drawn.eye_sizes.prepare()

            timer = threading.Timer(after, prepare)
            timer.name, timer.daemon = "baxterface-palette", True
            timer.start()

    def frame_key(self, state: FaceState) -> Any:
        """A value equal for two states exactly when their frames are the same: a sink that
        sends only changed frames compares these instead of drawing."""
        at = self._pose(state)
        if self.layers.drawn is not None:
            return (at, self.layers.drawn.keys(expression_of(state)))
        fading = state.fade_from is not None and state.fade < 1.0
        return (
            at,
            state.parts,
            state.fade_from if fading else None,
            int(state.fade * 255 + 0.5) if fading else 255,
        )

    def _pose(self, state: FaceState) -> Pose:
        """`pose(self.layers, state)`, its lids those of the state before when its eyelids and
        expression are (a look moves the eyes alone)."""
        key = (state.eyelids, state.expression)
        if key != self._lids[0]:
            self._lids = (key, lid_pose(self.layers, state))
        return looking(self.layers, state, self._lids[1])

    def render(self, state: FaceState) -> np.ndarray:
        self._dirty = []
        frame = self._render(state)
        self.changed = self._dirty if frame is self._last else None
        self._last, self._dirty = frame, None
        self.renders += 1
        return frame

    def _render(self, state: FaceState) -> np.ndarray:
        at = self._pose(state)
        if self.layers.drawn is not None:
            return self._draw(self.layers.drawn.keys(expression_of(state)), at)
        if state.fade_from is None or state.fade >= 1.0:
            return self._draw(state.parts, at)
        if state.fade <= 0.0:
            return self._draw(state.fade_from, at)
        old = self._draw(state.fade_from, at)
        new = self._draw(state.parts, at)
        if self._mix is None:
            self._mix = np.empty_like(new)
        mix = self._mix
        mix.flags.writeable = True
        self._dirty = None  # the mix is drawn anew, whatever its canvases redrew
        if state.fade_from.skin == state.skin:
            # Same skin, same pose: the frames differ only where a mouth or
            # brows of either side reach; elsewhere the blend is the frame.
            np.copyto(mix, new)
            for x0, y0, x1, y1 in self._part_rects(state.fade_from, state.parts):
                crossfade(old[y0:y1, x0:x1], new[y0:y1, x0:x1], state.fade, mix[y0:y1, x0:x1])
        else:
            crossfade(old, new, state.fade, mix)
        mix.flags.writeable = False
        return mix

    def _part_rects(self, *parts: Parts) -> List[Rect]:
        screen = (0, 0) + self.layers.size
        sprites = [self.layers.mouths[p.mouth] for p in parts] + [self.layers.brows[p.brows] for p in parts]
        return [r for r in (intersect(s.rect(), screen) for s in sprites) if r is not None]

    def _canvas(self, parts: Parts, at: Pose) -> _Canvas:
        canvas = self._canvases.get(parts)
        if canvas is not None:
            self._canvases.move_to_end(parts)
            return canvas
        drawn = self.layers.drawn
        if drawn is not None and not drawn.named(parts):
            return self._morphing(parts, at)
        canvas = _Canvas(self.layers, parts, at, *self._skin(parts.skin))
        self._canvases[parts] = canvas
        while len(self._canvases) > PARTS_KEPT:
            self._canvases.popitem(last=False)
        return canvas

    def _skin(self, key: Any) -> Tuple[TopStack, List[Rect]]:
        """A skin's stack and socket boxes: a named one's kept, one between them mixed."""
        drawn = self.layers.drawn
        stacked = None if drawn is None else drawn.skin_stacked(key)
        if stacked is not None:  # between the named skins
            prem, inv = stacked
            if inv is None:  # their outline, so their sockets
                named = self._skin(next(iter(self.layers.skins)))
                return TopStack(prem, named[0].inv), named[1]
            if key.eyes not in self._sockets:  # eyes of other sizes: sockets of their own
                self._sockets[key.eyes] = socket_boxes(inv)
                while len(self._sockets) > SKINS_KEPT:
                    self._sockets.popitem(last=False)
            return TopStack(prem, inv), self._sockets[key.eyes]
        if key not in self._skins:
            skin = skin_stack(self.layers, key)
            self._skins[key] = (skin, socket_boxes(skin.inv))
            while len(self._skins) > SKINS_KEPT:
                self._skins.popitem(last=False)
        self._skins.move_to_end(key)
        return self._skins[key]

    def _morphing(self, parts: Parts, at: Pose) -> _Canvas:
        """The drawn face between its presets: one canvas, changed where the parts changed
        (a morph moves the mouth, the brows or the skin a little, frame after frame)."""
        canvas = self._moving
        if canvas is None:
            canvas = self._moving = _Canvas(self.layers, parts, at, *self._skin(parts.skin))
        elif canvas.parts.skin != parts.skin:
            canvas.reskin(self.layers, parts, at, *self._skin(parts.skin))
            self._dirty = None  # every pixel
        elif canvas.parts != parts:
            self._drew(canvas.repaint(self.layers, parts))
        return canvas

    def _draw(self, parts: Parts, at: Pose) -> np.ndarray:
        canvas = self._canvas(parts, at)
        if canvas.at != at:
            canvas.frame.flags.writeable = True
            for rect in self._changed(canvas.at, at):
                for i, (box, top) in enumerate(zip(canvas.boxes, canvas.tops)):
                    hit = intersect(rect, box)
                    if hit is not None:
                        self._redraw(canvas, hit, box, top, at, canvas.clear(i, hit))
                        self._drew([hit])
            canvas.frame.flags.writeable = False
            canvas.at = at
        return canvas.frame

    def _drew(self, rects: List[Rect]) -> None:
        if self._dirty is not None:
            self._dirty.extend(rects)

    def _changed(self, old: Pose, new: Pose) -> List[Rect]:
        """Rectangles outside which a move from `old` to `new` changes no pixel."""
        rects: List[Rect] = []
        moved = (old.eye_dx, old.eye_dy) != (new.eye_dx, new.eye_dy)
        # A pupil's sprite is its size, a lid's its eye's tilt and size: where those and their
        # places are kept, nothing of them changed (a look moves the pupils only).
        if moved or old.pupils != new.pupils:
            for i in range(len(self.layers.eyes)):
                before, after = eye_sprite(self.layers, old, i), eye_sprite(self.layers, new, i)
                if moved or before is not after:
                    a, b = before.rect(old.eye_dx, old.eye_dy), after.rect(new.eye_dx, new.eye_dy)
                    rects.append((min(a[0], b[0]), min(a[1], b[1]), max(a[2], b[2]), max(a[3], b[3])))
        if (old.lid_dy, old.tilts, old.sizes) != (new.lid_dy, new.tilts, new.sizes):
            for i, (was, now) in enumerate(zip(old.lid_dy, new.lid_dy)):
                before, _ = lid_sprite(self.layers, old, i)
                lid, band = lid_sprite(self.layers, new, i)
                rects += _slid(before, lid, band, was, now)
        if (old.lower_dy, old.sizes) == (new.lower_dy, new.sizes):
            return rects
        if old.lower_dy or new.lower_dy:  # none drawn is the same as sunk out of sight
            sunk = (round_half_away(LOWER_TRAVEL * self.layers.scale),) * 2
            for i, (was, now) in enumerate(zip(old.lower_dy or sunk, new.lower_dy or sunk)):
                before, _ = lower_lid_sprite(self.layers, old, i)
                lid, band = lower_lid_sprite(self.layers, new, i)
                rects += _slid(before, lid, band, was, now)
        return rects

    def _redraw(
        self, canvas: _Canvas, rect: Rect, box: Rect, top: TopStack, at: Pose, clear: bool = False
    ) -> None:
        x0, y0, x1, y1 = rect
        under = bottom_stack(self.layers, at, rect)
        if clear:  # nothing of the top stack over it: the bottom stack is the frame
            np.copyto(canvas.frame[y0:y1, x0:x1], under, casting="unsafe")
            return
        inside = (slice(y0 - box[1], y1 - box[1]), slice(x0 - box[0], x1 - box[0]))
        finish(top.prem[inside], top.inv[inside], under, out=canvas.frame[y0:y1, x0:x1])
