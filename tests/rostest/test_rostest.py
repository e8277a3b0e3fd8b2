"""``ddes rostest``: rostest files run on simulated time, a fresh world per <test> (docs/rostest.md).

The files are those of the small package ``ddes_rostest_demo`` beside this file: a talker and
tests that pass, fail, time out, retry and lose a required node. Each run is compared with what
rostest prints and writes (the SUMMARY block, the JUnit XML files, the exit codes), and two runs
of one file give one trace digest.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from ddes.cli.main import main
from ddes.compat.rosunit import junitxml
from ddes.console.rostest import RostestReport, run_rostest
from ddes.console.shell import Console
from ddes.launch import load_launch
from ddes.rospack import RosPack
from ddes.world import World

DEMO = Path(__file__).resolve().parent / "ddes_rostest_demo"
TESTS = DEMO / "test"


def rostest(tmp_path: Path, *words: str) -> tuple[RostestReport, list[str], list[str]]:
    out: list[str] = []
    err: list[str] = []
    report = run_rostest(["--results-dir", str(tmp_path / "results"), *words],
                         rospack=RosPack(), world_class=World, out=out.append, err=err.append)
    return report, out, err


def summary_block(out: list[str]) -> list[str]:
    """rostest's SUMMARY: from the [ROSTEST]--- line to the empty line after the counts."""
    start = out.index("[ROSTEST]" + "-" * 71)
    end = next(i for i in range(start, len(out)) if out[i].startswith(" * FAILURES:"))
    return out[start:end + 1]


def test_a_passing_file_passes_with_rostests_summary(tmp_path: Path) -> None:
    report, out, err = rostest(tmp_path, str(TESTS / "pass.test"))
    assert report.code == 0 and err == []
    assert (report.tests, report.errors, report.failures) == (4, 0, 0)
    assert summary_block(out) == [
        "[ROSTEST]" + "-" * 71, "",
        "[ddes_rostest_demo.rosunit-hears_talker/test_hears_hello][passed]",
        "[ddes_rostest_demo.rosunit-hears_talker/test_master_knows_the_talker][passed]",
        "[ddes_rostest_demo.rosunit-hears_talker/test_rate_on_simulated_time][passed]",
        "[ddes_rostest_demo.rosunit-unit/test_sum][passed]", "",
        "SUMMARY", " * RESULT: SUCCESS", " * TESTS: 4", " * ERRORS: 0", " * FAILURES: 0"]
    results = tmp_path / "results" / "ddes_rostest_demo"
    assert out[0] == f"[ROSUNIT] Outputting test results to {results}/rostest-test_pass.xml"
    assert "[Testcase: testhears_talker] ... ok" in out and "[Testcase: testunit] ... ok" in out
    assert out[-1].startswith("trace digest: ") and "failed on seed" not in "\n".join(out)
    # one world per <test>: the talker's 0.65 s in the first, the unit test's instant in the other
    assert [(r.test_name, r.attempt, r.seed) for r in report.runs] == [
        ("hears_talker", 0, 0), ("unit", 0, 0)]
    assert out[-2] == f"simulated 0.650 s in 2 worlds; {report.events} trace events"


def test_a_failing_file_names_its_failures_and_the_seed_to_replay(tmp_path: Path) -> None:
    report, out, _err = rostest(tmp_path, "--seed", "4", str(TESTS / "fail.test"))
    assert report.code == 2
    block = summary_block(out)
    assert block[2] == "[ddes_rostest_demo.rosunit-fails/test_a_passes][passed]"
    assert block[3] == "[ddes_rostest_demo.rosunit-fails/test_b_fails][FAILURE]" + "-" * 25
    assert block[4] == "2 != 3 : arithmetic is off"
    assert "[ddes_rostest_demo.rosunit-fails/test_c_errors][ERROR]" + "-" * 26 in block
    assert "boom" in block
    assert block[-5:] == ["SUMMARY", " * RESULT: FAIL", " * TESTS: 3", " * ERRORS: 1",
                          " * FAILURES: 1"]
    assert out[-1] == (f"test [fails] failed on seed 4; replay it with: ddes rostest --seed 4 "
                       f"{TESTS / 'fail.test'}")


