"""Themes: the face's layer images, their manifest, and their fitting to a screen.

A theme is a folder of PNG layers and a `theme.json` manifest naming each
layer's kind, name, file and anchor (where its top-left corner sits on the
theme's screen; the eyes' anchor is their rest position, the lids' their
closed one). The built-in theme lives in assets/default/ and is redrawn from
its vector shapes at any other size; other themes are resampled to fit.
"""

from __future__ import annotations

import errno
import io
import json
import math
import os
import re
import stat
import warnings
from collections import OrderedDict
from functools import lru_cache
from pathlib import Path
from typing import Dict, List, NamedTuple, Optional, Tuple, Union

import numpy as np
from PIL import Image

from . import artwork
from .compositing import Sprite, split_columns, sprite_from_rgba
from .partial import remove_stale, write_atomic
from .resources import resource
from .tables import VISEMES, viseme_mouth

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
# speech mouths, which older themes lack, are drawn as the mouths tables.VISEMES names.
OPTIONAL: Dict[Key, Key] = {
    ("mouth", viseme_mouth(shape)): ("mouth", mouth) for shape, mouth in VISEMES.items()
}


class ThemeError(Exception):
    """A theme that cannot be used; the message names the file at fault."""


class Placed(NamedTuple):
    image: Image.Image  # RGBA
    anchor: Tuple[int, int]


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


def face_scale(size: Size) -> float:
    return min(size[0] / artwork.FACE_SIZE[0], size[1] / artwork.FACE_SIZE[1])


def face_origin(size: Size) -> Tuple[float, float]:
    s = face_scale(size)
    return (size[0] - artwork.FACE_SIZE[0] * s) / 2.0, (size[1] - artwork.FACE_SIZE[1] * s) / 2.0


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


class Theme:
    """A set of face layers at the theme's own size."""

    def __init__(
        self, name: str, size: Size, lid_travel: float, images: Dict[Key, Placed], builtin: bool = False
    ) -> None:
        self.name = name
        self.size = size
        self.lid_travel = lid_travel
        self.images = images
        self.builtin = builtin
        self._fitted: OrderedDict[Size, ThemeLayers] = OrderedDict()

    @property
    def stand_ins(self) -> Dict[Key, Key]:
        """The optional layers this theme leaves out, each with the layer drawn in its place."""
        return {key: other for key, other in OPTIONAL.items() if key not in self.images}

    # -- loading

    @classmethod
    def default(cls) -> Theme:
        return _default_theme()

    @classmethod
    def load(cls, folder: Union[str, Path]) -> Theme:
        """Read a theme folder, checking every layer; ThemeError names what is wrong."""
        folder = Path(folder)
        try:
            return cls._load(folder)
        except OSError as e:  # a name too long, say: Path.is_dir() lets that through
            raise ThemeError(f"{folder}: cannot read: {e.strerror or e}") from None

    @classmethod
    def _load(cls, folder: Path) -> Theme:
        manifest_path = folder / MANIFEST
        if not folder.is_dir():
            why = "not a folder" if folder.exists() else "no such folder"
            raise ThemeError(f"{folder}: not a theme folder ({why})")
        if not manifest_path.is_file():
            raise ThemeError(f"{manifest_path}: missing; a theme folder needs its manifest")
        manifest = _read_manifest(manifest_path)
        size = _manifest_size(manifest, manifest_path)
        lid_travel = manifest.get("lid_travel", artwork.LID_TRAVEL)
        if not _is_number(lid_travel) or not 0 < lid_travel < 10_000:
            raise ThemeError(f"{manifest_path}: 'lid_travel' must be a positive number of face pixels")
        theme_name = manifest.get("name", folder.name)
        if not isinstance(theme_name, str):
            raise ThemeError(f"{manifest_path}: 'name' must be a string")
        images: Dict[Key, Placed] = {}
        for i, entry in enumerate(_manifest_layers(manifest, manifest_path)):
            kind = entry["kind"]
            name = entry.get("name", kind)
            if (kind, name) in images:
                raise ThemeError(f"{manifest_path}: layer {i + 1} repeats the {kind} layer named '{name}'")
            path = _layer_path(folder, entry["file"], manifest_path)
            anchor = _anchor(entry.get("anchor", [0, 0]), manifest_path, path)
            image = _read_image(path)
            _check_fit(path, kind, image.size, anchor, size)
            images[(kind, name)] = Placed(image, anchor)
        missing = [key for key in artwork.layer_names() if key not in images and key not in OPTIONAL]
        if missing:
            kind, name = missing[0]
            more = f" and {len(missing) - 1} more" if len(missing) > 1 else ""
            raise ThemeError(f"{manifest_path}: no {kind} layer named '{name}'{more}")
        return cls(theme_name, size, float(lid_travel), images)

    # -- fitting to a screen

    def placed_at(self, size: Size) -> Dict[Key, Placed]:
        """Every layer fitted to a screen of `size`, face scaled to fit and centred."""
        if size == self.size:
            return self.images
        if self.builtin:
            return {key: Placed(image, (0, 0)) for key, image in artwork.draw_theme(size).items()}
        return {key: _resample(placed, key[0], self.size, size) for key, placed in self.images.items()}

    def layers(self, size: Size) -> ThemeLayers:
        """The theme at `size`, prepared for the renderer; the last two sizes are kept."""
        if size in self._fitted:
            self._fitted.move_to_end(size)
            return self._fitted[size]
        fitted = _prepare(self.placed_at(size), size, self.lid_travel)
        self._fitted[size] = fitted
        while len(self._fitted) > 2:
            self._fitted.popitem(last=False)
        return fitted

    # -- writing

    def export(
        self, folder: Union[str, Path], size: Optional[Size] = None, force: bool = False
    ) -> List[Path]:
        """Write the layers (PNG) and theme.json to `folder`, to edit or to use with --theme."""
        folder = Path(folder)
        size = size or self.size
        try:
            return self._export(folder, size, force)
        except OSError as e:
            raise ThemeError(f"{folder}: cannot write: {e.strerror or e}") from None

    def _export(self, folder: Path, size: Size, force: bool) -> List[Path]:
        if folder.exists() and not folder.is_dir():
            raise ThemeError(f"{folder}: not a folder; choose a new folder")
        if folder.exists() and any(folder.iterdir()) and not force:
            raise ThemeError(f"{folder}: not empty; choose a new folder or use --force")
        folder.mkdir(parents=True, exist_ok=True)
        remove_stale(folder)
        written, layers = [], []
        for (kind, name), placed in self.placed_at(size).items():
            filename = f"{kind}.png" if kind == name else f"{kind}-{name}.png"
            path = folder / filename
            data = io.BytesIO()
            placed.image.save(data, format="PNG", optimize=True)
            write_atomic(path, data.getvalue())
            written.append(path)
            layers.append({"kind": kind, "name": name, "file": filename, "anchor": list(placed.anchor)})
        manifest = {"name": self.name, "size": list(size), "lid_travel": self.lid_travel, "layers": layers}
        text = json.dumps(manifest, indent=2) + "\n"
        write_atomic(folder / MANIFEST, text.encode("utf-8"))
        return [*written, folder / MANIFEST]


