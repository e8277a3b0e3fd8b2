"""A throw-away ROS workspace in ``tmp_path`` for launch tests.

Packages are folders with a ``package.xml``, found through
``RosPack([root], use_env=False, bundled=False)``, so nothing outside the
test's own folder is visible.
"""

from __future__ import annotations

import random
import textwrap
from pathlib import Path
from typing import Any

from ddes.launch import LaunchPlan, load_launch
from ddes.rospack import RosPack


class CountingRandom(random.Random):
    """A Random whose ``randint`` counts 0, 1, 2 ...: anon names become ``id_0``, ``id_1``."""

    def __init__(self) -> None:
        super().__init__(0)
        self.n = -1

    def randint(self, a: int, b: int) -> int:
        self.n += 1
        return self.n


class Workspace:
    """Files and packages under one root, plus a RosPack that sees only them."""

    def __init__(self, root: Path) -> None:
        self.root = root
        self.src = root / "src"
        self.src.mkdir(parents=True, exist_ok=True)
        self.environ: dict[str, str] = {"DDES_TEST_VAR": "hello"}

    @property
    def rospack(self) -> RosPack:
        return RosPack([self.src], use_env=False, bundled=False)

    def package(self, name: str) -> Path:
        """Create package ``name`` (a folder with a package.xml) and return its folder."""
        folder = self.src / name
        folder.mkdir(parents=True, exist_ok=True)
        (folder / "package.xml").write_text(
            f'<?xml version="1.0"?>\n<package format="2"><name>{name}</name>'
            "<version>0.0.0</version><description>test</description>"
            "<maintainer email='a@b.c'>a</maintainer><license>BSD</license></package>\n"
        )
        return folder

    def write(self, rel: str, text: str | bytes) -> Path:
        """Write ``text`` (dedented) to ``root/rel`` and return the path."""
        path = self.root / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(text, bytes):
            path.write_bytes(text)
        else:
            path.write_text(textwrap.dedent(text).lstrip("\n"))
        return path

    def load(self, source: str | Path, anon: random.Random | int = 0, **args: str) -> LaunchPlan:
        """load_launch with this workspace's RosPack and environment."""
        if isinstance(source, str) and not source.lstrip().startswith("<"):
            source = self.root / source
        if isinstance(source, str):
            source = textwrap.dedent(source).strip()
        return load_launch(source, args, self.rospack, environ=self.environ, anon_seed=anon)

    def launch(self, rel: str, body: str, anon: random.Random | int = 0,
               **args: str) -> LaunchPlan:
        """Write ``<launch>body</launch>`` to ``rel`` and load it."""
        path = self.write(rel, "<launch>\n" + textwrap.dedent(body).strip("\n") + "\n</launch>\n")
        return self.load(path, anon, **args)


def plan_as_json(plan: LaunchPlan) -> dict[str, Any]:
    """The parts of a plan that roslaunch's config also has, in JSON-able form."""
    import base64

    def enc(v: Any) -> Any:
        if isinstance(v, bytes):
            return {"__bin__": base64.b64encode(v).decode()}
        if isinstance(v, dict):
            return {k: enc(x) for k, x in v.items()}
        if isinstance(v, (list, tuple)):
            return [enc(x) for x in v]
        return v

    return {
        "params": [[k, enc(v)] for k, v in plan.params.items()],
        "nodes": [
            {"pkg": n.pkg, "type": n.type, "name": n.name, "namespace": n.namespace,
             "args": n.args, "remaps": [list(r) for r in n.remappings],
             "env": [list(e) for e in n.env], "output": n.output, "respawn": n.respawn,
             "respawn_delay": n.respawn_delay, "required": n.required, "cwd": n.cwd}
            for n in plan.nodes
        ],
        "clear": plan.clear_params,
        "commands": [[c.command, c.param] + ([c.file] if c.file else [])
                     for c in plan.rosparam_commands],
        "files": plan.files,
        "summary": plan.to_text(),
    }
