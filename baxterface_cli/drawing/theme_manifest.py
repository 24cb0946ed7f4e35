"""A theme folder on disk: its manifest (theme.json) and layer images, checked as they are read,
and the sizes a theme may have. Every problem is a ThemeError naming the file at fault.
"""

from __future__ import annotations

import errno
import json
import os
import re
import stat
import warnings
from pathlib import Path
from typing import Dict, List, NamedTuple, Optional, Tuple

from PIL import Image

from ..core.face_constants import VISEMES, viseme_mouth
from . import artwork

MANIFEST = "theme.json"
MAX_SIDE = 8192
# Memory grows with the screen: a render that uses every emotion peaks near
# 400 bytes a pixel (full-screen layers, and up to 12 part combinations
# kept composited), 1 GB at 1920x1200 and 3.4 GB at 3840x2160, the most.
MAX_PIXELS = 3840 * 2160
Size = Tuple[int, int]
Key = Tuple[str, str]  # (kind, name)
FULL_SCREEN_KINDS = ("background", "skin")
# Layers a theme may leave out, each with the layer drawn in its place: the
# speech mouths, which older themes lack, are drawn as the mouths face_constants.VISEMES names.
OPTIONAL: Dict[Key, Key] = {
    ("mouth", viseme_mouth(shape)): ("mouth", mouth) for shape, mouth in VISEMES.items()
}


class ThemeError(Exception):
    """A theme that cannot be used; the message names the file at fault."""


class Placed(NamedTuple):
    image: Image.Image  # RGBA
    anchor: Tuple[int, int]


def parse_size(text: str) -> Size:
    """'1920x1200' -> (1920, 1200); ValueError with a clear message otherwise."""
    compact = text.lower().replace(" ", "")
    # ASCII digits only: str.isdigit() takes '²', which int() refuses.
    match = re.fullmatch(r"0*([0-9]{1,9})x0*([0-9]{1,9})", compact)
    if not match:
        if re.fullmatch(r"[0-9]+x[0-9]+", compact):  # a side of 10 digits or more
            shown = compact if len(compact) <= 30 else compact[:30] + "..."
            raise ValueError(f"size {shown} {size_problem((MAX_SIDE, MAX_SIDE))}")
        raise ValueError(f"size must look like 1024x600, not {text[:40]!r}")
    size = int(match.group(1)), int(match.group(2))
    check_size(size)
    return size


def check_size(size: Size) -> None:
    """ValueError unless a screen of `size` can be drawn in a few GB of memory."""
    problem = size_problem(size)
    if problem:
        raise ValueError(f"size {size[0]}x{size[1]} {problem}")


def size_problem(size: Size) -> Optional[str]:
    """What is wrong with a screen size ('is too large: ...'), or None."""
    width, height = size
    if width < 16 or height < 16:
        return "is too small: at least 16 pixels a side"
    if width * height > MAX_PIXELS:
        return f"is too large: at most {MAX_PIXELS} pixels (e.g. 3840x2160)"
    if width > MAX_SIDE or height > MAX_SIDE:
        return f"is too large: at most {MAX_SIDE} pixels a side"
    return None


def read_manifest(path: Path) -> dict:
    def whole_number(text: str) -> int:
        # Python 3.11+ refuses ints of over 4300 digits, older ones take
        # their time: no number a theme needs is longer than this.
        if len(text) > 30:
            raise ThemeError(f"{path}: the number {text[:20]}... is too long")
        return int(text)

    def constant(text: str) -> object:
        raise ThemeError(f"{path}: {text} is not a number a theme can use")

    try:
        if path.stat().st_size > 1_000_000:
            raise ThemeError(f"{path}: too large for a theme manifest")
        text = path.read_text(encoding="utf-8")
        data = json.loads(text, parse_int=whole_number, parse_constant=constant)
    except UnicodeDecodeError:
        raise ThemeError(f"{path}: not UTF-8 text") from None
    except json.JSONDecodeError as e:
        raise ThemeError(f"{path}:{e.lineno}:{e.colno}: not valid JSON: {e.msg}") from None
    except RecursionError:
        raise ThemeError(f"{path}: nested too deeply for a theme manifest") from None
    except OSError as e:
        raise ThemeError(f"{path}: cannot read: {e.strerror or e}") from None
    if not isinstance(data, dict):
        raise ThemeError(f"{path}: must hold a JSON object")
    return data


def _is_int(value: object) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)  # JSON's true is no number


def is_number(value: object) -> bool:
    return _is_int(value) or isinstance(value, float)