def test_text_mode_prints_each_test_nodes_unittest_text_then_the_summary(tmp_path: Path) -> None:
    report, out, _err = rostest(tmp_path, "--text", str(TESTS / "fail.test"))
    assert report.code == 2
    text = "\n".join(out)
    first = out[0]
    assert re.fullmatch(r"testfails \(rostest\.runner\.RosTest(\.testfails)?\) \.\.\. "
                        r"\[ROSTEST\]setup\[.*fail\.test\] run_id\[[0-9a-f-]{36}\] starting", first)
    for line in ("[ROSTEST]Running test [fails]", "process[talker-1]: started with pid",
                 "[ROSTEST]running test fails", "process[fails-2]: started with pid",
                 "Ran 3 tests in 1.000s", "FAILED (failures=1, errors=1)", "SUMMARY:",
                 " * RESULT: FAIL", " * TESTS: 3",
                 " * ERRORS: 1 [__main__.Fails.test_c_errors]",
                 " * FAILURES: 1 [__main__.Fails.test_b_fails]",
                 "[fails-2] process has died [pid", "[ROSTEST]test [fails] finished",
                 "[ROSTEST]test [fails] results summary: 1 errors, 1 failures, 3 tests",
                 "[talker-1] killing on exit", "Ran 1 test in 1.000s"):
        assert line in text, line
    assert any(re.fullmatch(r"test_b_fails \(__main__\.Fails(\.test_b_fails)?\) \.\.\. FAIL",
                            line) for line in out)
    # the unittest report of the test node, then rostest's SUMMARY (with --text too)
    assert text.index("Ran 3 tests") < text.index("[ROSTEST]" + "-" * 71)
    assert summary_block(out)[-5:] == ["SUMMARY", " * RESULT: FAIL", " * TESTS: 3",
                                       " * ERRORS: 1", " * FAILURES: 1"]


def test_the_same_file_gives_the_same_digest_every_run(tmp_path: Path) -> None:
    a, out_a, _ = rostest(tmp_path / "a", str(TESTS / "pass.test"))
    b, out_b, _ = rostest(tmp_path / "b", str(TESTS / "pass.test"))
    c, _, _ = rostest(tmp_path / "c", "--text", str(TESTS / "pass.test"))
    assert a.digest == b.digest == c.digest
    assert [r.digest for r in a.runs] == [r.digest for r in b.runs]
    strip = [line.replace(str(tmp_path / "a"), "R") for line in out_a]
    assert strip == [line.replace(str(tmp_path / "b"), "R") for line in out_b]
    other, _, _ = rostest(tmp_path / "d", "--seed", "1", str(TESTS / "pass.test"))
    assert other.digest != a.digest  # another seed, other worlds (their run ids differ)


def test_time_limit_is_simulated_seconds(tmp_path: Path) -> None:
    report, out, _err = rostest(tmp_path, str(TESTS / "timeout.test"))
    assert report.code == 1  # the runner's error, as rostest exits
    assert report.runs[0].timed_out and report.runs[0].simulated_ns == 3_000_000_000
    assert "[Testcase: testsleeps] ... ERROR!" in out
    assert ("ERROR: max time [3.0s] allotted for test [sleeps] of type "
            "[ddes_rostest_demo/sleeps.py]") in out
    assert summary_block(out)[-4:] == [" * RESULT: FAIL", " * TESTS: 0", " * ERRORS: 1",
                                       " * FAILURES: 0"]


def test_text_mode_shows_the_timeout_as_rostests_exception(tmp_path: Path) -> None:
    _report, out, _err = rostest(tmp_path, "--text", str(TESTS / "timeout.test"))
    assert ("roslaunch.launch.RLTestTimeoutException: max time [3.0s] allotted for test "
            "[sleeps] of type [ddes_rostest_demo/sleeps.py]") in out
    assert "[sleeps-1] killing on exit" in out


