"""The screen's state tells what its face shows when a command comes hard on an emotion's heels."""

from __future__ import annotations

from baxterface_cli.core.face_constants import EMOTIONS
from baxterface_cli.screen.screen_face import ScreenFace


class Clock:
    def __init__(self, now: float = 100.0) -> None:
        self.now = now

    def __call__(self) -> float:
        return self.now


def test_happy_sad_then_a_wink_a_tenth_later_shows_sad_as_the_state_says():
    clock = Clock()
    face = ScreenFace(seed=0, idle=False, clock=clock)
    face.command("happy")
    clock.now += 2.0
    face.command("sad")
    clock.now += 0.1
    face.command("wink left")
    clock.now += 2.0
    shown = face.face(clock.now)
    assert shown.emotion == "sad"
    assert shown.skin == EMOTIONS["sad"].skin and (shown.mouth, shown.brows) in EMOTIONS["sad"].variants
