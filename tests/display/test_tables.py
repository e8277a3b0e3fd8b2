"""ddes.display.tables: escaped HTML tables with a row limit."""

from __future__ import annotations

from ddes.display.tables import MAX_ROWS, html_table, html_text, key_value_table


def test_every_value_is_escaped() -> None:
    hostile = '<script>alert("x")</script>&'
    out = html_table(("a<b>",), [(hostile,)], caption="<i>cap</i>")
    assert "<script>" not in out and "<b>" not in out and "<i>cap" not in out
    assert "&lt;script&gt;alert(&quot;x&quot;)&lt;/script&gt;&amp;" in out
    assert "a&lt;b&gt;" in out and "&lt;i&gt;cap&lt;/i&gt;" in out
    kv = key_value_table([("<k>", "'v'")])
    assert "&lt;k&gt;" in kv and "&#x27;v&#x27;" in kv
    assert html_text(3) == "3"


def test_rows_beyond_the_limit_are_counted() -> None:
    out = html_table(("n",), ((i,) for i in range(MAX_ROWS + 7)))
    assert out.count("<tr>") == 1 + MAX_ROWS + 1  # header, rows, "more" line
    assert f"<td style=\"text-align:left;vertical-align:top\">{MAX_ROWS - 1}</td>" in out
    assert f">{MAX_ROWS}</td>" not in out
    assert "... 7 more rows" in out
    one_more = html_table(("n",), [(1,), (2,)], limit=1)
    assert "... 1 more row<" in one_more
    assert "more" not in html_table(("n",), [(1,)])
    # a prefix of the rows and the total: a long trace is not walked
    assert "... 998 more rows" in html_table(("n",), [(1,), (2,)], total=1000)


def test_monospace_columns() -> None:
    out = html_table(("name", "count"), [("/chatter", 3)], mono=(0,))
    assert "<code>/chatter</code>" in out and "<code>3</code>" not in out
