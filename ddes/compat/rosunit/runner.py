"""unittest runners on a clock of ddes's: rostest's and rosunit's texts with simulated times.

Python's ``unittest.TextTestRunner`` and rosunit's ``XMLTestRunner`` time a run with the wall
clock (``Ran 3 tests in 0.348s``) and write to the process's streams. These do the same on a
clock given to them (a world's kernel clock, in seconds) and write through a
:class:`LineStream`, so a test node's report is the same run after run and lands in the node's
output, in order with what the test prints. The texts are unittest's and rosunit's:
``test_x (__main__.T.test_x) ... ok``, the ``====`` blocks of failures and errors, ``Ran N
tests in T.TTTs``, ``OK`` / ``FAILED (failures=1, errors=2)``; rosunit's ``[Testcase: x] ...
ok`` lines and its two summaries (:func:`unittest_summary`, :func:`runner_summary`), without
their colour escapes (ddes prints roslaunch's lines without them too).
"""

from __future__ import annotations

import traceback
import unittest
from collections.abc import Callable
from typing import Any, TextIO, cast

from ddes.compat.rosunit.junitxml import CaseRecord, ErrorInfo, Result, suite_xml

__all__ = ["Clock", "LineStream", "TextResult", "XMLResult", "runner_summary", "text_run", "unittest_summary",
           "xml_run"]

Clock = Callable[[], float]


class LineStream:
    """A text stream that hands each complete line to ``sink`` (without its newline).

    A line still open (``test_x (...) ... `` before the test prints) waits in
    :attr:`pending`; :meth:`joined` wraps a line printer so a printed line starts with it, as
    both land on one terminal line.
    """

    def __init__(self, sink: Callable[[str], None]) -> None:
        self.sink = sink
        self.pending = ""

    def write(self, text: str) -> int:
        """Write ``text``; every complete line goes to the sink."""
        data = self.pending + text
        *lines, self.pending = data.split("\n")
        for line in lines:
            self.sink(line)
        return len(text)

    def writeln(self, text: str = "") -> None:
        """Write ``text`` and a newline."""
        self.write(text + "\n")

    def flush(self) -> None:
        """Nothing to do: lines leave as they complete (the open one stays open)."""

    def close(self) -> None:
        """Hand an open line to the sink."""
        if self.pending:
            line, self.pending = self.pending, ""
            self.sink(line)

    def take(self) -> str:
        """The open line, taken away."""
        text, self.pending = self.pending, ""
        return text

    def joined(self, printer: Callable[[str, bool], None]) -> Callable[[str, bool], None]:
        """``printer`` whose next line starts with the open line of this stream."""

        def out(text: str, stderr: bool) -> None:
            printer(self.take() + text, stderr)

        return out


def _problems(result: unittest.TestResult) -> tuple[int, int, int, int]:
    return (len(result.failures), len(result.errors), len(result.expectedFailures),
            len(result.unexpectedSuccesses))


def text_run(suite: unittest.TestSuite | unittest.TestCase, stream: LineStream, clock: Clock,
             verbosity: int = 2) -> TextResult:
    """``unittest.TextTestRunner(verbosity=2).run(suite)`` on ``clock``, writing to ``stream``.

    The result also holds a :class:`CaseRecord` per test method (``result.records``) and the
    run's simulated seconds (``result.seconds``), for a JUnit XML file of the same run."""
    result = TextResult(cast(TextIO, _Writeln(stream)), True, verbosity, clock)
    start = clock()
    result.startTestRun()
    try:
        suite(result)
    finally:
        result.stopTestRun()
    taken = clock() - start
    result.seconds = taken
    result.printErrors()
    stream.writeln(result.separator2)
    run = result.testsRun
    stream.writeln(f"Ran {run} test{'s' if run != 1 else ''} in {taken:.3f}s")
    stream.writeln()
    failed, errored, expected, unexpected = _problems(result)
    infos = []
    if not result.wasSuccessful():
        stream.write("FAILED")
        if failed:
            infos.append(f"failures={failed}")
        if errored:
            infos.append(f"errors={errored}")
    else:
        stream.write("OK")
    if result.skipped:
        infos.append(f"skipped={len(result.skipped)}")
    if expected:
        infos.append(f"expected failures={expected}")
    if unexpected:
        infos.append(f"unexpected successes={unexpected}")
    stream.writeln(f" ({', '.join(infos)})" if infos else "")
    return result


class _Writeln:
    """unittest's ``_WritelnDecorator`` over a :class:`LineStream`."""

    def __init__(self, stream: LineStream) -> None:
        self._stream = stream

    def write(self, text: str) -> int:
        return self._stream.write(text)

    def writeln(self, text: str | None = None) -> None:
        self._stream.writeln(text or "")

    def flush(self) -> None:
        self._stream.flush()

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


