"""A statement in words, as `explain` lists it: `look 40 -20 in 0.5s`, `happy 0.6 + confused 0.4`."""

from __future__ import annotations

from typing import Any

from ..language import syntax_tree as n
from ..language.durations import move_seconds, statement_seconds
from . import effects as fx


def describe(s: Any) -> str:
    """A statement in words, for `explain`."""

    def timed(s: Any) -> str:
        easing = s.timing.easing
        seconds = statement_seconds(s) if isinstance(s, n.Feeling) else move_seconds(s)
        return f" in {seconds:g}s" + ("" if easing == "linear" else f" {easing}")

    if isinstance(s, n.Emotion):
        return s.name + ("" if s.variant is None else f" variant {s.variant}")
    if isinstance(s, n.Look):
        kind = "dynamic look" if s.dynamic else "look"
        return f"{kind} {s.x:g} {s.y:g}{timed(s)}"
    if isinstance(s, n.Wobble):
        return f"wobble {fx.radians_and_degrees(s.angle)}{timed(s)}"
    if isinstance(s, n.Eyelids):
        return f"eyelids {s.openness:g}{timed(s)}"
    if isinstance(s, n.Wait):
        return f"wait {s.duration:g}s"
    if isinstance(s, n.Skin):
        return f"skin {s.index}"
    if isinstance(s, n.Mouth):
        return f"mouth {s.name}"
    if isinstance(s, n.Brows):
        return f"brows {s.side + ' ' if s.side else ''}{s.name}"
    if isinstance(s, n.Feeling):
        variants = list(s.variants) + [None] * (len(s.weights) - len(s.variants))
        blend = " + ".join(
            name.replace(" ", "_")
            + ("" if variant is None else f" variant {variant}")
            + ("" if len(s.weights) == 1 and weight == 1 else f" {weight:g}")
            for (name, weight), variant in zip(s.weights, variants)
        )
        return blend + (timed(s) if s.timing.duration is not None else "")
    if isinstance(s, n.Mood):
        return f"mood {s.valence:g} {s.arousal:g}{timed(s)}"
    if isinstance(s, n.Wink):
        return f"wink {s.side}"
    if isinstance(s, n.Adjust):
        words = " ".join(w for w in (s.part, s.side, s.control) if w)
        return f"{words} {s.value:g}{timed(s)}"
    if isinstance(s, n.Say) and s.file is not None:
        return (
            f"say file {fx.quoted(s.file)}"
            + (f" text {fx.quoted(s.text)}" if s.text else "")
            + (f" language {s.language}" if s.language else "")
        )
    if isinstance(s, n.Say):
        return (
            f"say {fx.quoted(s.text)}"
            + (f" voice {s.voice}" if s.voice else "")
            + (f" rate {s.rate}" if s.rate else "")
        )
    if isinstance(s, n.Follow):
        if s.target is None:
            return "follow off"
        return f"follow {s.target}" + (" dynamic" if s.dynamic else "")
    return type(s).__name__.lower()
