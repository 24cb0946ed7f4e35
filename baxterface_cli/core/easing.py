"""Easing functions: plain functions of progress t in [0, 1] -> [0, 1].

Timed moves (`look 40 -20 in 0.5s ease-in-out`) pick one by name; linear is
the default because the original node moved linearly.
"""

from __future__ import annotations

from typing import Callable, Dict

Easing = Callable[[float], float]


def linear(t: float) -> float:
    return t


def ease_in(t: float) -> float:
    return t * t * t


def ease_out(t: float) -> float:
    u = 1.0 - t
    return 1.0 - u * u * u


def ease_in_out(t: float) -> float:
    if t < 0.5:
        return 4.0 * t * t * t
    u = -2.0 * t + 2.0
    return 1.0 - u * u * u / 2.0


EASINGS: Dict[str, Easing] = {
    "linear": linear,
    "ease-in": ease_in,
    "ease-out": ease_out,
    "ease-in-out": ease_in_out,
}
