"""Palettes kept between runs: a face that starts again has its mixed skins at once.

The drawn face's palettes (skin_mixing.py: the whole skin's, and each eye's for eyes of other
sizes) take about two seconds to make; they are kept in the user's cache (array_cache.py) and
loaded back in milliseconds.
"""

from __future__ import annotations

from typing import Callable, Optional, Tuple

from .array_cache import kept
from .skin_mixing import SkinPalette

FOLDER = "palettes"


def kept_palette(
    name: str, size: Tuple[int, int], make: Callable[[], Optional[SkinPalette]]
) -> Optional[SkinPalette]:
    """Palette `name` at screen `size`: the one kept from an earlier run, or `make()`'s, kept."""
    return kept(FOLDER, name, size, make, SkinPalette.arrays, SkinPalette.from_arrays)
