"""A script's length against its limit, and in words: the one place both are decided.

Lengths are sums of many statements' seconds, so float rounding can put a script of exactly
the limit (`repeat 6000 { wink left }`, 6000 x 0.6 s) a hair over it: lengths are compared to
the microsecond. In words they are exact to the microsecond too, so a script over the limit
never reads as on it (`1 hour 0.001 s`), and one just over a minute never reads as a minute more.
"""

from __future__ import annotations

from ..core.face_constants import LIMITS

_MICRO = 1_000_000


def micro(seconds: float) -> int:
    """`seconds` in whole microseconds."""
    return int(round(seconds * _MICRO))


def over_limit(seconds: float, limit: float = LIMITS.max_seconds) -> bool:
    """Is a script that runs `seconds` longer than `limit`, to the microsecond?"""
    return micro(seconds) > micro(limit)


def in_words(seconds: float) -> str:
    """`3600.001` as "1 hour 0.001 s", `3660` as "1 hour 1 minute", `42.5` as "42.5 s": to the
    millisecond, unless that would read as the limit itself (`3600.0004` as "1 hour 0.0004 s")."""
    exact = micro(seconds)
    shown = int(round(exact, -3))
    if over_limit(seconds) and shown <= micro(LIMITS.max_seconds):
        shown = exact
    hours, rest = divmod(shown, 3600 * _MICRO)
    minutes, rest = divmod(rest, 60 * _MICRO)
    parts = [
        f"{k} {unit}" + ("" if k == 1 else "s") for k, unit in ((hours, "hour"), (minutes, "minute")) if k
    ]
    if rest or not parts:
        parts.append(f"{rest / _MICRO:.6f}".rstrip("0").rstrip(".") + " s")
    return " ".join(parts)