def test_retry_runs_a_failed_test_again_on_the_next_seed(tmp_path: Path) -> None:
    # flaky.py passes when its draw from the world's random stream is below 0.5: on seed 1 it
    # draws 0.89, on seed 2 0.77, on seed 3 0.45
    report, out, _err = rostest(tmp_path, "--seed", "1", str(TESTS / "retry.test"))
    assert report.code == 0
    assert [(r.attempt, r.seed, r.failed) for r in report.runs] == [
        (0, 1, True), (1, 2, True), (2, 3, False)]
    log = ET.parse(tmp_path / "results" / "ddes_rostest_demo" / "rostest-test_retry.xml")
    system_out = log.getroot().findtext("system-out") or ""
    assert "[ROSTEST]test [flaky] failed, retrying. Retries left: 2" in system_out
    assert "[ROSTEST]test [flaky] failed on seed 1; the retry runs on seed 2" in system_out
    assert "[ROSTEST]test [flaky] failed, retrying. Retries left: 1" in system_out
    assert summary_block(out)[-4:] == [" * RESULT: SUCCESS", " * TESTS: 1", " * ERRORS: 0",
                                       " * FAILURES: 0"]
    # the seed the retry passed on passes at once; retries that run out fail
    again, _, _ = rostest(tmp_path / "again", "--seed", "3", str(TESTS / "retry.test"))
    assert [(r.attempt, r.seed, r.failed) for r in again.runs] == [(0, 3, False)]
    out_of_luck, out, _ = rostest(tmp_path / "once", "--seed", "1", str(TESTS / "retry_once.test"))
    assert out_of_luck.code == 2 and len(out_of_luck.runs) == 2
    assert out[-1].startswith("test [flaky] failed on seed 2; replay it with: ddes rostest "
                              "--seed 2 ")


def test_a_required_node_ending_shuts_the_test_down(tmp_path: Path) -> None:
    report, out, _err = rostest(tmp_path, "--text", str(TESTS / "required.test"))
    text = "\n".join(out)
    assert "REQUIRED process [quitter-1] has died!" in text
    assert "[sleeps-2] killing on exit" in text
    # the test node is shut down as rospy is on SIGINT; its wall-clock sleep goes on, as
    # rospy's time.sleep does, and the test is killed with the launch: no results, as rostest
    assert "AssertionError: test [sleeps] did not generate test results" in text
    assert report.code == 1 and report.runs[0].simulated_ns == 1_000_000_000


def test_junit_xml_round_trip(tmp_path: Path) -> None:
    rostest(tmp_path, str(TESTS / "fail.test"))
    folder = tmp_path / "results" / "ddes_rostest_demo"
    node = ET.parse(folder / "rosunit-fails.xml").getroot()
    assert node.tag == "testsuite" and node.attrib == {
        "errors": "1", "failures": "1", "name": "unittest.suite.TestSuite", "tests": "3",
        "time": "1.000"}
    cases = {c.get("name"): c for c in node.iter("testcase")}
    assert cases["test_a_passes"].attrib == {"classname": "__main__.Fails",
                                             "name": "test_a_passes", "time": "1.0000"}
    failure = cases["test_b_fails"].find("failure")
    assert failure is not None and failure.get("type") == "AssertionError"
    assert (failure.text or "").startswith("2 != 3 : arithmetic is off\n")
    error = cases["test_c_errors"].find("error")
    assert error is not None and error.get("type") == "RuntimeError"
    outer = ET.parse(folder / "rostest-test_fail.xml").getroot()
    assert [(c.get("classname"), c.get("name")) for c in outer.iter("testcase")] == [
        ("rostest.runner.RosTest", "testfails")]
    assert "[ROSTEST]running test fails" in (outer.findtext("system-out") or "")
    # read back as rostest reads it
    result = junitxml.read(folder / "rosunit-fails.xml", "fails")
    assert (result.num_tests, result.num_errors, result.num_failures) == (3, 1, 1)
    assert [(c.name, c.passed) for c in result.test_case_results] == [
        ("ddes_rostest_demo.rosunit-fails/test_a_passes", True),
        ("ddes_rostest_demo.rosunit-fails/test_b_fails", False),
        ("ddes_rostest_demo.rosunit-fails/test_c_errors", False)]
    assert result.test_case_results[1].classname == "fails.Fails"
    # a file rostest's own helper shape writes reads back too
    bad = tmp_path / "bad" / "rosunit-x.xml"
    bad.parent.mkdir()
    bad.write_text(junitxml.test_failure_junit_xml("x", "it broke"))
    broken = junitxml.read(bad, "x")
    assert broken.num_failures == 1
    assert broken.test_case_results[0].failures[0].text == "it broke"
    warned: list[str] = []
    assert junitxml.read(tmp_path / "none.xml", "n", warn=warned.append).num_tests == 0
    assert warned and warned[0].startswith("WARN: cannot read test result file")


@pytest.mark.parametrize("name, code", [("pass.test", 0), ("fail.test", 2),
                                        ("timeout.test", 1)])
