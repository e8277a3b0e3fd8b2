#!/usr/bin/env python3
"""Print the shell commands of README.md's set-up section, in order, one per line.

``.ci/run`` runs exactly these, so CI installs and tests ddes as the README tells a student to
(tests/cli/test_packaging.py checks what they install).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

README = Path(__file__).resolve().parent.parent / "README.md"
SECTION = "## Set-up"


def setup_commands(text: str) -> list[str]:
    """The lines of the ```sh blocks between ``## Set-up`` and the next ``## `` heading."""
    start = text.find("\n" + SECTION)
    if start < 0:
        raise SystemExit(f"readme_commands: README.md has no {SECTION!r} section")
    end = text.find("\n## ", start + 1)
    section = text[start:end if end >= 0 else len(text)]
    blocks = re.findall(r"```sh\n(.*?)```", section, flags=re.S)
    return [line for block in blocks for line in block.splitlines() if line.strip()]


if __name__ == "__main__":
    commands = setup_commands(README.read_text(encoding="utf-8"))
    if not commands:
        sys.exit("readme_commands: README.md's set-up section has no ```sh block")
    print("\n".join(commands))
