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
import types
import warnings
from typing import Any, Optional, Tuple

# old name -> new name, both under baxterface_cli
MOVED = {
    "tables": "core.face_constants",
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
    "idle": "engine.animation",
    "live": "engine.live_face",
    "explanation": "engine.explanation",
    "intake": "engine.session_intake",
    "backlog": "engine.log_backlog",
    "artwork": "drawing.artwork",
    "theme": "drawing.theme",
    "compositing": "drawing.compositing",
    "renderer": "drawing.renderer",
    "face": "drawing.face",
    "following": "robot.following",
    "faces": "robot.person_finder",
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
    "studio.pump": "web.frame_pump",
    "studio.guard": "web.request_guard",
    "studio.server": "web.server",
    "studio.connections": "web.connections",
    "screen.web": "screen.screen_api",
    # a person's face, seen by the head camera, named apart from the robot's own face
    "robot.face_finder": "robot.person_finder",
    "robot.face_choice": "robot.person_choice",
    "robot.face_cascades": "robot.haar_detector",
    "robot.face_networks": "robot.mtcnn_detector",
    # modules named for what they hold
    "ros.wire": "ros.effect_messages",
    "web.pump": "web.frame_pump",
    "web.guard": "web.request_guard",
    "engine.intake": "engine.session_intake",
    "engine.command_intake": "engine.session_intake",
    "engine.backlog": "engine.log_backlog",
    "engine.first_motion": "engine.change_polling",
    "drawing.kept_arrays": "drawing.array_cache",
    "core.tables": "core.face_constants",
}


# Old modules split in two: their names are read from each new module in turn.
SPLIT = {
    # the timeline itself (Timeline, Track, Said, state_record, ...) and what compiles a script into it
    "timeline": ("engine.timeline", "engine.compiler"),
}


class _SplitModule(types.ModuleType):
    """An old module whose names now live in several: each read from the first that has it."""

    def __init__(self, name: str, parts: Tuple[str, ...]) -> None:
        super().__init__(name)
        self._parts = parts

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        for part in self._parts:
            module = importlib.import_module(part)
            if hasattr(module, name):
                return getattr(module, name)
        raise AttributeError(f"module {self.__name__!r} has no attribute {name!r}")


class _OldPaths(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    def find_spec(self, fullname: str, path: Any, target: Any = None) -> Optional[Any]:
        package, _, old = fullname.partition(".")
        if package != __package__ or (old not in MOVED and old not in SPLIT):
            return None
        return importlib.util.spec_from_loader(fullname, self)

    def create_module(self, spec: Any) -> Any:
        old = spec.name.partition(".")[2]
        if old in SPLIT:
            parts = tuple(f"{__package__}.{part}" for part in SPLIT[old])
            warnings.warn(
                f"{spec.name} is now {' and '.join(parts)}; the old name goes in the next release",
                DeprecationWarning,
                stacklevel=2,
            )
            return _SplitModule(spec.name, parts)
        new = f"{__package__}.{MOVED[old]}"
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
