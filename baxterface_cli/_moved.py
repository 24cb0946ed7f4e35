"""The modules' old import paths, from before the package had rooms or from a room they left: each
still imports, with a DeprecationWarning naming its new place, until the next release.

`import baxterface_cli.face` gives the very module `baxterface_cli.drawing.face` is, so
code that patched or compared it keeps working.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys
import warnings
from typing import Any, Optional

# old name -> new name, both under baxterface_cli
MOVED = {
    "tables": "core.tables",
    "geometry": "core.geometry",
    "easing": "core.easing",
    "state": "core.face_state",
    "voices": "core.voices",
    "partial": "core.partial_files",
    "nodes": "language.syntax_tree",
    "parser": "language.parser",
    "checker": "language.checker",
    "diagnostics": "language.diagnostics",
    "durations": "language.durations",
    "vocabulary": "language.vocabulary",
    "visemes": "speech.visemes",
    "soundtrack": "speech.soundtrack",
    "audio": "speech.sound_device",
    "effects": "engine.effects",
    "timeline": "engine.compiler",  # which also holds Timeline and the rest of the old module
    "idle": "engine.animation",
    "live": "engine.live_face",
    "explanation": "engine.explanation",
    "intake": "engine.intake",
    "backlog": "engine.backlog",
    "artwork": "drawing.artwork",
    "theme": "drawing.theme",
    "compositing": "drawing.compositing",
    "renderer": "drawing.renderer",
    "face": "drawing.face",
    "following": "robot.following",
    "faces": "robot.face_finder",
    "camera": "robot.camera_watch",
    "buttons": "robot.navigator_buttons",
    "playback": "play.player",
    "rehearsal": "robot.rehearsal",
    "play.rehearsal": "robot.rehearsal",
    "ros.node": "ros.face_node",
    "formats": "export.registry",
    "output": "export.png_gif",
    "video": "export.video",
    "animated": "export.apng",
    "bag": "export.bag",
    "rendering": "export.render_to_file",
    # what every face page shares, out of the studio into a room beneath it and the screen
    "studio.face_api": "web.face_api",
    "studio.pump": "web.pump",
    "studio.guard": "web.guard",
    "studio.server": "web.server",
    "studio.connections": "web.connections",
    "screen.web": "screen.screen_api",
}


class _OldPaths(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    def find_spec(self, fullname: str, path: Any, target: Any = None) -> Optional[Any]:
        package, _, old = fullname.partition(".")
        if package != __package__ or old not in MOVED:
            return None
        return importlib.util.spec_from_loader(fullname, self)

    def create_module(self, spec: Any) -> Any:
        new = f"{__package__}.{MOVED[spec.name.partition('.')[2]]}"
        warnings.warn(
            f"{spec.name} is now {new}; the old name goes in the next release",
            DeprecationWarning,
            stacklevel=2,
        )
        return importlib.import_module(new)

    def exec_module(self, module: Any) -> None:
        pass  # the module is the new one, already run


# Old modules whose names are rooms now: their names are read through the room, with a warning.
BECAME_ROOMS = {"speech": "speech.synthesis", "robot": "robot.robot_rules"}


def room_attribute(room: str, name: str) -> Any:
    """What `baxterface_cli.<room>.<name>` meant when the room was a module: a room's `__getattr__`."""
    new = f"{__package__}.{BECAME_ROOMS[room]}"
    if name.startswith("__") or importlib.util.find_spec(f"{__package__}.{room}.{name}") is not None:
        raise AttributeError(name)  # a module of the room: the import system brings it
    module = importlib.import_module(new)
    if not hasattr(module, name):
        raise AttributeError(f"module {__package__}.{room!r} has no attribute {name!r}")
    warnings.warn(
        f"{__package__}.{room}.{name} is now {new}.{name}; the old name goes in the next release",
        DeprecationWarning,
        stacklevel=3,
    )
    return getattr(module, name)


def install() -> None:
    if not any(isinstance(finder, _OldPaths) for finder in sys.meta_path):
        sys.meta_path.append(_OldPaths())
