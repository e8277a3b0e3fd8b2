"""Write the course notebooks from their Python sources, run them, record their digests.

Each notebook is written from ``src/NAME.py``, a plain Python file in the "percent" format
(reviewable as code): a line ``# %%`` starts a code cell, ``# %% [markdown]`` a markdown cell
(its lines without the leading ``# ``), and ``# %% tags=["plot"]`` a cell with tags.  The first
line ``# ddes-digest: HEX`` holds the trace digest the cell tagged ``digest`` must print; it is
stored in the notebook as ``metadata["ddes"]["digest"]``.  Notebooks are written without outputs.

    python course_notebooks/make.py                   # write every NAME.ipynb from src/NAME.py
    python course_notebooks/make.py --check           # exit 1 when an .ipynb is out of date
    python course_notebooks/make.py --run [NAME ...]  # execute, print times, check digests
    python course_notebooks/make.py --record-digests [NAME ...]
        # after a deliberate change of a trace: execute, store each printed digest in src/

tests/notebooks/test_course_notebooks.py runs every notebook with ``execute`` below.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import sys
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
SRC = HERE / "src"
DIGEST_LINE = re.compile(r"^# ddes-digest: ([0-9a-f]*)\n", re.M)
MARKER = re.compile(r"^# %%(?: \[(markdown)\])?(?: tags=(\[.*\]))?\s*$")


def sources() -> list[Path]:
    return sorted(SRC.glob("*.py"))


def build(src: Path) -> Any:
    """The notebook (an nbformat node, no outputs) of one source file."""
    import nbformat

    text = src.read_text(encoding="utf-8")
    match = DIGEST_LINE.match(text)
    if match is None:
        raise SystemExit(f"{src}: the first line must be '# ddes-digest: HEX' (may be empty)")
    cells: list[Any] = []
    kind: str | None = None
    tags: list[str] = []
    lines: list[str] = []

    def flush() -> None:
        body = "\n".join(lines).strip("\n")
        if kind == "markdown":
            body = "\n".join(line[2:] if line.startswith("# ") else line.lstrip("#")
                             for line in body.split("\n"))
            cell = nbformat.v4.new_markdown_cell(body)
        elif kind == "code":
            cell = nbformat.v4.new_code_cell(body)
        else:
            return
        if tags:
            cell.metadata["tags"] = list(tags)
        cell.pop("id", None)
        cells.append(cell)

    for line in text[match.end():].split("\n"):
        m = MARKER.match(line)
        if m:
            flush()
            kind = "markdown" if m.group(1) else "code"
            tags = json.loads(m.group(2)) if m.group(2) else []
            lines = []
        else:
            lines.append(line)
    flush()
    nb = nbformat.v4.new_notebook()
    nb.nbformat_minor = 4  # no cell ids: a stable file that diffs well
    nb.cells = cells
    nb.metadata = {
        "kernelspec": {"display_name": "Python 3", "language": "python", "name": "python3"},
        "language_info": {"name": "python"},
        "ddes": {"digest": match.group(1), "source": f"src/{src.name}"},
    }
    return nb


def dumps(nb: Any) -> str:
    import nbformat

    return nbformat.writes(nb) + "\n"


def target(src: Path) -> Path:
    return HERE / f"{src.stem}.ipynb"


def write_all() -> list[Path]:
    written = []
    for src in sources():
        text = dumps(build(src))
        path = target(src)
        if not path.exists() or path.read_text(encoding="utf-8") != text:
            path.write_text(text, encoding="utf-8")
            written.append(path)
    return written


def stale() -> list[str]:
    """Sources whose notebook is missing or differs from what ``build`` writes."""
    out = [src.name for src in sources()
           if not target(src).exists()
           or target(src).read_text(encoding="utf-8") != dumps(build(src))]
    out += [p.name for p in HERE.glob("*.ipynb") if not (SRC / f"{p.stem}.py").exists()]
    return out


def execute(path: Path | Any, timeout: int = 120, cwd: Path | None = None) -> tuple[Any, float]:
    """Run a notebook as Jupyter does (kernel python3, Agg); (nb, seconds).  ``path`` is a file
    or a notebook already read; the kernel starts in ``cwd`` (default: this folder, where
    Jupyter starts it; the notebooks find what they need from any folder)."""
    import nbformat
    from nbclient import NotebookClient

    nb = nbformat.read(path, as_version=4) if isinstance(path, (str, Path)) else path
    env = {"MPLBACKEND": "Agg",
           "PYTHONPATH": os.pathsep.join(filter(None, [str(HERE.parent),
                                                       os.environ.get("PYTHONPATH")]))}
    saved = {k: os.environ.get(k) for k in env}
    os.environ.update(env)  # the kernel inherits this process's environment
    try:
        start = time.perf_counter()
        NotebookClient(nb, timeout=timeout, kernel_name="python3",
                       resources={"metadata": {"path": str(cwd or HERE)}}).execute()
        seconds = time.perf_counter() - start
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
    return nb, seconds


def printed_digest(nb: Any) -> str:
    """The text the cell tagged ``digest`` printed, stripped."""
    cells = [c for c in nb.cells if "digest" in c.metadata.get("tags", [])]
    if len(cells) != 1:
        raise AssertionError(f"{len(cells)} cells tagged 'digest'; a notebook needs one")
    return "".join(o.get("text", "") for o in cells[0].outputs
                   if o.output_type == "stream" and o.name == "stdout").strip()


def _names(names: list[str]) -> list[Path]:
    chosen = sources()
    if names:
        chosen = [s for s in chosen if s.stem in names]
        missing = set(names) - {s.stem for s in chosen}
        if missing:
            raise SystemExit(f"no source for {sorted(missing)} in {SRC}")
    return chosen


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--check", action="store_true")
    group.add_argument("--run", action="store_true")
    group.add_argument("--record-digests", action="store_true")
    parser.add_argument("names", nargs="*")
    args = parser.parse_args(argv)
    if args.check:
        bad = stale()
        for name in bad:
            print(f"out of date: {name} (run python course_notebooks/make.py)")
        return 1 if bad else 0
    write_all()
    if not (args.run or args.record_digests):
        return 0
    status = 0
    for src in _names(args.names):
        nb, seconds = execute(target(src))
        digest = printed_digest(nb)
        if args.record_digests:
            text = src.read_text(encoding="utf-8")
            src.write_text(DIGEST_LINE.sub(f"# ddes-digest: {digest}\n", text, count=1),
                           encoding="utf-8")
            print(f"{src.stem}: {seconds:.1f} s, digest {digest} recorded")
        else:
            ok = digest == nb.metadata["ddes"]["digest"]
            status |= not ok
            print(f"{src.stem}: {seconds:.1f} s, digest {'ok' if ok else 'DIFFERS: ' + digest}")
    write_all()
    return status


if __name__ == "__main__":
    sys.exit(main())
