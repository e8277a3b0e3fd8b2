"""A minimal XML element tree that remembers the line of every element.

roslaunch parses with ``xml.dom.minidom``, which forgets line numbers.
ddes wants every error to name the file and the line, so launch files are
parsed with expat directly into :class:`Element` objects: the tag, the
attributes in document order, the line of the start tag, the child
elements and the element's own text (text and CDATA directly inside it,
as roslaunch's ``_get_text`` collects for ``<rosparam>``).  Comments and
processing instructions are dropped.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from xml.parsers import expat

from ddes.errors import ROSLaunchException

__all__ = ["Element", "parse_xml"]


@dataclass
class Element:
    """One XML element: tag, attributes (document order), line, children and text."""

    tag: str
    attrs: dict[str, str]
    line: int
    children: list[Element] = field(default_factory=list)
    text: str = ""

    def start_tag(self) -> str:
        """The start tag as written (attributes unresolved), for error messages."""
        parts = [self.tag] + [f'{k}="{_quote(v)}"' for k, v in self.attrs.items()]
        return "<" + " ".join(parts) + ">"


def _quote(value: str) -> str:
    return value.replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;")


def parse_xml(data: bytes, filename: str) -> Element:
    """Parse ``data`` into its root :class:`Element`.

    Malformed XML raises :class:`~ddes.errors.ROSLaunchException` naming
    ``filename``, the line and column, with expat's description (the same
    text roslaunch prints after "Invalid roslaunch XML syntax").
    """
    parser = expat.ParserCreate()
    parser.ordered_attributes = True
    stack: list[Element] = []
    roots: list[Element] = []

    def start(tag: str, attrs: list[str]) -> None:
        el = Element(tag, dict(zip(attrs[::2], attrs[1::2])), parser.CurrentLineNumber)
        if stack:
            stack[-1].children.append(el)
        else:
            roots.append(el)
        stack.append(el)

    def end(tag: str) -> None:
        stack.pop()

    def chars(text: str) -> None:
        if stack:
            stack[-1].text += text

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.CharacterDataHandler = chars
    try:
        parser.Parse(data, True)
    except expat.ExpatError as exc:
        raise ROSLaunchException(
            f"{filename}:{exc.lineno}: Invalid roslaunch XML syntax: "
            f"{expat.ErrorString(exc.code)} (line {exc.lineno}, column {exc.offset}). "
            "Fix the XML: close every tag, quote every attribute value and write & as &amp;"
        ) from None
    return roots[0]