class _Recording(unittest.TestResult):
    """A result that keeps one :class:`CaseRecord` per test method, timed on ``clock``."""

    clock: Clock
    records: list[CaseRecord]
    seconds: float
    _start: float
    _failure: ErrorInfo | None
    _error: ErrorInfo | None

    def _init_records(self, clock: Clock) -> None:
        self.clock = clock
        self.records = []
        self.seconds = 0.0
        self._start = 0.0
        self._failure = self._error = None

    def startTest(self, test: unittest.TestCase) -> None:  # noqa: N802 - unittest's name
        super().startTest(test)
        self._failure = self._error = None
        self._start = self.clock()

    def stopTest(self, test: unittest.TestCase) -> None:  # noqa: N802 - unittest's name
        taken = self.clock() - self._start
        super().stopTest(test)
        self.records.append(CaseRecord(test.id(), taken, self._failure, self._error))

    def addError(self, test: unittest.TestCase, err: Any) -> None:  # noqa: N802
        super().addError(test, err)
        self._error = err

    def addFailure(self, test: unittest.TestCase, err: Any) -> None:  # noqa: N802
        super().addFailure(test, err)
        self._failure = err


class TextResult(_Recording, unittest.TextTestResult):
    """unittest's TextTestResult that also records each test method."""

    def __init__(self, stream: TextIO, descriptions: bool, verbosity: int,
                 clock: Clock) -> None:
        unittest.TextTestResult.__init__(self, stream, descriptions, verbosity)  # type: ignore[misc]
        self._init_records(clock)


class XMLResult(_Recording):
    """rosunit's ``_XMLTestResult`` on ``clock``: one :class:`CaseRecord` per test method."""

    def __init__(self, clock: Clock) -> None:
        super().__init__()
        self._init_records(clock)

    def report_lines(self) -> list[str]:
        """rosunit's ``print_report_text``: ``[Testcase: name] ... ok`` (or the problem)."""
        lines: list[str] = []
        for rec in self.records:
            method = rec.test_id.rpartition(".")[2]
            head = f"[Testcase: {method}]"
            if rec.failure is None and rec.error is None:
                lines.append(head + " ... ok")
            for tag, err in (("failure", rec.failure), ("error", rec.error)):
                if err is None:
                    continue
                lines.append(head + (" ... FAILURE!" if tag == "failure" else " ... ERROR!"))
                lines.append(f"{tag.upper()}: {_escape(str(err[1]))}")
                lines += _escape("".join(traceback.format_tb(err[2]))).rstrip("\n").split("\n")
                lines.append("-" * 80)
        return lines


def _escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def xml_run(suite: unittest.TestSuite | unittest.TestCase, name: str, clock: Clock,
            capture: Callable[[], Any]) -> tuple[XMLResult, str]:
    """rosunit's ``XMLTestRunner.run``: run ``suite`` with its output captured, return the
    result and the XML text. ``capture`` is a context manager factory yielding a pair of
    lists that receive the lines the tests print on standard output and error."""
    result = XMLResult(clock)
    start = clock()
    with capture() as (out, err):
        suite(result)
    taken = clock() - start
    text = suite_xml(name, result.records, result.testsRun, len(result.errors),
                     len(result.failures), taken, _lines(out), _lines(err))
    return result, text


def _lines(lines: list[str]) -> str:
    return "".join(line + "\n" for line in lines)


def suite_class_name(suite: object) -> str:
    """The ``name`` rosunit gives a run: the suite's class, ``unittest.suite.TestSuite``."""
    klass = type(suite)
    return f"{klass.__module__}.{klass.__name__}"


def unittest_summary(result: unittest.TestResult) -> list[str]:
    """rosunit's ``print_unittest_summary``: the test node's own SUMMARY block."""

    def names(items: list[tuple[unittest.TestCase, str]]) -> str:
        return ", ".join(t.id() for t, _ in items)

    lines = ["-" * 61, "SUMMARY:",
             " * RESULT: SUCCESS" if result.wasSuccessful() else " * RESULT: FAIL",
             f" * TESTS: {result.testsRun}",
             f" * ERRORS: {len(result.errors)} [{names(result.errors)}]",
             f" * FAILURES: {len(result.failures)} [{names(result.failures)}]", ""]
    return lines


def runner_summary(runner: unittest.TestResult, results: Result,
                   runner_name: str = "ROSTEST") -> list[str]:
    """rosunit's ``print_runner_summary``: rostest's SUMMARY of the runner's and the tests'
    results (``runner`` counts the test files run; ``results`` the tests inside them)."""
    text = f"[{runner_name}]" + "-" * 71 + "\n\n"
    for case in results.test_case_results:
        text += case.description
    for test, _ in runner.failures:
        text += f"[{cast(unittest.TestCase, test)._testMethodName}][failed]\n"
    text += "\nSUMMARY\n"
    ok = runner.wasSuccessful() and results.num_errors + results.num_failures == 0
    text += " * RESULT: SUCCESS\n" if ok else " * RESULT: FAIL\n"
    text += f" * TESTS: {results.num_tests}\n"
    text += f" * ERRORS: {results.num_errors + len(runner.errors)}\n"
    text += f" * FAILURES: {results.num_failures + len(runner.failures)}\n"
    if runner.failures:
        text += "\nERROR: The following tests failed to run:\n"
        for test, _ in runner.failures:
            text += f" * {cast(unittest.TestCase, test)._testMethodName}\n"
    return text.split("\n")
