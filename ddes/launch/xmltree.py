"""A minimal XML element tree that remembers the line of every element.

roslaunch parses with ``xml.dom.minidom``, which forgets line numbers.
ddes wants every error to name the file and the line, so launch files are
parsed with expat directly into :class:`Element` objects: the tag, the
attributes in document order, the line of the start tag, the child
elements and the element's own text (text and CDATA directly inside it,
as roslaunch's ``_get_text`` collects for ``<rosparam>``).  Comments and
processing instructions are dropped.

Hostile input: a ``<!DOCTYPE>`` (and with it every ``<!ENTITY>``, so no
entity bomb and no external entity) is refused, as are elements nested
more than :data:`MAX_XML_DEPTH` deep and data larger than
:data:`MAX_XML_BYTES`, each with :class:`~ddes.errors.ResourceLimitError`.
roslaunch's minidom expands internal entities (expat >= 2.4 stops only
amplification past 100x after 8 MiB).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from xml.parsers import expat

from ddes.errors import ResourceLimitError, ROSLaunchException
from ddes.graph.yamlsafe import MAX_FILE_BYTES

__all__ = ["MAX_XML_BYTES", "MAX_XML_DEPTH", "Element", "parse_xml"]

#: The largest launch file ddes parses (the same 16 MiB as every file a loader reads).
MAX_XML_BYTES = MAX_FILE_BYTES
#: How deep elements may nest in one launch file.
MAX_XML_DEPTH = 128


class _Refused(Exception):
    """Raised inside an expat handler to stop the parse; becomes ResourceLimitError."""


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
    if len(data) > MAX_XML_BYTES:
        raise ResourceLimitError(
            f"{filename}: launch XML of {len(data)} bytes is larger than {MAX_XML_BYTES}, the "
            "most ddes reads; split it into included files")
    parser = expat.ParserCreate()
    parser.ordered_attributes = True
    stack: list[Element] = []
    roots: list[Element] = []

    def doctype(name: str, *_: object) -> None:
        raise _Refused(
            f"{filename}:{parser.CurrentLineNumber}: <!DOCTYPE {name}> is not allowed in a "
            "launch file: ddes refuses DTDs and <!ENTITY> declarations (an entity bomb expands "
            "a few hundred bytes into gigabytes); remove the DOCTYPE and write the text out, "
            "or use <arg> and $(arg name)")

    def start(tag: str, attrs: list[str]) -> None:
        if len(stack) >= MAX_XML_DEPTH:
            raise _Refused(
                f"{filename}:{parser.CurrentLineNumber}: <{tag}> is nested more than "
                f"{MAX_XML_DEPTH} elements deep; flatten the <group>s or move part of the file "
                "into an <include>")
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
    parser.StartDoctypeDeclHandler = doctype
    try:
        parser.Parse(data, True)
    except _Refused as exc:
        raise ResourceLimitError(str(exc)) from None
    except expat.ExpatError as exc:
        raise ROSLaunchException(
            f"{filename}:{exc.lineno}: Invalid roslaunch XML syntax: "
            f"{expat.ErrorString(exc.code)} (line {exc.lineno}, column {exc.offset}). "
            "Fix the XML: close every tag, quote every attribute value and write & as &amp;"
        ) from None
    return roots[0]
