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
more than :data:`MAX_XML_DEPTH` deep, data larger than :data:`MAX_XML_BYTES`
and more elements than an :class:`ElementBudget` allows (one budget is shared
by a launch file and everything it includes), each with
:class:`~ddes.errors.ResourceLimitError`.  roslaunch's minidom expands
internal entities (expat >= 2.4 stops only amplification past 100x after 8 MiB).

Nothing here recurses: expat keeps its own stack and the tree is built with
a list, so a deep file costs memory in proportion to its size, never Python
stack.
"""

from __future__ import annotations

import io
from dataclasses import dataclass, field
from xml.parsers import expat

from ddes.errors import ResourceLimitError, ROSLaunchException
from ddes.graph.yamlsafe import MAX_FILE_BYTES

__all__ = ["MAX_XML_BYTES", "MAX_XML_DEPTH", "MAX_XML_ELEMENTS", "Element", "ElementBudget",
           "parse_xml"]

#: The largest launch file ddes parses (the same 16 MiB as every file a loader reads).
MAX_XML_BYTES = MAX_FILE_BYTES
#: How deep elements may nest in one launch file: five times what roslaunch itself reads
#: (Noetic's recursive loader dies with RecursionError near 990 empty ``<group>``s, near 490
#: with a ``<node>`` inside, on Python's default limit of 1000 frames).
MAX_XML_DEPTH = 5000
#: How many elements one load may parse, the launch file and every include counted each time
#: it is read (a file that includes another one 100 times, which includes another 100 times
#: ..., multiplies the work; real launch files hold a few thousand).
MAX_XML_ELEMENTS = 200_000


class _Refused(Exception):
    """Raised inside an expat handler to stop the parse; becomes ResourceLimitError."""


@dataclass
class ElementBudget:
    """How many more elements a load may parse (shared by the files of one load)."""

    left: int = MAX_XML_ELEMENTS
    limit: int = MAX_XML_ELEMENTS


@dataclass(slots=True)
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


def parse_xml(data: bytes, filename: str, budget: ElementBudget | None = None) -> Element:
    """Parse ``data`` into its root :class:`Element`.

    Malformed XML raises :class:`~ddes.errors.ROSLaunchException` naming
    ``filename``, the line and column, with expat's description (the same
    text roslaunch prints after "Invalid roslaunch XML syntax").  ``budget``
    (default: a fresh one) counts the elements made.
    """
    budget = budget if budget is not None else ElementBudget()
    if len(data) > MAX_XML_BYTES:
        raise ResourceLimitError(
            f"{filename}: launch XML of {len(data)} bytes is larger than {MAX_XML_BYTES}, the "
            "most ddes reads; split it into included files")
    parser = expat.ParserCreate()
    parser.ordered_attributes = True
    parser.buffer_text = True  # one call per run of text, not one per entity
    parser.buffer_size = 1 << 16
    stack: list[Element] = []
    #: the text of each open element, collected in a buffer (``+=`` on the element's text
    #: copied it for every piece expat delivers: quadratic, ``a&amp;`` * 10**6 took minutes)
    texts: list[io.StringIO] = []
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
                f"{MAX_XML_DEPTH} elements deep (ddes.launch.xmltree.MAX_XML_DEPTH); flatten "
                "the <group>s")
        if budget.left <= 0:
            raise _Refused(
                f"{filename}:{parser.CurrentLineNumber}: more than {budget.limit} elements in "
                "one load (this file and the files it includes, counted each time one is "
                "read); split the launch, or include a file fewer times")
        budget.left -= 1
        el = Element(tag, dict(zip(attrs[::2], attrs[1::2])), parser.CurrentLineNumber)
        if stack:
            stack[-1].children.append(el)
        else:
            roots.append(el)
        stack.append(el)
        texts.append(io.StringIO())

    def end(tag: str) -> None:
        stack.pop().text = texts.pop().getvalue()

    def chars(text: str) -> None:
        if texts:
            texts[-1].write(text)

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
