"""tests/docsnippets.py: a snippet run by the docs tests has a source of its own."""

from __future__ import annotations

import inspect
import linecache
import traceback
from pathlib import Path

import pytest

from .docsnippets import REPO, python_blocks, run_snippet, snippet_filename

# Markdown around the code: Python 3.12's tokenizer raises on its backticks and apostrophes
# when inspect reads a .md file as the source of a snippet's function
DOC_TEXT = """# A page

Some `code` isn't Python.

```python
def double(x):
    return 2 * x

def fail():
    raise ValueError("from the snippet")
```

More text's here.
"""


def test_python_blocks() -> None:
    assert python_blocks(DOC_TEXT) == [
        'def double(x):\n    return 2 * x\n\ndef fail():\n    raise ValueError("from the snippet")\n']


def test_names() -> None:
    assert snippet_filename(REPO / "docs" / "testing.md", 2) == "<docs/testing.md, block 2>"
    assert snippet_filename("docs/trace.md", "'Logging' block 0") == "<docs/trace.md, 'Logging' block 0>"
    assert snippet_filename(Path("/elsewhere/x.md")) == "</elsewhere/x.md>"


def test_a_snippets_function_has_its_source(tmp_path: Path) -> None:
    doc = tmp_path / "page.md"
    doc.write_text(DOC_TEXT)  # a real file of that name: inspect must not read it
    scope = run_snippet(python_blocks(DOC_TEXT)[0], doc, 0)
    linecache.checkcache()  # as pytest and traceback do: the entry stays
    assert inspect.getsource(scope["double"]) == "def double(x):\n    return 2 * x\n"
    assert scope["double"](2) == 4


def test_a_traceback_shows_the_snippets_line() -> None:
    scope = run_snippet(python_blocks(DOC_TEXT)[0], "docs/page.md", 7)
    with pytest.raises(ValueError) as info:
        scope["fail"]()
    text = "".join(traceback.format_exception(info.value))
    assert 'File "<docs/page.md, block 7>", line 5, in fail' in text
    assert 'raise ValueError("from the snippet")' in text


def test_blocks_in_one_namespace_keep_their_own_sources() -> None:
    scope = run_snippet("def one():\n    return 1\n", "docs/page.md", 0)
    run_snippet("def two():\n    return one() + 1\n", "docs/page.md", 1, scope)
    assert scope["two"]() == 2
    assert inspect.getsource(scope["one"]) == "def one():\n    return 1\n"
    assert inspect.getsource(scope["two"]) == "def two():\n    return one() + 1\n"
