"""What a script calls without defining it: the face's gestures, and the `define`s of `use`d files.

The gestures are face scripts shipped in the package (data/gestures.face), parsed once. A
`use "my-gestures.face"` at a script's top level reads another file's definitions, its path
taken from the script's folder and confined to it as the node's `say file` is
(speech/recordings.py): no absolute path, no `..` or symbolic link out of it. A script with no
folder (a command sent to the node, the screen's POST /api/command) refuses every `use`.

Only what the script calls (through each other's calls) is borrowed, appended to its body as
`define`s of its own, so every reader of a script (the checker, the compiler, `explain`, the
live session) knows them. The script's own `define` of a name comes first, then a used file's,
then the gesture of that name.
"""

from __future__ import annotations

import functools
import os
import re
from dataclasses import dataclass
from typing import Callable, Dict, List, Optional, Sequence, Tuple

from ..resources import resource
from . import syntax_tree as n
from .checker import measure
from .diagnostics import Diagnostic, ScriptError

GESTURES_FILE = "data/gestures.face"
NO_FOLDER = "this script has no folder to read files from"


@dataclass(frozen=True)
class Borrowing:
    """Where a script's `use`s are read from, and whether it knows the gestures."""

    folder: Optional[str] = None  # the script's folder; None refuses every `use`
    root: Optional[str] = None  # the folder no `use` may leave (the first script's)
    gestures: bool = True
    using: Tuple[str, ...] = ()  # the files being read, the first first: a `use` of one is a circle
    refusal: str = NO_FOLDER

    @classmethod
    def in_folder(cls, folder: Optional[str], refusal: str = NO_FOLDER) -> Borrowing:
        real = None if folder is None else os.path.realpath(folder)
        return cls(real, real, refusal=refusal)


# A used file's text, read and parsed: its path, the name its errors give, how it borrows.
Reader = Callable[[str, str, Borrowing], n.Script]


@dataclass(frozen=True)
class Gesture:
    name: str
    seconds: float
    about: str  # what it does in a few words: the comment above its `define`
    define: n.Define
    text: str  # its `define` as the library writes it


@functools.lru_cache(maxsize=1)
def gesture_library(read: Reader) -> Dict[str, Gesture]:
    """The face's gestures by name, in the library's order (`parser.gestures()` reads them)."""
    path = resource(GESTURES_FILE)
    script = read(str(path), GESTURES_FILE, Borrowing(gestures=False))
    lines = script.source.splitlines()
    found: Dict[str, Gesture] = {}
    called: Dict[str, Tuple[float, int]] = {}
    for define in script.body:
        if isinstance(define, n.Define):
            above = lines[define.pos.line - 2] if define.pos.line >= 2 else ""
            about = re.sub(r"^#\s*", "", above.strip()) if above.strip().startswith("#") else ""
            called[define.name] = measure(define.body, called)
            text = "\n".join(_block_lines(lines, define.pos.line - 1))
            found[define.name] = Gesture(define.name, called[define.name][0], about, define, text)
    return found


def _block_lines(lines: List[str], start: int) -> List[str]:
    """The lines of the `define` starting at `start` (0-based), to its closing brace."""
    depth, out = 0, []
    for line in lines[start:]:
        out.append(line)
        depth += line.count("{") - line.count("}")
        if depth <= 0:
            break
    return out


def borrowed(
    body: Sequence[n.Statement], borrowing: Borrowing, read: Reader, out: List[Diagnostic]
) -> Tuple[n.Define, ...]:
    """The definitions `body` calls and does not define, from its `use`s and the gestures."""
    own = {s.name for s in body if isinstance(s, n.Define)}
    offered: Dict[str, Tuple[n.Define, str]] = {}  # name -> its definition, the file it came from
    for statement in body:
        if not isinstance(statement, n.Use) or not statement.path:
            continue
        used = _read_used(statement, borrowing, read, out)
        for define in () if used is None else used.body:
            if not isinstance(define, n.Define) or define.name in own:
                continue
            if define.name in offered and offered[define.name][1] != statement.path:
                _error(
                    out, statement, f"'{define.name}' is defined both here and in {offered[define.name][1]!r}"
                )
            offered.setdefault(define.name, (define, statement.path))
    if borrowing.gestures:
        for name, gesture in gesture_library(read).items():
            offered.setdefault(name, (gesture.define, GESTURES_FILE))
    return called(body, {name: d for name, (d, _) in offered.items() if name not in own})


def called(body: Sequence[n.Statement], offered: Dict[str, n.Define]) -> Tuple[n.Define, ...]:
    """The definitions of `offered` that `body` calls, through each other's calls, in the order
    first called; without recursion, so blocks nested as deep as the parser allows cost no stack."""
    taken: Dict[str, n.Define] = {}
    stack = [iter(body)]
    while stack:
        statement = next(stack[-1], None)
        if statement is None:
            stack.pop()
            continue
        if isinstance(statement, n.Call):
            name = statement.name
            if name not in taken and name in offered:
                taken[name] = offered[name]
                stack.append(iter(offered[name].body))
        elif isinstance(statement, n.BLOCKS):
            stack.append(iter(statement.body))
    return tuple(taken.values())


def _read_used(use: n.Use, borrowing: Borrowing, read: Reader, out: List[Diagnostic]) -> Optional[n.Script]:
    written = use.path
    if borrowing.folder is None or borrowing.root is None:
        _error(out, use, f"cannot use {written!r}: {borrowing.refusal}")
        return None
    if os.path.isabs(written) or written.startswith("~"):
        _error(out, use, f"cannot use {written!r}: give a path from the script's folder, not an absolute one")
        return None
    root = borrowing.root
    real = os.path.realpath(os.path.join(borrowing.folder, written))
    if os.path.commonpath([real, root]) != root:
        _error(out, use, f"cannot use {written!r}: it is outside {root}, the folder of the script")
        return None
    if real in borrowing.using:
        chain = " -> ".join(os.path.relpath(p, root) for p in borrowing.using[borrowing.using.index(real) :])
        _error(
            out,
            use,
            f"cannot use {written!r}: it uses this file again ({chain} -> {written}); 'use' cannot go round",
        )
        return None
    if not os.path.isfile(real):
        _error(out, use, f"cannot use {written!r}: there is no such file in {os.path.dirname(real)}")
        return None
    inner = Borrowing(os.path.dirname(real), root, borrowing.gestures, borrowing.using + (real,))
    try:
        return read(real, written, inner)
    except ScriptError as e:
        first = next((d for d in e.diagnostics if d.severity == "error"), None)
        where = f"{written}:{first.line}:{first.column}: {first.message}" if first else str(e)
        _error(out, use, f"cannot use {written!r}: it has errors: {where}")
    except OSError as e:
        _error(out, use, f"cannot use {written!r}: {e.strerror or e}")
    return None


def top_level_only(body: Sequence[n.Statement], out: List[Diagnostic]) -> None:
    """Report a `use` inside a block: it brings definitions, which are only at the top level."""
    stack = [s.body for s in body if isinstance(s, n.BLOCKS)]
    while stack:
        for statement in stack.pop():
            if isinstance(statement, n.Use):
                _error(out, statement, "'use' is only allowed at the top level of a script")
            elif isinstance(statement, n.BLOCKS):
                stack.append(statement.body)


def _error(out: List[Diagnostic], node: n.Statement, message: str) -> None:
    out.append(Diagnostic(node.pos.line, node.pos.column, message))
