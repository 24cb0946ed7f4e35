"""Themes: the face's layer images, their manifest, and their fitting to a screen.

A theme is a folder of PNG layers and a `theme.json` manifest naming each
layer's kind, name, file and anchor (where its top-left corner sits on the
theme's screen; the eyes' anchor is their rest position, the lids' their
closed one). The built-in theme lives in assets/default/ and is redrawn from
its vector shapes at any other size; other themes are resampled to fit.
"""

from __future__ import annotations

import io
import json
from collections import OrderedDict
from functools import lru_cache
from pathlib import Path
from typing import Dict, List, Optional, Union

from ..core.partial_files import remove_stale, write_atomic
from ..resources import resource
from . import artwork
from .drawn_parts import DrawnParts
from .layer_store import kept_layers
from .theme_fitting import ThemeLayers, prepare_layers, resample
from .theme_manifest import (
    MANIFEST,
    OPTIONAL,
    Key,
    Placed,
    Size,
    ThemeError,
    check_fit,
    is_number,
    layer_path,
    manifest_layers,
    manifest_size,
    parse_anchor,
    read_image,
    read_manifest,
)


class Theme:
    """A set of face layers at the theme's own size."""

    def __init__(
        self,
        name: str,
        size: Size,
        lid_travel: float,
        images: Optional[Dict[Key, Placed]],
        builtin: bool = False,
        folder: Optional[Path] = None,
    ) -> None:
        """`images` None: read from `folder` when first asked for (the default theme's, whose
        fitted layers mostly come from the user's cache, layer_store.py)."""
        self.name = name
        self.size = size
        self.lid_travel = lid_travel
        self._images = images
        self._folder = folder
        self.builtin = builtin
        self._fitted: OrderedDict[Size, ThemeLayers] = OrderedDict()

    @property
    def images(self) -> Dict[Key, Placed]:
        if self._images is None:
            self._images = Theme.load(self._folder or ".").images
        return self._images

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
        manifest = read_manifest(manifest_path)
        size = manifest_size(manifest, manifest_path)
        lid_travel = manifest.get("lid_travel", artwork.LID_TRAVEL)
        if not is_number(lid_travel) or not 0 < lid_travel < 10_000:
            raise ThemeError(f"{manifest_path}: 'lid_travel' must be a positive number of face pixels")
        theme_name = manifest.get("name", folder.name)
        if not isinstance(theme_name, str):
            raise ThemeError(f"{manifest_path}: 'name' must be a string")
        images: Dict[Key, Placed] = {}
        for i, entry in enumerate(manifest_layers(manifest, manifest_path)):
            kind = entry["kind"]
            name = entry.get("name", kind)
            if (kind, name) in images:
                raise ThemeError(f"{manifest_path}: layer {i + 1} repeats the {kind} layer named '{name}'")
            path = layer_path(folder, entry["file"], manifest_path)
            anchor = parse_anchor(entry.get("anchor", [0, 0]), manifest_path, path)
            image = read_image(path)
            check_fit(path, kind, image.size, anchor, size)
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
        return {key: resample(placed, key[0], self.size, size) for key, placed in self.images.items()}

    def layers(self, size: Size) -> ThemeLayers:
        """The theme at `size`, prepared for the renderer; the last two sizes are kept."""
        if size in self._fitted:
            self._fitted.move_to_end(size)
            return self._fitted[size]
        if self.builtin:
            fitted = kept_layers(size, lambda: prepare_layers(self.placed_at(size), size, self.lid_travel))
        else:
            fitted = prepare_layers(self.placed_at(size), size, self.lid_travel)
        if self.builtin:
            drawn = DrawnParts(size, fitted.skins, fitted.mouths, fitted.brows)
            fitted = fitted._replace(skins=drawn.skins, mouths=drawn.mouths, brows=drawn.brows, drawn=drawn)
        self._fitted[size] = fitted
        while len(self._fitted) > 2:
            self._fitted.popitem(last=False)
        return fitted

    # -- writing

    def export(
        self,
        folder: Union[str, Path],
        size: Optional[Size] = None,
        force: bool = False,
        smallest: bool = False,
    ) -> List[Path]:
        """Write the layers (PNG) and theme.json to `folder`, to edit or to use with --theme;
        `smallest` compresses the pictures as far as PNG goes (a quarter smaller, four times
        slower: for the theme the package ships)."""
        folder = Path(folder)
        size = size or self.size
        try:
            return self._export(folder, size, force, smallest)
        except OSError as e:
            raise ThemeError(f"{folder}: cannot write: {e.strerror or e}") from None

    def _export(self, folder: Path, size: Size, force: bool, smallest: bool) -> List[Path]:
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
            placed.image.save(data, format="PNG", optimize=smallest)
            write_atomic(path, data.getvalue())
            written.append(path)
            layers.append({"kind": kind, "name": name, "file": filename, "anchor": list(placed.anchor)})
        manifest = {"name": self.name, "size": list(size), "lid_travel": self.lid_travel, "layers": layers}
        text = json.dumps(manifest, indent=2) + "\n"
        write_atomic(folder / MANIFEST, text.encode("utf-8"))
        return [*written, folder / MANIFEST]


@lru_cache(maxsize=1)
def _default_theme() -> Theme:
    """The built-in theme: its manifest read now, its pictures only when something needs them."""
    folder = resource("assets/default")
    manifest_path = folder / MANIFEST
    manifest = read_manifest(manifest_path)
    size = manifest_size(manifest, manifest_path)
    lid_travel = float(manifest.get("lid_travel", artwork.LID_TRAVEL))
    return Theme(str(manifest.get("name", folder.name)), size, lid_travel, None, builtin=True, folder=folder)


def resolve(theme: Union[None, str, Path, Theme]) -> Theme:
    """A Theme from None (the default), a folder, or a Theme."""
    if theme is None:
        return Theme.default()
    if isinstance(theme, Theme):
        return theme
    return Theme.load(theme)
