"""``rosunit`` of ROS Noetic for a test node run by ddes: ``rosunit.unitrun(PKG, NAME, Case)``.

A test script's ``import rosunit`` is this module (``ddes.compat.scripts``). It runs the
script's ``unittest`` cases inside the node, on the world's clock: a test that calls
``rospy.sleep`` or ``rospy.wait_for_message`` blocks on simulated time, and the times in the
report are simulated seconds. What it prints goes where the node's output goes, in order with
what the tests print.

* :func:`unitrun` (and :func:`run_node_tests`, shared with ``rostest.rosrun``) read
  ``--gtest_output=xml:FILE`` and ``--text`` from the script's arguments, as rosunit does. With
  ``--text``: unittest's verbose text report and rosunit's ``SUMMARY:`` block. Without: the
  tests' printed lines are captured into the JUnit XML file (``rosunit.junitxml``), then the
  ``[Testcase: x] ... ok`` lines and the ``SUMMARY:`` block. A failing run ends the script with
  ``sys.exit(1)``.
* Deviation: with both flags, the XML file is written too (rosunit writes none with
  ``--text``), so ``ddes rostest --text`` can still print its SUMMARY of every test.
* :func:`xml_results_file`, :func:`rostest_name_from_path`, :func:`print_unittest_summary`,
  :func:`print_runner_summary`, :data:`XML_OUTPUT_FLAG`, :mod:`~ddes.compat.rosunit.junitxml`.

Coverage (``--cov``) is not provided: the flag is accepted and ignored.
"""

from __future__ import annotations

import os
import unittest
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from ddes.compat.rosunit import junitxml
from ddes.compat.rosunit.runner import (
    LineStream,
    runner_summary,
    suite_class_name,
    text_run,
    unittest_summary,
    xml_run,
)

__all__ = ["XML_OUTPUT_FLAG", "junitxml", "print_runner_summary", "print_unittest_summary",
           "rostest_name_from_path", "run_node_tests", "test_results_dir", "unitrun",
           "xml_results_file"]

__version__ = "1.7.0"

#: The flag rostest passes a test node to name its results file (gtest's).
XML_OUTPUT_FLAG = "--gtest_output=xml:"

Printer = Callable[[str, bool], None]


def test_results_dir(environ: Mapping[str, str] | None = None) -> Path:
    """rospkg's ``get_test_results_dir``: ``ROS_TEST_RESULTS_DIR``, else ``ROS_HOME/test_results``,
    else ``~/.ros/test_results``."""
    env = os.environ if environ is None else environ
    if env.get("ROS_TEST_RESULTS_DIR"):
        return Path(env["ROS_TEST_RESULTS_DIR"])
    home = env.get("ROS_HOME") or os.path.join(os.path.expanduser("~"), ".ros")
    return Path(home) / "test_results"


test_results_dir.__test__ = False  # type: ignore[attr-defined]  # not a pytest test


def xml_results_file(test_pkg: str, test_name: str, is_rostest: bool = False,
                     env: Mapping[str, str] | None = None, *, base: Path | None = None) -> str:
    """The results file of a test (rosunit's rule): ``DIR/PKG/rostest-NAME.xml`` for rostest's
    own file, ``DIR/PKG/rosunit-NAME.xml`` for a test node's; the folder is made. ``base``
    replaces the results folder (ddes's ``--results-dir``)."""
    folder = (base if base is not None else test_results_dir(env)) / test_pkg
    folder.mkdir(parents=True, exist_ok=True)
    for c in " \"'&$!`/\\":
        test_name = test_name.replace(c, "_")
    prefix = "rostest" if is_rostest else "rosunit"
    return str(folder / f"{prefix}-{test_name}.xml")


def rostest_name_from_path(pkg_dir: str, test_file: str) -> str:
    """rostest's name of a test file: its path in the package, ``/`` as ``_``, no extension
    (``test/test-add-two-ints.launch`` -> ``test_test-add-two-ints``)."""
    path = os.path.abspath(test_file)
    if path.startswith(pkg_dir):
        path = path[len(pkg_dir):]
        if path[:1] == os.sep:
            path = path[1:]
    name = path.replace(os.sep, "_")
    return name[:name.rfind(".")] if "." in name else name


# -- the node's output ----------------------------------------------------------------------

