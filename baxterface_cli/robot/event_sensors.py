"""The robot's senses as events for a live session: the camera's face, the sonar's person, the
navigators' buttons and wheel, the cuffs' buttons. Each turns raw readings into the events a
script reacts to, with the hysteresis or edge detection that keeps a flickering reading from
raising a storm. The clock is the caller's (`at`, seconds); nothing here knows ROS
(ros/robot_senses.py feeds them).
"""

from __future__ import annotations

from typing import Dict, Iterable, List, Optional, Sequence

from ..language import syntax_tree as n
from ..language.events import BUTTONS, CUFF_BUTTONS, CUFFS, NAVIGATORS
from .following import FRONT_SENSORS

SEEN_AFTER = 0.2  # seconds a face must be found before `face seen`
LOST_AFTER = 0.8  # seconds unseen before `face lost`
NEAR = 1.0  # metres: a person this near the head sonar is `person near`
# A cuff's digital inputs (/robot/digital_io/SIDE_INPUT/state) by the names a script uses.
CUFF_INPUTS = dict(zip(("upper_button", "lower_button", "lower_cuff"), CUFF_BUTTONS))
GONE_AFTER = 1.0  # seconds with nobody near before `person gone`
FARTHER_TO_GO = 0.2  # metres past `near` a person must be to count as gone: no flicker at the edge


class Hysteresis:
    """A yes/no reading in, `on` and `off` out: on once it has said yes for `on_after` seconds
    together, off once it has not for `off_after` (a reading of no, or none at all)."""

    def __init__(self, on: str, off: str, on_after: float, off_after: float) -> None:
        if on_after < 0 or off_after < 0:
            raise ValueError("hysteresis times must not be negative")
        self.names = (on, off)
        self.on_after, self.off_after = on_after, off_after
        self.state = False
        self.yes_since: Optional[float] = None
        self.last_yes: Optional[float] = None

    def reading(self, yes: bool, at: float) -> List[n.Event]:
        if yes:
            self.last_yes = at
            if self.yes_since is None:
                self.yes_since = at
        else:
            self.yes_since = None
        return self.check(at)

    def check(self, at: float) -> List[n.Event]:
        """The event that time alone brings about (lost after `off_after` without readings)."""
        if not self.state and self.yes_since is not None and at - self.yes_since >= self.on_after:
            self.state = True
            return [n.Event(self.names[0])]
        if self.state and (self.last_yes is None or at - self.last_yes >= self.off_after):
            self.state = False
            self.yes_since = None
            return [n.Event(self.names[1])]
        return []


class FaceSightings(Hysteresis):
    """The camera watch's answers (a face's target, or None) in; `face seen` and `face lost` out."""

    def __init__(self, seen_after: float = SEEN_AFTER, lost_after: float = LOST_AFTER) -> None:
        super().__init__("face seen", "face lost", seen_after, lost_after)


class SonarPresence:
    """Head sonar readings in; `person near` when a front sensor reads within `near` metres,
    `person gone` when none has read within `near` + FARTHER_TO_GO for `gone_after` seconds."""

    def __init__(self, near: float = NEAR, gone_after: float = GONE_AFTER) -> None:
        if not near > 0:
            raise ValueError("the near distance must be more than 0 m")
        self.near = near
        self.hysteresis = Hysteresis("person near", "person gone", 0.0, gone_after)

    def reading(self, sensor_ids: Iterable[float], distances: Iterable[float], at: float) -> List[n.Event]:
        front = [d for i, d in zip(sensor_ids, distances) if int(i) in FRONT_SENSORS and d > 0]
        nearest = min(front, default=float("inf"))
        reach = self.near + (FARTHER_TO_GO if self.hysteresis.state else 0.0)
        return self.hysteresis.reading(nearest <= reach, at)

    def check(self, at: float) -> List[n.Event]:
        return self.hysteresis.check(at)


class NavigatorPresses:
    """Navigator states in; `button NAVIGATOR BUTTON` on each press (not while held) and
    `button wheel up|down` on each click of a wheel (it wraps at 256)."""

    def __init__(self) -> None:
        self.down: Dict[str, bool] = {}
        self.wheel_at: Dict[str, int] = {}

    def reading(self, navigator: str, buttons: Sequence[bool], wheel: Optional[int]) -> List[n.Event]:
        if navigator not in NAVIGATORS:
            return []
        out = []
        for index, name in enumerate(BUTTONS[: len(buttons)]):
            key = f"{navigator} {name}"
            pressed = bool(buttons[index])
            if pressed and not self.down.get(key, False):
                out.append(n.Event("button", key))
            self.down[key] = pressed
        if wheel is not None:
            value = int(wheel) % 256
            before = self.wheel_at.get(navigator)
            self.wheel_at[navigator] = value
            if before is not None:
                clicks = (value - before + 128) % 256 - 128
                turn = "wheel up" if clicks > 0 else "wheel down"
                out += [n.Event("button", turn) for _ in range(min(abs(clicks), 8))]
        return out


class CuffPresses:
    """A cuff's digital inputs in (`left`, `upper_button`, pressed or not); `button left_cuff dash`
    (`circle`, `squeeze`) out on each press, not while held."""

    def __init__(self) -> None:
        self.down: Dict[str, bool] = {}

    def reading(self, side: str, io_name: str, pressed: bool) -> List[n.Event]:
        cuff, button = f"{side}_cuff", CUFF_INPUTS.get(io_name)
        if cuff not in CUFFS or button is None:
            return []
        key = f"{cuff} {button}"
        was, self.down[key] = self.down.get(key, False), bool(pressed)
        return [n.Event("button", key)] if pressed and not was else []
