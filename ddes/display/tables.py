"""Escaped HTML tables for notebooks (``_repr_html_``).

Every value goes through :func:`html.escape`, so a parameter value, a log
line or a topic read from a hostile bag cannot inject markup or script into
a notebook.  The tables are plain ``<table>`` elements with a few inline
styles (left-aligned, monospace names) that read well in JupyterLab,
classic Notebook and VS Code alike.
"""

from __future__ import annotations

import html
from collections.abc import Iterable, Sequence

__all__ = ["MAX_ROWS", "html_table", "html_text", "key_value_table"]

#: Rows a table shows before it says how many more there are.
MAX_ROWS = 50

_TABLE = '<table class="ddes" style="border-collapse:collapse;text-align:left">'
_CELL = 'style="text-align:left;vertical-align:top"'


def html_text(value: object) -> str:
    """``str(value)`` escaped for HTML (quotes too)."""
    return html.escape(str(value), quote=True)


def _caption(caption: str | None) -> str:
    return "" if caption is None else (
        f'<caption style="text-align:left;font-weight:bold">{html_text(caption)}</caption>')


def html_table(header: Sequence[object], rows: Iterable[Sequence[object]], *,
               caption: str | None = None, total: int | None = None,
               limit: int = MAX_ROWS, mono: Sequence[int] = ()) -> str:
    """A table with a header row; at most ``limit`` rows, then "... N more".

    ``total`` is the number of rows there are (when ``rows`` is a prefix of
    them, so a long trace is not walked); by default the rows counted.
    ``mono`` lists the columns shown in a monospace font (names, values).
    """
    out = [_TABLE, _caption(caption), "<thead><tr>"]
    out += [f"<th {_CELL}>{html_text(h)}</th>" for h in header]
    out.append("</tr></thead><tbody>")
    shown = 0
    counted = 0
    for row in rows:
        counted += 1
        if shown >= limit:
            continue
        shown += 1
        cells = []
        for i, value in enumerate(row):
            text = html_text(value)
            cells.append(f"<td {_CELL}><code>{text}</code></td>" if i in mono
                         else f"<td {_CELL}>{text}</td>")
        out.append("<tr>" + "".join(cells) + "</tr>")
    more = (counted if total is None else total) - shown
    if more > 0:
        out.append(f'<tr><td {_CELL} colspan="{max(len(header), 1)}"><i>... {more} more '
                   f'row{"s" if more != 1 else ""}</i></td></tr>')
    out.append("</tbody></table>")
    return "".join(out)


def key_value_table(pairs: Iterable[tuple[str, object]], *, caption: str | None = None) -> str:
    """A two-column table of ``name: value`` lines (names in bold)."""
    out = [_TABLE, _caption(caption), "<tbody>"]
    for key, value in pairs:
        out.append(f"<tr><th {_CELL}>{html_text(key)}</th><td {_CELL}>{html_text(value)}</td></tr>")
    out.append("</tbody></table>")
    return "".join(out)
