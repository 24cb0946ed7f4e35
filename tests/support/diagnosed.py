"""What `check` says of a script, a line each as a user reads it: its errors, or its warnings."""

from __future__ import annotations

from typing import List

import pytest

from baxterface_cli import parse
from baxterface_cli.language.diagnostics import ScriptError


def errors(text: str) -> List[str]:
    with pytest.raises(ScriptError) as caught:
        parse(text, "t.face")
    return [d.head("t.face") for d in caught.value.diagnostics]


def warnings(text: str) -> List[str]:
    return [d.head("t.face") for d in parse(text, "t.face").warnings]
