"""The command line's number options, NaN and infinity refused.

click reads 'nan' and 'inf' as floats, and NaN passes every range check (each comparison is
false): `--duration nan` ran for ever and `--fps nan` ended in a traceback. Each float option
gives `finite` as its callback, which says no to them as to a number out of range.
"""

from __future__ import annotations

import math
from typing import Optional

import typer


def finite(value: Optional[float]) -> Optional[float]:
    if value is not None and not math.isfinite(value):
        raise typer.BadParameter(f"{value} is not a finite number.")
    return value
