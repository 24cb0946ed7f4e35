"""What a page is told went wrong, as JSON: a script's diagnostics, or a problem with no place in it.

No Starlette here: the studio's workspace, which works without the web, says its checks in
the very form the routes answer with.
"""

from __future__ import annotations

from typing import Any, Dict, List

from ..language.diagnostics import Diagnostic


def diagnostics_json(diagnostics: List[Diagnostic]) -> List[Dict[str, Any]]:
    return [
        {"line": d.line, "column": d.column, "severity": d.severity, "message": d.message}
        for d in diagnostics
    ]


def problem(message: str, severity: str = "error") -> Dict[str, Any]:
    """A diagnostic with no place in the text."""
    return {"line": 0, "column": 0, "severity": severity, "message": message}
