"""Palettes kept between runs: a face that starts again has its mixed skins at once.

The drawn face's palettes (skin_mixing.py: the whole skin's, and each eye's for eyes of other
sizes) take about two seconds to make, and depend only on the screen size and on the code and
libraries that draw them. So they are kept in the user's cache folder (core/user_cache.py),
named by a fingerprint of all of those, and loaded back in milliseconds. A file that is missing,
damaged or of another fingerprint is made again; where the cache cannot be written, nothing is
kept. Only plain arrays are stored (no pickles): loading a file runs nothing from it.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import tempfile
import zipfile
from functools import lru_cache
from pathlib import Path
from typing import Callable, Optional, Tuple

import numpy as np

from ..core.user_cache import made_cache_folder
from .skin_mixing import SkinPalette

Size = Tuple[int, int]
FOLDER = "palettes"


def kept_palette(name: str, size: Size, make: Callable[[], Optional[SkinPalette]]) -> Optional[SkinPalette]:
    """Palette `name` at screen `size`: the one kept from an earlier run, or `make()`'s, kept."""
    folder = made_cache_folder(FOLDER)
    if folder is None:
        return make()
    prefix = f"{name}-{size[0]}x{size[1]}-"
    path = folder / f"{prefix}{_fingerprint()}.npz"
    found = _load(path)
    if found is not None:
        return found
    palette = make()
    if palette is not None:
        _save(path, palette)
        for old in folder.glob(f"{prefix}*.npz"):  # another version's: never read again
            if old != path:
                _remove(old)
    return palette


@lru_cache(maxsize=1)
def _fingerprint() -> str:
    """What a palette is made from: the package's code (this and every module it could draw
    with) and the versions of numpy and Pillow, which rasterise and mix."""
    import PIL

    digest = hashlib.sha256(f"numpy {np.__version__} Pillow {PIL.__version__}".encode())
    package = Path(__file__).resolve().parent.parent
    for source in sorted(package.rglob("*.py")):
        digest.update(source.relative_to(package).as_posix().encode())
        digest.update(source.read_bytes())
    return digest.hexdigest()[:20]


def _load(path: Path) -> Optional[SkinPalette]:
    try:
        with np.load(str(path), allow_pickle=False) as stored:
            return SkinPalette.from_arrays({key: stored[key] for key in stored.files})
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile):  # missing, cut short, not ours
        return None


def _save(path: Path, palette: SkinPalette) -> None:
    """Written whole under a temporary name, then renamed: a reader never sees half a file."""
    temporary = None
    try:
        handle, temporary = tempfile.mkstemp(prefix=".palette-", suffix=".npz", dir=str(path.parent))
        with os.fdopen(handle, "wb") as out:
            np.savez(out, **palette.arrays())
        os.replace(temporary, path)
    except OSError:  # a full disk or a folder gone: the palette is still used, only not kept
        if temporary is not None:
            _remove(Path(temporary))


def _remove(path: Path) -> None:
    with contextlib.suppress(OSError):
        path.unlink()
