#!/usr/bin/env python3
"""Print the Python interpreters this machine has that pyproject.toml's ``requires-python``
admits, oldest first, one ``X.Y PATH`` line each (``--oldest``: only the first line).

Looks for ``pythonX.Y`` on PATH, then under pyenv's versions folder (``$PYENV_ROOT`` or
``~/.pyenv``: a pyenv shim that is not the selected version fails and is skipped), then in
/usr/local/bin and /usr/bin; each candidate is run to check that it works and is X.Y.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
MINORS = range(8, 20)  # 3.8 .. 3.19: whichever of them requires-python admits


def requires_python(pyproject: Path = ROOT / "pyproject.toml") -> str:
    match = re.search(r'^requires-python\s*=\s*"([^"]*)"', pyproject.read_text(encoding="utf-8"),
                      flags=re.M)
    if match is None:
        raise SystemExit("find_pythons: pyproject.toml has no requires-python")
    return match.group(1)


def admits(spec: str, version: tuple[int, int]) -> bool:
    """Whether ``spec`` (``>=3.10``, ``>=3.10,<3.14``, ``!=3.11.*`` ...) admits X.Y."""
    for clause in filter(None, (c.strip() for c in spec.split(","))):
        match = re.fullmatch(r"(>=|<=|==|!=|>|<|~=)\s*(\d+)\.(\d+)(?:\.\*|\.0)?", clause)
        if match is None:
            raise SystemExit(f"find_pythons: cannot read requires-python clause {clause!r}")
        op, want = match.group(1), (int(match.group(2)), int(match.group(3)))
        ok = {">=": version >= want, "<=": version <= want, ">": version > want,
              "<": version < want, "==": version == want, "!=": version != want,
              "~=": version >= want and version[0] == want[0]}[op]
        if not ok:
            return False
    return True


def candidates(minor: int) -> list[str]:
    name = f"python3.{minor}"
    found = [p for p in [shutil.which(name)] if p]
    root = Path(os.environ.get("PYENV_ROOT", Path.home() / ".pyenv"))
    found += sorted((str(p) for p in root.glob(f"versions/3.{minor}.*/bin/{name}")),
                    key=lambda p: [int(x) for x in re.findall(r"\d+", p.split("/versions/")[1])[:3]],
                    reverse=True)
    found += [f"{d}/{name}" for d in ("/usr/local/bin", "/usr/bin")]
    return found


def works(path: str, minor: int) -> bool:
    try:
        out = subprocess.run([path, "-c", "import sys, venv; print(sys.version_info[:2])"],
                             capture_output=True, text=True, timeout=30, check=False)
    except (OSError, subprocess.TimeoutExpired):
        return False
    return out.returncode == 0 and out.stdout.strip() == f"(3, {minor})"


def find(spec: str) -> list[tuple[str, str]]:
    found = []
    for minor in MINORS:
        if admits(spec, (3, minor)):
            path = next((p for p in candidates(minor) if works(p, minor)), None)
            if path is not None:
                found.append((f"3.{minor}", path))
    return found


if __name__ == "__main__":
    pythons = find(requires_python())
    if not pythons:
        sys.exit(f"find_pythons: no Python on this machine satisfies {requires_python()}")
    for version, path in pythons[:1] if "--oldest" in sys.argv[1:] else pythons:
        print(version, path)
