"""The fenced blocks of the README and docs/, for the tests that run them."""

from __future__ import annotations

import re
from pathlib import Path
from typing import List, NamedTuple, Optional

ROOT = Path(__file__).resolve().parents[2]
DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


class Block(NamedTuple):
    tag: str  # the language after the fence: "", "console", "python", ...
    body: str
    before: str  # the prose between the previous block and this one


def fenced_blocks(text: str) -> List[Block]:
    """Each fenced block, in order."""
    blocks: List[Block] = []
    tag: Optional[str] = None
    lines: List[str] = []
    prose: List[str] = []
    for line in text.splitlines():
        if line.startswith("```"):
            if tag is None:
                tag, lines = line[3:].strip(), []
            else:
                blocks.append(Block(tag, "\n".join(lines), "\n".join(prose)))
                tag, prose = None, []
        elif tag is not None:
            lines.append(line)
        else:
            prose.append(line)
    return blocks


def console_commands(block: Block) -> List[str]:
    """The `$ ` commands of a console block, without their trailing comments."""
    lines = block.body.splitlines()
    return [re.sub(r"\s{2,}#.*$", "", line[2:]).strip() for line in lines if line.startswith("$ ")]


class PythonExample(NamedTuple):
    doc: str
    number: int  # the how-manieth Python block of its doc, from 1
    code: str
    expected: Optional[List[str]]  # what it prints, where the doc shows it
    setup: List[str]  # console commands before it in its doc that made what it uses


def printed_in_comments(code: str) -> List[str]:
    """The output a block shows as comment lines right after a line that prints."""
    out: List[str] = []
    lines = code.splitlines()
    for i, line in enumerate(lines):
        if "print(" not in line:
            continue
        for following in lines[i + 1 :]:
            if not following.startswith("# "):
                break
            out.append(following[2:])
    return out


def python_examples(paths=DOCS) -> List[PythonExample]:
    """Every Python block of the docs, with the output shown after it, if any.

    A block's output is either the comment lines that follow a print, or a
    text block that follows the Python block with nothing but blank lines between.
    """
    examples: List[PythonExample] = []
    for path in paths:
        blocks = fenced_blocks(path.read_text(encoding="utf-8"))
        number = 0
        for i, block in enumerate(blocks):
            if block.tag != "python":
                continue
            number += 1
            expected: Optional[List[str]] = printed_in_comments(block.body) or None
            after = blocks[i + 1] if i + 1 < len(blocks) else None
            if after is not None and after.tag == "text" and not after.before.strip():
                expected = after.body.splitlines()
            setup = [
                command
                for earlier in blocks[:i]
                if earlier.tag == "console"
                for command in console_commands(earlier)
                if " export " in command
            ]
            examples.append(PythonExample(path.name, number, block.body, expected, setup))
    return examples