def _context() -> tuple[Any, Any]:
    """The running task and its script context (None, None outside a ddes script)."""
    from ddes.compat.scripts import ScriptContext
    from ddes.graph.blocking import current_task

    task = current_task()
    ctx = task.context if task is not None else None
    return task, ctx if isinstance(ctx, ScriptContext) else None


def _real_printer(text: str, stderr: bool) -> None:
    import sys

    (sys.stderr if stderr else sys.stdout).write(text + "\n")


def _printer() -> Printer:
    _task, ctx = _context()
    if ctx is not None and ctx.print_line is not None:
        return ctx.print_line  # type: ignore[no-any-return]
    return _real_printer


def _clock() -> Callable[[], float]:
    task, _ctx = _context()
    if task is None:
        import time

        return time.perf_counter
    env = task.world.env
    return lambda: int(env.now) / 1e9


def print_unittest_summary(result: unittest.TestResult) -> None:
    """rosunit's ``SUMMARY:`` block of a unittest result, on the node's standard output."""
    out = _printer()
    for line in unittest_summary(result):
        out(line, False)


def print_runner_summary(runner_results: unittest.TestResult, junit_results: junitxml.Result,
                         runner_name: str = "ROSUNIT") -> None:
    """rosunit's summary of a runner and the results of the tests it ran."""
    out = _printer()
    for line in runner_summary(runner_results, junit_results, runner_name):
        out(line, False)


# -- running a node's tests -----------------------------------------------------------------

def _suite(test: Any) -> unittest.TestSuite:
    loader = unittest.TestLoader()
    if isinstance(test, str):
        return loader.loadTestsFromName(test)
    if isinstance(test, unittest.TestSuite):
        return test
    if isinstance(test, unittest.TestCase):
        return unittest.TestSuite([test])
    return loader.loadTestsFromTestCase(test)


@contextmanager
def _captured(ctx: Any) -> Iterator[tuple[list[str], list[str]]]:
    """The script's printed lines collected, not shown, while the tests run (rosunit's
    XMLTestRunner swaps ``sys.stdout``/``sys.stderr`` for buffers)."""
    out: list[str] = []
    err: list[str] = []
    if ctx is None:
        yield out, err
        return
    saved = ctx.print_line
    ctx.print_line = lambda text, stderr: (err if stderr else out).append(text)
    try:
        yield out, err
    finally:
        ctx.print_line = saved


def run_node_tests(package: str, test_name: str, test: Any,
                   sysargs: Sequence[str] | None = None) -> unittest.TestResult:
    """Run ``test`` (a TestCase class or instance, a suite, or a name) as rosunit runs a test
    node's tests; returns the unittest result (see the module docstring)."""
    task, ctx = _context()
    if sysargs is None:
        import sys

        sysargs = list(ctx.argv) if ctx is not None else list(sys.argv)
    result_file = None
    for arg in sysargs:
        if arg.startswith(XML_OUTPUT_FLAG):
            result_file = arg[len(XML_OUTPUT_FLAG):]
    text_mode = "--text" in sysargs
    suite = _suite(test)
    clock = _clock()
    out = _printer()
    if text_mode:
        stream = LineStream(lambda line: out(line, True))
        if ctx is not None:
            saved = ctx.print_line
            ctx.print_line = stream.joined(saved)
        try:
            result = text_run(suite, stream, clock)
            if result_file is not None:  # ddes: the XML too, for rostest's SUMMARY
                _write(result_file, junitxml.suite_xml(
                    suite_class_name(suite), result.records, result.testsRun,
                    len(result.errors), len(result.failures), result.seconds, "", ""))
        finally:
            stream.close()
            if ctx is not None:
                ctx.print_line = saved
        return result
    if result_file is None:
        result_file = xml_results_file(package, os.path.basename(test_name), False)
    out(f"[ROSUNIT] Outputting test results to {result_file}", False)
    xml_result, xml = xml_run(suite, suite_class_name(suite), clock, lambda: _captured(ctx))
    _write(result_file, xml)
    for line in xml_result.report_lines():
        out(line, False)
    return xml_result


def _write(path: str, text: str) -> None:
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)


def unitrun(package: str, test_name: str, test: Any, sysargs: Sequence[str] | None = None,
            coverage_packages: Sequence[str] | None = None) -> None:
    """rosunit's ``unitrun``: run the tests, print the summary, ``sys.exit(1)`` on failure."""
    result = run_node_tests(package, test_name, test, sysargs)
    print_unittest_summary(result)
    if not result.wasSuccessful():
        raise SystemExit(1)
