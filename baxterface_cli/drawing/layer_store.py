"""The default theme fitted to a screen, kept between runs: a face starts without reading its
pictures.

Reading the default theme's 28 pictures and cutting them into sprites takes about 0.6 s, the
most of what `render` or a node does before its first frame; at a size other than its own the
theme is drawn from its vector shapes, longer still. The fitted layers depend only on the size
and on what the fingerprint of array_cache.py covers, so they are kept in the user's cache and
loaded back in a tenth of the time. A theme of the user's own is always read afresh.
"""

from __future__ import annotations

from typing import Callable, Dict, List, Optional, Tuple

import numpy as np

from .array_cache import Arrays, kept
from .compositing import Sprite
from .theme_fitting import ThemeLayers, with_stand_ins
from .theme_manifest import OPTIONAL

FOLDER = "themes"
KINDS = ("eyes", "lids", "skins", "mouths", "brows")


def kept_layers(size: Tuple[int, int], make: Callable[[], ThemeLayers]) -> ThemeLayers:
    """The default theme at `size`: the layers kept from an earlier run, or `make()`'s, kept."""
    found = kept(FOLDER, "default", size, make, layers_arrays, layers_from_arrays)
    return found if found is not None else make()


def layers_arrays(layers: ThemeLayers) -> Optional[Arrays]:
    """The layers as named arrays, what `layers_from_arrays` takes back; None where a sprite's
    alpha is not one value across its channels (never, for a theme read from pictures)."""
    # A speech mouth the theme lacks is another mouth's sprite: made again on loading.
    mouths = layers.mouths
    stand_ins = {name for (_, name), (_, other) in OPTIONAL.items() if mouths.get(name) is mouths.get(other)}
    own_mouths = {name: sprite for name, sprite in layers.mouths.items() if name not in stand_ins}
    arrays: Arrays = {
        "size": np.array(layers.size, np.int64),
        "scale": np.array(layers.scale, np.float64),
        "lid_travel": np.array(layers.lid_travel, np.int64),
        "lid_bands": np.array(layers.lid_bands, np.int64).reshape(-1, 2),
        "background": layers.background,
    }
    groups: Dict[str, Dict[str, Sprite]] = {
        "eyes": {str(i): s for i, s in enumerate(layers.eyes)},
        "lids": {str(i): s for i, s in enumerate(layers.lids)},
        "skins": {str(n): s for n, s in layers.skins.items()},
        "mouths": own_mouths,
        "brows": dict(layers.brows),
    }
    for kind, sprites in groups.items():
        for name, sprite in sprites.items():
            inv = sprite.inv[..., :1]
            if not np.array_equal(np.broadcast_to(inv, sprite.inv.shape), sprite.inv):
                return None
            arrays[f"{kind}.{name}.at"] = np.array([sprite.x, sprite.y], np.int64)
            arrays[f"{kind}.{name}.rgb_a"] = sprite.rgb_a
            arrays[f"{kind}.{name}.inv"] = inv[..., 0].astype(np.uint8)
    return arrays


def layers_from_arrays(arrays: Arrays) -> ThemeLayers:
    """Layers from `layers_arrays`; ValueError (or KeyError) where they do not make them."""
    w, h = (int(n) for n in arrays["size"])
    background = arrays["background"]
    if background.shape != (h, w, 3) or background.dtype != np.uint8:
        raise ValueError("not a theme's background")
    groups: Dict[str, Dict[str, Sprite]] = {kind: {} for kind in KINDS}
    for key in arrays:
        if key.endswith(".rgb_a"):
            kind, name = key[: -len(".rgb_a")].split(".", 1)
            groups[kind][name] = _sprite(arrays, f"{kind}.{name}")
    eyes, lids = _numbered(groups["eyes"]), _numbered(groups["lids"])
    bands = [(int(a), int(b)) for a, b in arrays["lid_bands"]]
    if not eyes or len(lids) != len(eyes) or len(bands) != len(lids):
        raise ValueError("not a theme's eyes and lids")
    return ThemeLayers(
        size=(w, h),
        scale=float(arrays["scale"]),
        background=background,
        eyes=eyes,
        lids=lids,
        lid_bands=bands,
        lid_travel=int(arrays["lid_travel"]),
        skins={int(n): s for n, s in groups["skins"].items()},
        mouths=with_stand_ins(groups["mouths"]),
        brows=groups["brows"],
    )


def _sprite(arrays: Arrays, prefix: str) -> Sprite:
    x, y = (int(n) for n in arrays[f"{prefix}.at"])
    rgb_a, inv = arrays[f"{prefix}.rgb_a"], arrays[f"{prefix}.inv"]
    if rgb_a.ndim != 3 or rgb_a.shape[2] != 3 or rgb_a.dtype != np.uint16 or inv.shape != rgb_a.shape[:2]:
        raise ValueError(f"not a sprite: {prefix}")
    return Sprite(x, y, rgb_a, np.repeat(inv[..., None], 3, axis=2).astype(np.uint16))


def _numbered(sprites: Dict[str, Sprite]) -> List[Sprite]:
    return [sprites[str(i)] for i in range(len(sprites))]
