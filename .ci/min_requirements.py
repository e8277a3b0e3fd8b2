#!/usr/bin/env python3
"""Print pyproject.toml's requirements pinned at their lower bounds, one per line.

``python3 .ci/min_requirements.py test`` prints ``[project] dependencies`` and the ``test``
extra with every ``>=X`` turned into ``==X`` (other bounds dropped; a requirement without a
lower bound is printed as it stands), for ``pip install -r`` in ``.ci/min-versions``: the
lower bounds pyproject.toml states are the versions CI installs and tests.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib  # type: ignore[no-redef,import-not-found,unused-ignore]

ROOT = Path(__file__).resolve().parent.parent
_REQ = re.compile(r"^\s*([A-Za-z0-9][A-Za-z0-9._-]*)\s*(\[[^\]]*\])?\s*([^;]*?)\s*(;.*)?$")


def pin_lower_bound(requirement: str) -> str:
    """``"simpy>=4.1,<5"`` -> ``"simpy==4.1"``; ``"types-PyYAML"`` stays as it is."""
    match = _REQ.match(requirement)
    if match is None:
        raise ValueError(f"cannot read the requirement {requirement!r}")
    name, extras, specs, marker = match.groups()
    lower = [s.strip()[2:].strip() for s in specs.split(",") if s.strip().startswith(">=")]
    if not lower:
        return requirement.strip()
    return f"{name}{extras or ''}=={lower[0]}{' ' + marker if marker else ''}"


def requirements(extras: list[str], pyproject: Path = ROOT / "pyproject.toml") -> list[str]:
    """The dependencies and the named extras of ``pyproject``, pinned at their lower bounds."""
    project = tomllib.loads(pyproject.read_text(encoding="utf-8"))["project"]
    found = list(project.get("dependencies", []))
    optional = project.get("optional-dependencies", {})
    for extra in extras:
        if extra not in optional:
            raise SystemExit(f"min_requirements: pyproject.toml has no extra {extra!r}")
        found.extend(optional[extra])
    return [pin_lower_bound(r) for r in found]


if __name__ == "__main__":
    print("\n".join(requirements(sys.argv[1:])))
