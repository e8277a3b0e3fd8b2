"""Starter code generated from reference solutions (``ddes course build``).

Every file of ``solutions/<id>/`` is copied to ``exercises/<id>/`` except ``mutants/`` and
``__pycache__``.  In a text file, a block between two whole lines ``### BEGIN SOLUTION`` and
``### END SOLUTION`` (nbgrader's delimiters; in XML written inside a comment,
``<!-- ### BEGIN SOLUTION -->``) becomes one stub line at the block's indentation:

* Python: ``raise NotImplementedError("your code here")``, or the text after ``stub:`` on the
  BEGIN line (``### BEGIN SOLUTION stub: pass  # your code here``);
* XML/launch: ``<!-- your code here -->``; YAML, RViz configs, anything else: ``# your code here``.

:func:`build` writes the tree and returns the files it changed; with ``check=True`` it writes
nothing and returns the files that are out of date (``ddes course build --check``).
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path

from ddes.errors import GradingError

__all__ = ["SKIP", "build", "starter_text"]

#: Folders of a solution that students never receive.
SKIP = ("mutants", "__pycache__", ".pytest_cache")

_BEGIN = re.compile(r"^(\s*)(?:<!--\s*)?(?:#\s*)?### BEGIN SOLUTION(?:\s+stub:\s*(.*?))?\s*(?:-->)?\s*$")
_END = re.compile(r"^\s*(?:<!--\s*)?(?:#\s*)?### END SOLUTION\s*(?:-->)?\s*$")


def _stub(path: str, indent: str, custom: str | None) -> str:
    if custom:
        return f"{indent}{custom}\n"
    if path.endswith(".py"):
        return f'{indent}raise NotImplementedError("your code here")\n'
    if path.endswith((".launch", ".xml", ".world", ".sdf", ".urdf")):
        return f"{indent}<!-- your code here -->\n"
    return f"{indent}# your code here\n"


def starter_text(text: str, path: str = "file.py") -> str:
    """``text`` with every solution block replaced by its stub; a BEGIN without END (or the
    reverse) raises :class:`GradingError` naming the file and line."""
    out: list[str] = []
    inside: int | None = None
    for n, line in enumerate(text.splitlines(keepends=True), 1):
        begin = _BEGIN.match(line)
        if begin:
            if inside is not None:
                raise GradingError(f"{path}:{n}: BEGIN SOLUTION inside the block opened at line "
                                   f"{inside}; close it with ### END SOLUTION first")
            inside = n
            out.append(_stub(path, begin.group(1), begin.group(2)))
        elif _END.match(line):
            if inside is None:
                raise GradingError(f"{path}:{n}: END SOLUTION without a BEGIN SOLUTION")
            inside = None
        elif inside is None:
            out.append(line)
    if inside is not None:
        raise GradingError(f"{path}:{inside}: BEGIN SOLUTION is never closed (### END SOLUTION)")
    return "".join(out)


def _wanted(solution: Path) -> dict[str, bytes]:
    files: dict[str, bytes] = {}
    for path in sorted(solution.rglob("*")):
        rel = path.relative_to(solution)
        if any(part in SKIP for part in rel.parts) or not path.is_file() or path.suffix == ".pyc":
            continue
        data = path.read_bytes()
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError:
            files[rel.as_posix()] = data
            continue
        files[rel.as_posix()] = starter_text(text, rel.as_posix()).encode("utf-8")
    return files


def build(solutions: Path, exercises: Path, *, check: bool = False,
          only: list[str] | None = None) -> list[str]:
    """Regenerate ``exercises/<id>/`` from ``solutions/<id>/`` for every exercise (or ``only``
    those); returns the changed (or, with ``check``, out-of-date) paths relative to
    ``exercises``, extra files included."""
    if not solutions.is_dir():
        raise GradingError(f"no solutions folder at {solutions} (run from the repository root "
                           "or give --root)")
    ids = sorted(p.name for p in solutions.iterdir() if p.is_dir() and not p.name.startswith("."))
    if only:
        unknown = sorted(set(only) - set(ids))
        if unknown:
            raise GradingError(f"unknown exercise(s) {', '.join(unknown)} (solutions has: "
                               f"{', '.join(ids)})")
        ids = [i for i in ids if i in only]
    changed: list[str] = []
    for ex in ids:
        wanted = _wanted(solutions / ex)
        target = exercises / ex
        have = {p.relative_to(target).as_posix(): p for p in sorted(target.rglob("*"))
                if p.is_file() and "__pycache__" not in p.parts} if target.is_dir() else {}
        for rel, data in wanted.items():
            path = target / rel
            if rel in have and have[rel].read_bytes() == data:
                continue
            changed.append(f"{ex}/{rel}")
            if not check:
                path.parent.mkdir(parents=True, exist_ok=True)
                path.write_bytes(data)
                src_mode = (solutions / ex / rel).stat().st_mode & 0o777
                path.chmod(src_mode)
        for rel in sorted(set(have) - set(wanted)):
            changed.append(f"{ex}/{rel}")
            if not check:
                have[rel].unlink()
        if not check and target.is_dir():
            for d in sorted((p for p in target.rglob("*") if p.is_dir()), reverse=True):
                if not any(d.iterdir()):
                    shutil.rmtree(d)
    return changed
