"""``rosunit.junitxml`` for ddes: JUnit XML results, written and read as rosunit does.

A test node run by rostest writes its results as Ant JUnit XML (``--gtest_output=xml:FILE``);
rostest reads the file back (:func:`read`) and adds up the results (:class:`Result`). The
shapes follow Noetic's rosunit 1.7: a ``<testsuite errors failures name tests time>`` holding a
``<testcase classname name time>`` per test method, with a ``<failure type>`` or ``<error
type>`` whose text is the message and the traceback, then ``<system-out>`` and
``<system-err>`` as CDATA. :func:`read` gives each test case the name
``<folder>.<file stem>/<method>`` (``rospy_tutorials.rosunit-add_two_ints/test_add_two_ints``)
and the description rostest's SUMMARY prints (``[NAME][passed]``, a ``[NAME][FAILURE]---``
block). Parsing uses :mod:`xml.etree.ElementTree` with the document's size bounded
(:data:`MAX_RESULT_BYTES`), never minidom.
"""

from __future__ import annotations

import os
import re
import traceback
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass, field
from types import TracebackType
from typing import Any

__all__ = ["MAX_RESULT_BYTES", "Result", "TestCaseResult", "TestError", "TestFailure", "cdata",
           "filter_nonprintable_text", "read", "suite_xml", "test_failure_junit_xml"]

#: The largest results file :func:`read` parses (a real one is a few KiB; a test that prints
#: without end is cut off here rather than read whole).
MAX_RESULT_BYTES = 64 << 20

_INVALID = re.compile("[^\x09\x0a\x0d\x20-\x7e\x85\xa0-\xff\u0100-\ud7ff\ue000-\ufdcf"
                      "\ufde0-\ufffd]")


def filter_nonprintable_text(text: str) -> str:
    """``text`` with characters XML cannot hold written as ``&#xNNNN;`` (rosunit's rule)."""
    return _INVALID.sub(lambda m: f"&#x{ord(m.group(0)):04X};", text)


def cdata(text: str) -> str:
    """rosunit's CDATA wrapping (kept as text: ElementTree escapes it, as rosunit's output)."""
    return f"<![CDATA[\n{text}\n]]>"


@dataclass
class TestFailure:
    """A ``<failure>``: its ``type`` attribute and its text."""

    __test__ = False  # not a pytest test class

    type: str
    text: str


@dataclass
class TestError:
    """An ``<error>``: its ``type`` attribute and its text."""

    __test__ = False  # not a pytest test class

    type: str
    text: str


@dataclass
class TestCaseResult:
    """One ``<testcase>``: ``name`` is ``<suite>/<method>`` once read."""

    __test__ = False  # not a pytest test class

    name: str
    classname: str = ""
    time: float = 0.0
    failures: list[TestFailure] = field(default_factory=list)
    errors: list[TestError] = field(default_factory=list)

    @property
    def passed(self) -> bool:
        """True without failures and errors."""
        return not self.failures and not self.errors

    @property
    def description(self) -> str:
        """What rostest's SUMMARY prints for this test case."""
        if self.passed:
            return f"[{self.name}][passed]\n"
        return _blocks(self.name, "FAILURE", self.failures) + _blocks(self.name, "ERROR",
                                                                       self.errors)


def _blocks(name: str, kind: str, items: Sequence[TestFailure | TestError]) -> str:
    if not items:
        return ""
    head = f"[{name}][{kind}]"
    head += "-" * (80 - len(head))
    return "\n".join(f"{head}\n{x.text}\n" + "-" * 80 + "\n\n" for x in items)


@dataclass
class Result:
    """The added-up results of one or more suites (rosunit's ``junitxml.Result``)."""

    name: str
    num_errors: int = 0
    num_failures: int = 0
    num_tests: int = 0
    test_case_results: list[TestCaseResult] = field(default_factory=list)
    system_out: str = ""
    system_err: str = ""
    time: float = 0.0

    def accumulate(self, other: Result) -> None:
        """Add ``other``'s counts, test cases and output to this one."""
        self.num_errors += other.num_errors
        self.num_failures += other.num_failures
        self.num_tests += other.num_tests
        self.time += other.time
        self.test_case_results.extend(other.test_case_results)
        if other.system_out:
            self.system_out += "\n" + other.system_out
        if other.system_err:
            self.system_err += "\n" + other.system_err


def _text(el: ET.Element) -> str:
    return "".join(el.itertext()).strip()


def _strip_cdata(text: str) -> str:
    """The text inside rosunit's escaped ``<![CDATA[ ... ]]>`` wrapping (it is written as
    escaped text, so it reads back with the markers)."""
    text = text.strip()
    if text.startswith("<![CDATA[") and text.endswith("]]>"):
        text = text[len("<![CDATA["):-len("]]>")].strip()
    return text


def _load_suite(suite_name: str, suite: ET.Element, result: Result) -> None:
    for node in suite:
        tag = node.tag
        if tag == "testsuite":  # flattened, as rosunit does
            _load_suite(suite_name, node, result)
        elif tag in ("system-out", "system-err"):
            text = _strip_cdata(_text(node))
            if text:
                which = "stdout" if tag == "system-out" else "stderr"
                block = f"[{suite_name}] {which}" + "-" * (71 - len(suite_name)) + "\n" + text
                if tag == "system-out":
                    result.system_out += block
                else:
                    result.system_err += block
        elif tag == "testcase":
            name = node.get("name") or "unknown"
            classname = node.get("classname") or "unknown"
            if "__main__." in classname:
                classname = classname[classname.find("__main__.") + 9:]
            if classname == "rostest.rostest.RosTest":
                classname = "rostest"
            elif not classname.startswith(result.name):
                classname = f"{result.name}.{classname}"
            try:
                seconds = float(node.get("time") or "")
            except ValueError:
                seconds = 0.0
            case = TestCaseResult(f"{suite_name}/{name}", classname, seconds)
            result.test_case_results.append(case)
            for child in node:
                text = _strip_cdata(_text(child)) or (child.get("message") or "")
                if child.tag == "failure":
                    case.failures.append(TestFailure(child.get("type") or "", text))
                elif child.tag == "error":
                    case.errors.append(TestError(child.get("type") or "", text))


