"""A command on a live face as the screen runs one that reacts to nothing (screen/screen_face.py)."""

from __future__ import annotations

from baxterface_cli.engine.live_face import LiveFace
from baxterface_cli.language.parser import parse


def command(live: LiveFace, text: str, now: float, filename: str = "display_chatter") -> None:
    """Compile `text` from the face as it is at `now` (what began finishing), and begin it there."""
    live.begin(live.take_over(parse(text, filename), now), now)
