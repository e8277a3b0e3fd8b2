#!/usr/bin/env python3
"""Check a built sdist: it carries every file git tracks (the tests, docs, examples,
benchmarks and CI scripts with the package) and no caches.

``python3 .ci/check_sdist.py dist/ddes-0.1.0.tar.gz`` prints what is missing or stray and
exits 1, or prints a one-line summary and exits 0.
"""

from __future__ import annotations

import subprocess
import sys
import tarfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: Tracked files an sdist has no use for.
NOT_SHIPPED = {".gitignore"}
#: Folders the sdist must have, whether or not git is at hand to list the tracked files.
REQUIRED_DIRS = ("ddes", "tests", "docs", "examples", "benchmarks", ".ci")
REQUIRED_FILES = ("LICENSE", "README.md", "pyproject.toml", "PKG-INFO")
STRAY = ("__pycache__", ".pyc", ".hypothesis", ".pytest_cache", ".mypy_cache", ".ruff_cache",
         ".venv", ".egg-info/", ".bag.active")


def members(sdist: Path) -> set[str]:
    """The sdist's file names, without the leading ``ddes-X.Y.Z/``."""
    with tarfile.open(sdist) as tar:
        return {m.name.split("/", 1)[1] for m in tar.getmembers() if m.isfile() and "/" in m.name}


def tracked() -> set[str]:
    """The files git tracks (empty when this is no git checkout)."""
    try:
        out = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True)
    except (OSError, subprocess.CalledProcessError):
        return set()
    names = {name for name in out.stdout.decode().split("\0") if name} - NOT_SHIPPED
    return {name for name in names if (ROOT / name).is_file()}  # not one deleted, uncommitted


def problems(names: set[str], expected: set[str]) -> list[str]:
    """What is wrong with an sdist holding ``names`` (``expected``: tracked files)."""
    found = [f"missing: {name}" for name in sorted(expected - names)]
    found += [f"missing: {name}" for name in REQUIRED_FILES if name not in names]
    found += [f"missing folder: {d}/" for d in REQUIRED_DIRS
              if not any(n.startswith(d + "/") for n in names)]
    found += [f"stray: {name}" for name in sorted(names)
              if any(s in name for s in STRAY) and not name.startswith("ddes.egg-info/")]
    return found


def main(argv: list[str]) -> int:
    if len(argv) != 1:
        print("usage: check_sdist.py SDIST", file=sys.stderr)
        return 2
    names = members(Path(argv[0]))
    found = problems(names, tracked())
    for line in found:
        print(f"{argv[0]}: {line}", file=sys.stderr)
    if found:
        return 1
    print(f"{argv[0]}: {len(names)} files, every tracked file included, no caches")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
