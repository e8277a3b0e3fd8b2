"""Run the Python blocks of the project's Markdown documents, as the docs tests do.

Every docs test runs its snippets through :func:`run_snippet`, so a snippet's code
has a source that ``inspect`` and tracebacks can read.  Compiled under the
Markdown file's own name, it had none: ``inspect.getsource`` of a function the
snippet defines (hypothesis calls it when it reports a failing state machine)
read the ``.md`` file from disk and tokenized Markdown as Python, which
Python 3.12's tokenizer rejects (``TokenError: unterminated string literal``).

Here each snippet is compiled under a name of its own, ``<docs/x.md, block 2>``,
whose lines :mod:`linecache` holds, so ``inspect`` and tracebacks show the
snippet's own lines.
"""

from __future__ import annotations

import linecache
import re
from pathlib import Path
from typing import Any

__all__ = ["python_blocks", "run_snippet", "snippet_filename"]

REPO = Path(__file__).resolve().parents[1]

_PYTHON_BLOCK = re.compile(r"```python\n(.*?)```", flags=re.S)


def python_blocks(text: str) -> list[str]:
    """The code of every fenced ```python block of a Markdown text, in order."""
    return _PYTHON_BLOCK.findall(text)


def snippet_filename(doc: str | Path, label: str | int | None = None) -> str:
    """The name a snippet of ``doc`` is compiled under: ``<docs/x.md, block 2>``.

    ``doc`` is the document (a path, shown relative to the checkout, or a name);
    ``label`` tells the snippet apart from the document's others (a block index
    or any short text).  The angle brackets say it is no file on disk.
    """
    path = Path(doc)
    try:
        shown = path.resolve().relative_to(REPO).as_posix() if path.is_absolute() else str(doc)
    except ValueError:
        shown = str(doc)
    if label is None:
        return f"<{shown}>"
    return f"<{shown}, block {label}>" if isinstance(label, int) else f"<{shown}, {label}>"


def run_snippet(code: str, doc: str | Path, label: str | int | None = None,
                namespace: dict[str, Any] | None = None) -> dict[str, Any]:
    """Run one snippet of ``doc`` in ``namespace`` (a fresh one by default) and return it.

    The code is compiled under :func:`snippet_filename` and its lines are put in
    :mod:`linecache`, so functions and classes the snippet defines have a source.
    """
    filename = snippet_filename(doc, label)
    lines = code.splitlines(keepends=True)
    if lines and not lines[-1].endswith("\n"):
        lines[-1] += "\n"
    # mtime None: linecache.checkcache keeps the entry (there is no file to compare it with)
    linecache.cache[filename] = (len(code), None, lines, filename)
    scope: dict[str, Any] = {} if namespace is None else namespace
    exec(compile(code, filename, "exec"), scope)  # noqa: S102 - our own documentation
    return scope