def manifest_size(manifest: dict, path: Path) -> Size:
    size = manifest.get("size")
    if not isinstance(size, list) or len(size) != 2 or not all(_is_int(v) for v in size):
        raise ThemeError(f"{path}: 'size' must be [width, height] in pixels, like [1024, 600]")
    problem = size_problem((size[0], size[1]))
    if problem:
        raise ThemeError(f"{path}: 'size' {size} {problem}")
    return size[0], size[1]


def manifest_layers(manifest: dict, path: Path) -> List[dict]:
    layers = manifest.get("layers")
    if not isinstance(layers, list):
        raise ThemeError(f"{path}: 'layers' must be a list of layers")
    known = set(artwork.layer_names())
    for i, entry in enumerate(layers):
        if not isinstance(entry, dict) or not all(isinstance(entry.get(k), str) for k in ("kind", "file")):
            raise ThemeError(f"{path}: layer {i + 1} needs a 'kind', a 'name' and a 'file'")
        if not isinstance(entry.get("name", ""), str):
            raise ThemeError(f'{path}: layer {i + 1}\'s \'name\' must be a string, like "0" or "smile"')
        key = (entry["kind"], entry.get("name", entry["kind"]))
        if key not in known:
            kinds = sorted({k for k, _ in known})
            what = f"{_shown(key[0])} {_shown(key[1])}"
            raise ThemeError(f"{path}: layer {i + 1} is an unknown {what} (kinds: {', '.join(kinds)})")
    return layers


def _shown(text: str, most: int = 40) -> str:
    """A name from a manifest, quoted, and cut short: the message stays one readable line."""
    return repr(text if len(text) <= most else text[:most] + "...")


def layer_path(folder: Path, name: str, manifest_path: Path) -> Path:
    """The layer's file, which must lie inside the theme folder."""
    if "\0" in name:
        raise ThemeError(f"{manifest_path}: layer file {name!r} has a NUL character in its name")
    try:
        os.fsencode(name)
        path = (folder / name).resolve()
        root = folder.resolve()
    except UnicodeEncodeError:
        raise ThemeError(f"{manifest_path}: layer file {name!r} is not a possible file name here") from None
    except (OSError, RuntimeError) as e:  # RuntimeError: a loop of links, before Python 3.13
        why = getattr(e, "strerror", None) or e
        raise ThemeError(f"{manifest_path}: layer file {name!r}: {why}") from None
    if os.path.isabs(name) or root not in path.parents:
        raise ThemeError(f"{manifest_path}: layer file {name!r} must be inside the theme folder")
    return folder / name


def parse_anchor(value: object, manifest_path: Path, path: Path) -> Tuple[int, int]:
    if not isinstance(value, list) or len(value) != 2 or not all(_is_int(v) for v in value):
        raise ThemeError(f"{manifest_path}: the anchor of {path.name} must be [x, y] in whole pixels")
    return value[0], value[1]


def read_image(path: Path) -> Image.Image:
    try:
        info = path.stat()
    except OSError as e:
        if e.errno in (errno.ENOENT, errno.ENOTDIR):
            raise ThemeError(f"{path}: missing (named in {MANIFEST})") from None
        raise ThemeError(f"{path}: cannot read: {e.strerror or e}") from None
    if not stat.S_ISREG(info.st_mode):
        raise ThemeError(f"{path}: not a file (named in {MANIFEST})")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)  # the size is checked below
            with Image.open(path) as image:
                problem = size_problem((max(image.width, 16), max(image.height, 16)))
                if problem:
                    raise ThemeError(f"{path}: {image.width}x{image.height} {problem}")
                return image.convert("RGBA")
    except ThemeError:
        raise
    except Exception as e:  # noqa: BLE001 - a decoder may fail in any way on a damaged file
        raise ThemeError(f"{path}: cannot read image: {e}") from None


def check_fit(path: Path, kind: str, image_size: Size, anchor: Tuple[int, int], size: Size) -> None:
    w, h = image_size
    if kind in FULL_SCREEN_KINDS:
        if (w, h) != size or anchor != (0, 0):
            raise ThemeError(
                f"{path}: is {w}x{h}, but a {kind} layer must cover the theme's {size[0]}x{size[1]} screen"
            )
        return
    x, y = anchor
    if x < 0 or y < 0 or x + w > size[0] or y + h > size[1]:
        raise ThemeError(
            f"{path}: a {w}x{h} image at {x},{y} runs off the theme's {size[0]}x{size[1]} screen"
        )