def _int(value: str | None) -> int:
    try:
        return int(value or 0)
    except ValueError:
        return 0


def read(test_file: str | os.PathLike[str], test_name: str,
         warn: Any = None) -> Result:
    """Read the results file ``test_file`` of test ``test_name`` (rosunit's ``junitxml.read``).

    A missing, empty, oversized or malformed file gives an empty result and a ``WARN:`` line
    through ``warn`` (default: nothing printed), as rosunit prints one.
    """
    say = warn or (lambda _text: None)
    path = os.fspath(test_file)
    try:
        if not os.path.isfile(path):
            raise OSError("test file does not exist")
        if os.path.getsize(path) > MAX_RESULT_BYTES:
            raise OSError(f"larger than {MAX_RESULT_BYTES} bytes")
        with open(path, "rb") as f:
            data = f.read(MAX_RESULT_BYTES + 1)
        if not data.strip():
            say(f"WARN: test result file is empty [{path}]")
            return Result(test_name)
        root = ET.fromstring(data)
    except (OSError, ET.ParseError) as exc:
        say(f"WARN: cannot read test result file [{path}]: {exc}")
        return Result(test_name)
    suites = [root] if root.tag == "testsuite" else list(root.iter("testsuite"))
    if not suites:
        say(f"WARN: test result file [{path}] contains no results")
        return Result(test_name)
    if root.tag != "testsuite":  # a <testsuites> document: its top-level suites
        suites = [s for s in root if s.tag == "testsuite"]
    results = Result(test_name)
    base = os.path.basename(os.path.dirname(os.path.abspath(path)))
    fname = os.path.basename(path)
    if fname.startswith("TEST-"):
        fname = fname[5:]
    if fname.endswith(".xml"):
        fname = fname[:-4]
    suite_name = f"{base}.{fname}"
    for suite in suites:
        one = Result(test_name, _int(suite.get("errors")), _int(suite.get("failures")),
                     _int(suite.get("tests")))
        try:
            one.time = float(suite.get("time") or 0.0)
        except ValueError:
            one.time = 0.0
        _load_suite(suite_name, suite, one)
        results.accumulate(one)
    return results


ErrorInfo = tuple[type[BaseException], BaseException, TracebackType | None]


@dataclass
class CaseRecord:
    """One test method run by :func:`suite_xml`'s caller: id, simulated seconds, outcome."""

    test_id: str
    seconds: float
    failure: ErrorInfo | None = None
    error: ErrorInfo | None = None


def _problem(case: ET.Element, tag: str, err: ErrorInfo) -> None:
    el = ET.SubElement(case, tag)
    el.set("type", err[0].__name__)
    el.text = f"{err[1]}\n{''.join(traceback.format_tb(err[2]))}"


def suite_xml(name: str, cases: Sequence[CaseRecord], tests_run: int, errors: int,
              failures: int, seconds: float, out: str, err: str) -> str:
    """The XML text rosunit's ``XMLTestRunner`` writes for one run (declaration included)."""
    suite = ET.Element("testsuite")
    suite.set("errors", str(errors))
    suite.set("failures", str(failures))
    suite.set("name", name)
    suite.set("tests", str(tests_run))
    suite.set("time", f"{seconds:.3f}")
    for rec in cases:
        klass, _, method = rec.test_id.rpartition(".")
        case = ET.SubElement(suite, "testcase")
        case.set("classname", klass)
        case.set("name", method)
        case.set("time", f"{rec.seconds:.4f}")
        if rec.failure is not None:
            _problem(case, "failure", rec.failure)
        if rec.error is not None:
            _problem(case, "error", rec.error)
    ET.SubElement(suite, "system-out").text = cdata(filter_nonprintable_text(out))
    ET.SubElement(suite, "system-err").text = cdata(filter_nonprintable_text(err))
    return ('<?xml version="1.0" encoding="utf-8"?>\n'
            + ET.tostring(suite, encoding="unicode", method="xml"))


def test_failure_junit_xml(test_name: str, message: str, stdout: str | None = None,
                           class_name: str = "Results", testcase_name: str = "test_ran") -> str:
    """A one-test suite whose test failed with ``message`` (rosunit's helper of that name)."""
    suite = ET.Element("testsuite")
    for key, value in (("tests", "1"), ("failures", "1"), ("time", "1"), ("errors", "0"),
                       ("name", test_name)):
        suite.set(key, value)
    case = ET.SubElement(suite, "testcase")
    for key, value in (("name", testcase_name), ("status", "run"), ("time", "1"),
                       ("classname", class_name)):
        case.set(key, value)
    failure = ET.SubElement(case, "failure")
    failure.set("message", message)
    failure.set("type", "")
    if stdout:
        ET.SubElement(suite, "system-out").text = cdata(filter_nonprintable_text(stdout))
    return ET.tostring(suite, encoding="unicode", method="xml")


test_failure_junit_xml.__test__ = False  # type: ignore[attr-defined]  # not a pytest test