def test_the_command_exits_as_rostest_does(name: str, code: int, tmp_path: Path,
                                           capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["rostest", "--results-dir", str(tmp_path), str(TESTS / name)]) == code
    assert "trace digest: " in capsys.readouterr().out


def test_results_filename_names_rostests_own_file(tmp_path: Path) -> None:
    report, out, _ = rostest(tmp_path, "--results-filename", "mine.xml", str(TESTS / "pass.test"))
    assert report.results_file == str(tmp_path / "results" / "ddes_rostest_demo" /
                                      "rostest-mine.xml")
    assert ET.parse(report.results_file).getroot().get("tests") == "2"


def test_help_prints_the_usage(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["rostest", "-h"]) == 0
    assert capsys.readouterr().out.startswith("usage: rostest [options] [package] <filename>")


def test_the_command_finds_a_file_in_a_package(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.setenv("DDES_PACKAGE_PATH", str(DEMO.parent))
    assert main(["rostest", "--results-dir", str(tmp_path), "ddes_rostest_demo",
                 "pass.test"]) == 0
    assert " * RESULT: SUCCESS" in capsys.readouterr().out
    assert main(["rostest", "ddes_rostest_demo", "nope.test"]) == 1
    assert "is neither a launch file in package [ddes_rostest_demo]" in capsys.readouterr().err
    assert main(["rostest", "--reuse-master", "x.test"]) == 1


def test_the_console_runs_rostest_in_worlds_of_its_own(tmp_path: Path) -> None:
    console = Console(out=lambda _line: None)
    before = console.world.digest()
    result = console.execute(f"rostest --results-dir {tmp_path} {TESTS / 'pass.test'}")
    assert result.code == 0 and " * RESULT: SUCCESS" in result.out
    assert console.world.digest() == before  # the console's own world is untouched
    assert "/talker" not in console.run("rosnode list")


def test_the_loader_keeps_tests_with_their_attributes() -> None:
    plan = load_launch("""<launch>
      <node pkg="p" type="t" name="n"/>
      <test test-name="a" pkg="p" type="x.py" time-limit="7.5" retry="2" args="-v"
            required="true"><param name="k" value="1"/><remap from="in" to="out"/></test>
      <test test-name="b" name="bee" pkg="p" type="y.py" ns="g"/>
    </launch>""", rospack=RosPack([], bundled=False))
    a, b = plan.tests
    assert (a.test_name, a.name, a.time_limit, a.retry, a.args, a.required) == (
        "a", "a", 7.5, 2, ["-v"], False)
    assert a.remappings == [("in", "out")] and a.params == {"/a/k": 1}
    assert (b.test_name, b.full_name, b.time_limit, b.retry) == ("b", "/g/bee", 60.0, 0)
    assert [n.name for n in plan.nodes] == ["n"] and plan.params == {"/a/k": 1}


def test_missing_and_duplicate_test_nodes_fail_as_rostest_says(tmp_path: Path) -> None:
    path = tmp_path / "pkg" / "test" / "x.test"
    path.parent.mkdir(parents=True)
    (tmp_path / "pkg" / "package.xml").write_text("<package><name>pkg</name></package>")
    path.write_text("""<launch>
      <test test-name="gone" pkg="pkg" type="nothing.py"/>
      <test test-name="nopkg" pkg="no_such_pkg" type="x.py"/>
      <test test-name="unit" pkg="ddes_rostest_demo" type="unit.py"/>
      <test test-name="unit" pkg="ddes_rostest_demo" type="unit.py" name="unit2"/>
    </launch>""")
    out: list[str] = []
    report = run_rostest(["--results-dir", str(tmp_path / "r"), str(path)],
                         rospack=RosPack([DEMO.parent]), world_class=World, out=out.append,
                         err=out.append)
    assert report.code == 1
    text = "\n".join(out)
    assert "Test node [pkg/nothing.py] does not exist or is not executable" in text
    assert "Package [no_such_pkg] for test node [no_such_pkg/x.py] does not exist" in text
    assert "Duplicate tests named [unit] in rostest suite" in text
    # as in rostest, the duplicate's failing method replaces the first one of that name
    assert "[testgone][failed]" in text and "[testunit][failed]" in text
    assert " * TESTS: 0" in text and " * FAILURES: 3" in text and report.runs == []
