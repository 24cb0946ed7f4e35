"""Golden tests of what `baxterface check` prints for bad scripts.

Each tests/golden/errors/NAME.face has beside it NAME.txt: the exact text
check writes to stderr. After a deliberate change to the messages,
`make golden` rewrites the .txt files; review them with `git diff`.
"""

from __future__ import annotations

import os
import re

import pytest

from baxterface_cli.core.face_constants import LIMITS
from conftest import ROOT, baxterface

pytestmark = pytest.mark.language

GOLDEN = ROOT / "tests" / "golden" / "errors"
CASES = sorted(GOLDEN.glob("*.face"))
UPDATE = os.environ.get("BAXTERFACE_UPDATE_GOLDEN") == "1"


@pytest.mark.parametrize("case", CASES, ids=[c.stem for c in CASES])
def test_check_output_matches_golden(case):
    run = baxterface("check", str(case.relative_to(ROOT)))
    expected_file = case.with_suffix(".txt")
    if UPDATE:
        expected_file.write_text(run.err, encoding="utf-8")
    expected = expected_file.read_text(encoding="utf-8")
    assert run.err == expected
    assert run.out == ""
    assert run.code == (1 if ": error: " in expected else 0)
    assert "Traceback" not in run.err


def test_goldens_cover_line_column_caret_and_suggestion():
    # The golden files themselves must show what users rely on.
    text = (GOLDEN / "did_you_mean.txt").read_text(encoding="utf-8")
    assert (
        "tests/golden/errors/did_you_mean.face:3:7: error: unknown mouth 'smil'; did you mean 'smile'?"
        in text
    )
    assert "\n    mouth smil\n          ^\n" in text
    tabs = (GOLDEN / "tabs.txt").read_text(encoding="utf-8")
    assert "\n    \t\tmouth smiel\n    \t\t      ^\n" in tabs


FLOODS = {
    "unknown words": ("a\n", 1),
    "misspellings": ("hapy\n", 1),
    "warnings": ("look 500 0 in 0s\n", 0),
}


@pytest.mark.parametrize("line, code", FLOODS.values(), ids=list(FLOODS))
def test_a_flood_of_problems_prints_the_first_and_counts_the_rest(tmp_path, line, code):
    pieces = len(line.split()) + 1  # words and the new line
    count = min(LIMITS.max_bytes // len(line), LIMITS.max_pieces // pieces)
    path = tmp_path / "flood.face"
    path.write_text(line * count, encoding="utf-8")
    run = baxterface("check", str(path))
    assert run.code == code and "Traceback" not in run.err
    heads = [x for x in run.err.splitlines() if re.match(re.escape(str(path)) + r":\d+:\d+: ", x)]
    assert len(heads) == LIMITS.max_shown
    what = "errors" if code else "warnings"
    assert run.err.splitlines()[-1] == f"{path}: ... and {count - LIMITS.max_shown} more {what}"


def test_a_script_of_too_many_pieces_is_refused_at_the_first_one_past_the_limit(tmp_path):
    lines = LIMITS.max_pieces // 2 + 10  # 'a' and a new line: two pieces each
    path = tmp_path / "many.face"
    path.write_text("a\n" * lines, encoding="utf-8")
    run = baxterface("check", str(path))
    first_past = LIMITS.max_pieces // 2 + 1
    assert run.code == 1
    assert run.err.splitlines()[0] == (
        f"{path}:{first_past}:1: error: script is too long to read: more than {LIMITS.max_pieces} "
        "words, numbers and separators; split it into smaller scripts"
    )
    assert "more errors" not in run.err  # one error, not a flood of unknown words
