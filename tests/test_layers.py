"""The import-layer rule of docs/architecture.md, checked on every module of ddes.

Each module may import only modules of its own package and of lower layers;
peers in one layer never import each other.  Every import counts: module
level, inside functions, and under ``if TYPE_CHECKING:``.  The file-format
half of ``ddes.rosbag`` may use only errors, expr, display, time, rospack and
msg, so bags can be read without a world.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import ddes

REPO = Path(__file__).resolve().parents[1]
#: The source tree of the checkout (the installed copy when tests run elsewhere).
ROOT = REPO / "ddes" if (REPO / "ddes" / "__init__.py").is_file() else Path(ddes.__file__).parent

#: Bottom to top.  A group of several names is one layer of peers.
LAYERS: list[tuple[str, ...]] = [
    ("errors", "_version", "_floats"),
    ("expr", "display", "transformations"),
    ("time",),
    ("kernel",),
    ("rospack",),
    ("msg",),
    ("graph",),
    ("services",),
    ("actionlib", "dynamic_reconfigure", "rosbag", "tf2"),
    ("tf2_ros",),
    ("rqt",),
    ("sim",),
    ("compat", "roscpp"),
    ("nodes", "packages"),
    ("launch",),
    ("console",),
    ("facade",),
    ("testing",),
    ("grading",),  # the grader uses the protocol checks of ddes.testing
    ("cli",),
]

#: Groups that form one room although they are two folders.
SAME_ROOM = {"packages": "nodes"}

#: rosbag's file-format modules: readable without a world.
ROSBAG_FORMAT = {"bag", "bagfile", "records", "info", "mcapfile", "ops"}
ROSBAG_FORMAT_MAY_USE = {"errors", "_version", "expr", "display", "time", "rospack", "msg",
                         "rosbag"}

RANK = {name: i for i, group in enumerate(LAYERS) for name in group}


def room_of(module: str) -> str:
    """``ddes.graph.node`` -> ``graph``; ``ddes`` and ``ddes.world`` -> ``facade``;
    ``ddes.__main__`` (``python -m ddes``, an entry point of the command) -> ``cli``."""
    parts = module.split(".")
    if parts[0] != "ddes":
        raise ValueError(module)
    if len(parts) == 1 or parts[1] == "world":
        return "facade"
    if parts[1] == "__main__":
        return "cli"
    return parts[1]


def modules() -> list[tuple[str, Path]]:
    out = []
    for path in sorted(ROOT.rglob("*.py")):
        rel = path.relative_to(ROOT.parent).with_suffix("")
        parts = list(rel.parts)
        if parts[-1] == "__init__":
            parts.pop()
        out.append((".".join(parts), path))
    return out


def imports_of(module: str, path: Path) -> list[tuple[int, str]]:
    """Every ddes module ``module`` imports, with line numbers (all scopes)."""
    tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    found: list[tuple[int, str]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [(node.lineno, a.name) for a in node.names if a.name.split(".")[0] == "ddes"]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.split(".")[0] != "ddes":
                continue
            if target == "ddes":  # from ddes import graph  -> the submodule, else the facade
                for alias in node.names:
                    sub = ROOT / alias.name
                    is_sub = sub.is_dir() or sub.with_suffix(".py").is_file()
                    found.append((node.lineno, f"ddes.{alias.name}" if is_sub else "ddes"))
            else:
                found.append((node.lineno, target))
    return found


def violations() -> list[str]:
    bad = []
    for module, path in modules():
        room = SAME_ROOM.get(room_of(module), room_of(module))
        if room not in RANK:
            bad.append(f"{module}: room {room!r} has no layer; add it to LAYERS and the docs")
            continue
        for line, target in imports_of(module, path):
            troom = SAME_ROOM.get(room_of(target), room_of(target))
            where = f"{path.relative_to(ROOT.parent)}:{line}: {module} imports {target}"
            if troom not in RANK:
                bad.append(f"{where} (unknown room {troom!r})")
                continue
            if troom == room:
                pass
            elif RANK[troom] == RANK[room]:
                bad.append(f"{where}: peers {room} and {troom} must not import each other")
            elif RANK[troom] > RANK[room]:
                bad.append(f"{where}: {room} is below {troom}")
            if room == "rosbag" and module.split(".")[2:3] and module.split(".")[2] in ROSBAG_FORMAT:
                if troom not in ROSBAG_FORMAT_MAY_USE or (
                        troom == "rosbag" and target.split(".")[2:3]
                        and target.split(".")[2] not in ROSBAG_FORMAT):
                    bad.append(f"{where}: rosbag's file layer may use only errors, time, "
                               "rospack, msg and its own format modules")
    return bad


def test_every_import_follows_the_layers() -> None:
    bad = violations()
    assert not bad, "import-layer violations:\n" + "\n".join(bad)


def test_every_room_is_documented() -> None:
    text = (REPO / "docs" / "architecture.md").read_text(encoding="utf-8")
    rooms = {SAME_ROOM.get(room_of(m), room_of(m)) for m, _ in modules()}
    for room in sorted(rooms - {"facade", "_version"}):
        assert f"`{room}" in text, f"docs/architecture.md does not describe {room}"


@pytest.mark.parametrize("source, expected", [
    ("import ddes.graph.node\n", ["ddes.graph.node"]),
    ("from ddes.graph import node\n", ["ddes.graph"]),
    ("from ddes import graph, World\n", ["ddes.graph", "ddes"]),
    ("def f():\n    from ddes.services import Service\n", ["ddes.services"]),
    ("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from ddes.cli import main\n",
     ["ddes.cli"]),
    ("from . import topics\n", ["ddes.graph"]),
    ("from ..msg import spec\n", ["ddes.msg"]),
])
def test_the_checker_sees_every_kind_of_import(tmp_path: Path, source: str,
                                               expected: list[str]) -> None:
    path = tmp_path / "mod.py"
    path.write_text(source)
    assert [t for _, t in imports_of("ddes.graph.mod", path)] == expected


def test_the_checker_rejects_an_upward_import(tmp_path: Path, monkeypatch: pytest.MonkeyPatch
                                              ) -> None:
    pkg = tmp_path / "ddes"
    (pkg / "time").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "time" / "__init__.py").write_text("")
    (pkg / "time" / "bad.py").write_text("def f():\n    from ddes.graph.node import Node\n")
    (pkg / "rosbag").mkdir()
    (pkg / "rosbag" / "__init__.py").write_text("")
    (pkg / "rosbag" / "bag.py").write_text("from ddes.kernel import Kernel\n")
    (pkg / "actionlib").mkdir()
    (pkg / "actionlib" / "__init__.py").write_text("from ddes.rosbag import Bag\n")
    monkeypatch.setitem(globals(), "ROOT", pkg)
    bad = violations()
    assert any("time is below graph" in b for b in bad), bad
    assert any("rosbag's file layer" in b for b in bad), bad
    assert any("peers actionlib and rosbag" in b for b in bad), bad
