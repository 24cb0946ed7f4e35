"""The language documentation tells the truth: its examples and its table parse."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from baxterface_cli import parse
from baxterface_cli.vocabulary import BARE_WORDS, LEGACY_USAGE

pytestmark = pytest.mark.language

ROOT = Path(__file__).resolve().parent.parent
DOC = (ROOT / "docs" / "language.md").read_text(encoding="utf-8")
README = (ROOT / "README.md").read_text(encoding="utf-8")


def fenced_blocks(text):
    """(language tag, body) of each fenced block, in order."""
    blocks, tag, lines = [], None, []
    for line in text.splitlines():
        if line.startswith("```"):
            if tag is None:
                tag, lines = line[3:].strip(), []
            else:
                blocks.append((tag, "\n".join(lines)))
                tag = None
        elif tag is not None:
            lines.append(line)
    return blocks


# Untagged blocks are face scripts; console, python and text blocks are not.
SCRIPT_BLOCKS = [body for tag, body in fenced_blocks(DOC) + fenced_blocks(README) if tag == ""]
LEGACY_ROWS = re.findall(r"^\| `([a-z0-9_.-]+)` \| `([^`]+)` \|$", DOC, re.M)


@pytest.mark.parametrize("block", SCRIPT_BLOCKS, ids=[f"block{i}" for i in range(len(SCRIPT_BLOCKS))])
def test_every_script_example_parses(block):
    parse(block)


def test_the_legacy_table_is_right_and_complete():
    assert len(LEGACY_ROWS) >= 27
    for legacy, script in LEGACY_ROWS:
        assert parse(legacy).body == parse(script).body, legacy
    documented = {legacy for legacy, _ in LEGACY_ROWS}
    for word in BARE_WORDS:
        if "_" in word:
            assert word in documented
    for command in LEGACY_USAGE:
        assert any(row.startswith(command + "_") for row in documented), command
