"""Baxter's navigator and cuff buttons as face commands: a mapping file and edge detection.

One press, one command: a button sends when it goes down, not while it is
held. Keys are NAVIGATOR.BUTTON (`left.up`) or CUFF.BUTTON (`left_cuff.dash`,
`right_cuff.squeeze`), as scripts name them. A button mapped to a list sends its commands in
turn (a toggle). The wheel (0..255, wrapping) steps through its commands one a click while the
face is awake. The mapping is `buttons.json` beside this file unless a user
gives their own.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Type, Union

from ..language.diagnostics import ScriptError
from ..language.events import BUTTONS, CUFF_BUTTONS, CUFFS, NAVIGATORS
from ..language.parser import parse
from .event_sensors import CUFF_INPUTS

DEFAULT_MAPPING = Path(__file__).resolve().parent / "buttons.json"


class MappingError(Exception):
    """A mapping file that cannot be used; the message names the file and the entry."""


class ButtonMap:
    def __init__(
        self, buttons: Dict[str, List[str]], wheel_navigator: Optional[str], wheel: List[str]
    ) -> None:
        self.buttons = buttons
        self.wheel_navigator = wheel_navigator
        self.wheel = wheel

    @classmethod
    def load(cls, path: Union[None, str, Path] = None) -> ButtonMap:
        path = Path(path) if path else DEFAULT_MAPPING
        data = read_json(path, MappingError)
        if not isinstance(data, dict):
            raise MappingError(f"{path}: must hold a JSON object")
        buttons: Dict[str, List[str]] = {}
        for key, value in (data.get("buttons") or {}).items():
            navigator, _, button = key.partition(".")
            if not (navigator in NAVIGATORS and button in BUTTONS) and not (
                navigator in CUFFS and button in CUFF_BUTTONS
            ):
                raise MappingError(
                    f"{path}: unknown button {key!r}; use NAVIGATOR.BUTTON or CUFF.BUTTON, "
                    "e.g. left.up or left_cuff.dash"
                )
            buttons[key] = _commands(value, path, key)
        wheel = data.get("wheel") or {}
        navigator = wheel.get("navigator")
        if navigator is not None and navigator not in NAVIGATORS:
            raise MappingError(f"{path}: unknown wheel navigator {navigator!r}")
        return cls(buttons, navigator, _commands(wheel.get("commands", []), path, "wheel") if wheel else [])


def read_json(path: Path, error: Type[Exception]) -> Any:
    """A user's JSON file, or `error` saying in one line why it cannot be read."""
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except OSError as e:
        raise error(f"{path}: cannot read: {e.strerror or e}") from None
    except (ValueError, UnicodeDecodeError) as e:
        raise error(f"{path}: not valid JSON: {e}") from None


def _commands(value: object, path: Path, key: str) -> List[str]:
    commands = [value] if isinstance(value, str) else value
    if not isinstance(commands, list) or not all(isinstance(c, str) for c in commands):
        raise MappingError(f"{path}: {key} must be a command or a list of commands")
    for command in commands:
        try:
            parse(command, f"{path} ({key})")
        except ScriptError as e:
            raise MappingError(e.render()) from None
    return commands


class Buttons:
    """Navigator and cuff states in, the commands they mean out."""

    def __init__(self, mapping: ButtonMap) -> None:
        self.mapping = mapping
        self.down: Dict[str, bool] = {}
        self.turns: Dict[str, int] = {}  # how many times each toggle was pressed
        self.wheel_at: Optional[int] = None
        self.wheel_index = 0
        self.awake = False  # the face node starts asleep

    def update(self, navigator: str, buttons: Sequence[bool], wheel: Optional[int] = None) -> List[str]:
        out: List[str] = []
        for index, name in enumerate(BUTTONS[: len(buttons)]):
            out += self._pressed(f"{navigator}.{name}", bool(buttons[index]))
        if wheel is not None and navigator == self.mapping.wheel_navigator and self.mapping.wheel:
            turned = self._wheel(int(wheel) % 256)
            for command in turned:
                self.heard(command)
            out += turned
        return out

    def cuff(self, side: str, io_name: str, pressed: bool) -> List[str]:
        """A cuff's input (`left`, `upper_button`) read as pressed or not: the command it means."""
        button = CUFF_INPUTS.get(io_name)
        return [] if button is None else self._pressed(f"{side}_cuff.{button}", pressed)

    def _pressed(self, key: str, pressed: bool) -> List[str]:
        out = []
        if pressed and not self.down.get(key, False) and key in self.mapping.buttons:
            commands = self.mapping.buttons[key]
            turn = self.turns.get(key, 0)
            out.append(commands[turn % len(commands)])
            self.turns[key] = turn + 1
            self.heard(out[0])
        self.down[key] = bool(pressed)
        return out

    def _wheel(self, value: int) -> List[str]:
        if self.wheel_at is None:
            self.wheel_at = value
            return []
        clicks = (value - self.wheel_at + 128) % 256 - 128  # the wheel wraps at 256
        self.wheel_at = value
        if clicks == 0 or not self.awake:
            return []
        self.wheel_index = (self.wheel_index + (1 if clicks > 0 else -1)) % len(self.mapping.wheel)
        return [self.mapping.wheel[self.wheel_index]]

    def heard(self, command: str) -> None:
        """Keep track of sleep and waking, from the commands sent (or seen on the face's ~state)."""
        if command.strip().lower() in ("sleep", "exit"):
            self.awake = False
        elif command.strip().lower() in ("wake_up", "wake up"):
            self.awake = True