@lru_cache(maxsize=1)
def _default_theme() -> Theme:
    theme = Theme.load(resource("assets/default"))
    theme.builtin = True
    return theme


def resolve(theme: Union[None, str, Path, Theme]) -> Theme:
    """A Theme from None (the default), a folder, or a Theme."""
    if theme is None:
        return Theme.default()
    if isinstance(theme, Theme):
        return theme
    return Theme.load(theme)


# -- manifest checks -------------------------------------------------------


def _read_manifest(path: Path) -> dict:
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


def _is_number(value: object) -> bool:
    return _is_int(value) or isinstance(value, float)


def _manifest_size(manifest: dict, path: Path) -> Size:
    size = manifest.get("size")
    if not isinstance(size, list) or len(size) != 2 or not all(_is_int(v) for v in size):
        raise ThemeError(f"{path}: 'size' must be [width, height] in pixels, like [1024, 600]")
    problem = size_problem((size[0], size[1]))
    if problem:
        raise ThemeError(f"{path}: 'size' {size} {problem}")
    return size[0], size[1]


def _manifest_layers(manifest: dict, path: Path) -> List[dict]:
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


def _layer_path(folder: Path, name: str, manifest_path: Path) -> Path:
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


def _anchor(value: object, manifest_path: Path, path: Path) -> Tuple[int, int]:
    if not isinstance(value, list) or len(value) != 2 or not all(_is_int(v) for v in value):
        raise ThemeError(f"{manifest_path}: the anchor of {path.name} must be [x, y] in whole pixels")
    return value[0], value[1]


def _read_image(path: Path) -> Image.Image:
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


def _check_fit(path: Path, kind: str, image_size: Size, anchor: Tuple[int, int], size: Size) -> None:
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


# -- fitting ---------------------------------------------------------------


def _resample(placed: Placed, kind: str, native: Size, size: Size) -> Placed:
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


def _alike_rows(sprite: Sprite) -> Tuple[int, int]:
    """The longest run of identical rows: a lid's flat upper part."""
    same = np.all(sprite.rgb_a[1:] == sprite.rgb_a[:-1], axis=(1, 2)) & np.all(
        sprite.inv[1:] == sprite.inv[:-1], axis=(1, 2)
    )
    best, start = (0, 1), None
    for i, alike in enumerate(list(same) + [False]):
        if alike and start is None:
            start = i
        elif not alike and start is not None:
            if i + 1 - start > best[1] - best[0]:
                best = (start, i + 1)
            start = None
    return best


def _prepare(placed: Dict[Key, Placed], size: Size, lid_travel: float) -> ThemeLayers:
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
        lid_bands=[_alike_rows(lid) for lid in lids],
        lid_travel=int(math.floor(lid_travel * scale + 0.5)),
        skins={int(n): _sprite(p, size) for (k, n), p in placed.items() if k == "skin"},
        mouths=_with_stand_ins({n: _sprite(p, size) for (k, n), p in placed.items() if k == "mouth"}),
        brows={n: _sprite(p, size) for (k, n), p in placed.items() if k == "brows"},
    )


def _with_stand_ins(mouths: Dict[str, Sprite]) -> Dict[str, Sprite]:
    """Every mouth the renderer may be asked for: a speech mouth the theme lacks is the
    mouth tables.VISEMES gives for it (the same sprite, shared)."""
    for (_, name), (_, other) in OPTIONAL.items():
        if name not in mouths and other in mouths:
            mouths[name] = mouths[other]
    return mouths
