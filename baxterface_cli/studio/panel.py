"""The studio's button panel: labelled commands with shortcut keys, from a JSON file.

The default panel is `panel.json` beside this file; a user copies it, edits
it, and passes it with `--buttons`. Every command is checked when the file is
read, so a bad one is reported once, with its label, not on the day it is
pressed.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import List, NamedTuple, Optional, Union

from ..language.diagnostics import ScriptError
from ..language.parser import parse
from ..robot.navigator_buttons import read_json

DEFAULT_PANEL = Path(__file__).resolve().parent / "panel.json"
MAX_BUTTONS = 200


class PanelError(Exception):
    """A panel file that cannot be used; the message names the file and the button."""


class Button(NamedTuple):
    group: str
    label: str
    command: str
    key: Optional[str]  # a character, or a KeyboardEvent.key name such as ArrowLeft

    def as_json(self) -> dict:
        return self._asdict()


def load_panel(path: Union[None, str, Path] = None) -> List[Button]:
    """The buttons in `path` (the default panel without one); PanelError if it is unusable."""
    path = Path(path) if path else DEFAULT_PANEL
    data = read_json(path, PanelError)
    entries = data.get("buttons") if isinstance(data, dict) else None
    if not isinstance(entries, list):
        raise PanelError(f'{path}: must hold an object with a "buttons" list')
    if len(entries) > MAX_BUTTONS:
        raise PanelError(f"{path}: {len(entries)} buttons; the most a panel takes is {MAX_BUTTONS}")
    buttons: List[Button] = []
    keys = {}
    for number, entry in enumerate(entries, 1):
        button = _button(entry, path, number)
        if button.key is not None:
            if button.key in keys:
                raise PanelError(
                    f"{path}: button {button.label!r} has key {button.key!r}, as {keys[button.key]!r} has"
                )
            keys[button.key] = button.label
        buttons.append(button)
    return buttons


# The browser's names (KeyboardEvent.key) of the keys a shortcut may be, besides one character.
FUNCTION_KEYS = frozenset(f"F{n}" for n in range(1, 13))
KEY_NAMES = FUNCTION_KEYS | {
    "ArrowLeft", "ArrowRight", "ArrowUp", "ArrowDown", "Enter", "Escape", "Tab", "Backspace",
    "Delete", "Insert", "Home", "End", "PageUp", "PageDown",
}  # fmt: skip


def _button(entry: object, path: Path, number: int) -> Button:
    if not isinstance(entry, dict):
        raise PanelError(f"{path}: button {number} must be an object with a label and a command")
    label, command = entry.get("label"), entry.get("command")
    group, key = entry.get("group", "Buttons"), entry.get("key")
    if not isinstance(command, str) or not command.strip():
        raise PanelError(f"{path}: button {number} needs a command")
    if label is None:
        label = command
    for name, value in (("label", label), ("group", group)):
        if not isinstance(value, str) or not value.strip():
            raise PanelError(f"{path}: button {number}: {name} must be a non-empty string")
    if key is not None and not (isinstance(key, str) and (len(key) == 1 or key in KEY_NAMES)):
        raise PanelError(
            f"{path}: button {label!r}: key {json.dumps(key)} is not one character or a key name"
            f" ({', '.join(sorted(KEY_NAMES - FUNCTION_KEYS))}, F1 to F12)"
        )
    try:
        parse(command, f"{path} (button {label!r})")
    except ScriptError as e:
        raise PanelError(e.summary()) from None
    return Button(group, label, command, key)
