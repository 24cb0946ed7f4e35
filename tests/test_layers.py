"""The package's rooms are layered: a room imports only from rooms below it, and nothing closes a circle.

The order is written once, in `baxterface_cli.LAYERS`. Every import is read from the code
itself (at any depth: inside functions too, and under TYPE_CHECKING), so a lazy import that
points up the order fails here as a top-level one would.
"""

from __future__ import annotations

import ast
from pathlib import Path
from typing import Dict, List, Set

import baxterface_cli
from baxterface_cli import LAYERS

PACKAGE = Path(baxterface_cli.__file__).resolve().parent
# The package's own entry points sit above every room; its root helpers below them all.
TOP = {"baxterface_cli", "baxterface_cli.__main__"}


def module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imports(path: Path) -> Set[str]:
    """The modules of ours that `path` imports, anywhere in it."""
    name = module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: Set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found |= {a.name for a in node.names if a.name.startswith("baxterface_cli")}
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module or ""
            if not module.startswith("baxterface_cli"):
                continue
            found.add(module)
            for alias in node.names:  # `from . import x`: x may be a module
                if (
                    (PACKAGE.parent / (module + "." + alias.name).replace(".", "/"))
                    .with_suffix(".py")
                    .exists()
                ):
                    found.add(f"{module}.{alias.name}")
    return found


def graph() -> Dict[str, Set[str]]:
    return {module_name(p): imports(p) for p in PACKAGE.rglob("*.py")}


def room(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 and parts[1] in LAYERS else "(root)"


def rank(module: str) -> int:
    if module in TOP:
        return len(LAYERS) + 1
    r = room(module)
    return 0 if r == "(root)" else 1 + LAYERS.index(r)


def test_every_room_is_in_the_order_and_every_folder_is_a_room():
    rooms = {p.name for p in PACKAGE.iterdir() if p.is_dir() and (p / "__init__.py").exists()}
    assert rooms == set(LAYERS)
    assert len(LAYERS) == len(set(LAYERS))


def test_no_import_points_up_the_order():
    upward = [
        f"{module} ({room(module)}) imports {target} ({room(target)})"
        for module, targets in graph().items()
        for target in targets
        if target != "baxterface_cli" and rank(target) > rank(module)
    ]
    assert not upward, "\n".join(upward)


def test_the_studio_and_the_screen_share_the_web_room_and_neither_imports_the_other():
    # The layer order alone would let the screen, above the studio, import it: what both pages
    # need is the web room's, beneath them.
    crossing = [
        f"{module} imports {target}"
        for module, targets in graph().items()
        for target in targets
        if {room(module), room(target)} == {"studio", "screen"}
    ]
    assert not crossing, "\n".join(crossing)


def test_no_import_closes_a_circle():
    edges = graph()
    done: Set[str] = set()

    def visit(module, path):
        if module in path:
            raise AssertionError(" -> ".join(path[path.index(module) :] + [module]))
        if module in done:
            return
        for target in sorted(edges.get(module, ())):
            if target in edges and target != "baxterface_cli":
                visit(target, path + [module])
        done.add(module)

    for module in sorted(edges):
        if module not in TOP:
            visit(module, [])


def test_the_root_keeps_at_most_eight_modules_and_no_module_is_long():
    assert len(list(PACKAGE.glob("*.py"))) <= 8
    lengths = {
        str(p.relative_to(PACKAGE)): len(p.read_text(encoding="utf-8").splitlines())
        for p in PACKAGE.rglob("*.py")
    }
    assert not {name: n for name, n in lengths.items() if n > 450}


def stem(name: str) -> str:
    """A module name less an ending that only inflects it: renderer, rendering -> render."""
    for ending in ("ing", "er", "es", "s", "ed"):
        if name.endswith(ending) and len(name) - len(ending) >= 3:
            return name[: -len(ending)]
    return name


def test_no_two_module_names_differ_only_by_an_ending():
    names = sorted({p.stem for p in PACKAGE.rglob("*.py")} - {"__init__", "__main__"})
    by_stem: Dict[str, List[str]] = {}
    for name in names:
        by_stem.setdefault(stem(name), []).append(name)
    assert not [group for group in by_stem.values() if len(group) > 1]


def test_a_bag_export_loads_neither_rospy_nor_the_robot_core_nor_the_camera(tmp_path):
    import subprocess
    import sys

    code = (
        "import sys; from baxterface_cli.cli import main\n"
        "try:\n"
        f"    main(['render', '-e', 'happy; nod', '--out', {str(tmp_path / 'x.bag')!r}, '--quiet'])\n"
        "except SystemExit:\n"
        "    pass\n"
        "print(sorted(m for m in sys.modules if m.startswith(('rospy', 'cv2', 'baxterface_cli.robot'))))"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert (tmp_path / "x.bag").exists()
    assert run.stdout.strip().splitlines()[-1] == "[]"
