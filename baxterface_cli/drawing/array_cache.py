"""What the drawing works out once, kept between runs as plain arrays in the user's cache.

The default theme fitted to a screen (layer_store.py) and the drawn face's palettes
(palette_store.py) depend only on the screen size and on what draws them: the package's code,
the default theme's pictures, and the numpy and Pillow that rasterise and mix. So each is kept in
the user's cache folder (core/user_cache.py) under a name with a fingerprint of all of those, and
loaded back in milliseconds. A file that is missing, damaged or of another fingerprint is made
again; where the cache cannot be written, nothing is kept. The last `VERSIONS` fingerprints used
are kept side by side: a robot runs the node in ROS's Python and `play` in another, with another
numpy, and keeping one had each remake what the other had just made (over a second of work and
100 MB more at the node's start). Only plain arrays are stored (no pickles): loading a file runs
nothing from it.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import tempfile
import zipfile
from functools import lru_cache
from pathlib import Path
from typing import Callable, Dict, Optional, Tuple, TypeVar

import numpy as np

from ..core.user_cache import made_cache_folder, trim
from ..resources import resource

Size = Tuple[int, int]
Arrays = Dict[str, np.ndarray]
T = TypeVar("T")
VERSIONS = 3  # fingerprints kept of each thing at each size, the least recently used gone first


def kept(
    folder_name: str,
    name: str,
    size: Size,
    make: Callable[[], Optional[T]],
    to_arrays: Callable[[T], Optional[Arrays]],
    from_arrays: Callable[[Arrays], T],
) -> Optional[T]:
    """`name` at screen `size`: the one kept from an earlier run, or `make()`'s, kept.

    `to_arrays` gives what is stored (None: not to be kept); `from_arrays` takes it back, and
    raises ValueError (or KeyError) where the arrays do not make one.
    """
    folder = made_cache_folder(folder_name)
    if folder is None:
        return make()
    prefix = f"{name}-{size[0]}x{size[1]}-"
    path = folder / f"{prefix}{fingerprint()}.npz"
    found = _load(path, from_arrays)
    if found is not None:
        with contextlib.suppress(OSError):
            os.utime(path)  # used now: kept before versions used less lately
        return found
    made = make()
    arrays = None if made is None else to_arrays(made)
    if arrays is not None:
        _save(path, arrays)
        trim(folder, f"{prefix}*.npz", None, most_files=VERSIONS)  # versions counted, not bytes
    return made


@lru_cache(maxsize=1)
def fingerprint() -> str:
    """What everything kept is made from: the package's code, the default theme's pictures, and
    the versions of numpy and Pillow."""
    import PIL

    digest = hashlib.sha256(f"numpy {np.__version__} Pillow {PIL.__version__}".encode())
    package = Path(__file__).resolve().parent.parent
    sources = [(p.relative_to(package).as_posix(), p) for p in package.rglob("*.py")]
    theme = resource("assets/default")
    sources += [(f"theme/{p.name}", p) for p in theme.iterdir() if p.is_file()]
    for name, source in sorted(sources):
        digest.update(name.encode())
        digest.update(source.read_bytes())
    return digest.hexdigest()[:20]


def _load(path: Path, from_arrays: Callable[[Arrays], T]) -> Optional[T]:
    try:
        with np.load(str(path), allow_pickle=False) as stored:
            return from_arrays({key: stored[key] for key in stored.files})
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile):  # missing, cut short, not ours
        return None


def _save(path: Path, arrays: Arrays) -> None:
    """Written whole under a temporary name, then renamed: a reader never sees half a file."""
    temporary = None
    try:
        handle, temporary = tempfile.mkstemp(prefix=".kept-", suffix=".npz", dir=str(path.parent))
        with os.fdopen(handle, "wb") as out:
            np.savez(out, **arrays)
        os.replace(temporary, path)
    except OSError:  # a full disk or a folder gone: what was made is still used, only not kept
        if temporary is not None:
            _remove(Path(temporary))


def _remove(path: Path) -> None:
    with contextlib.suppress(OSError):
        path.unlink()
