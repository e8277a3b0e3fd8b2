"""Upstream rostest files (../shared/upstream) under ``ddes rostest``, and one against real rostest.

The files whose test methods all pass on ddes today are run here, each as rostest runs it (one
world per <test>); docs/rostest.md has the table of every upstream file with Python test nodes,
real rostest beside ddes, and the cause of each failure. The test marked ``ros`` runs
rospy_tutorials' talker/listener file with Noetic's ``rostest`` and compares its SUMMARY and its
JUnit XML with ddes's.
"""

from __future__ import annotations

import json
import os
import re
import textwrap
import xml.etree.ElementTree as ET
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from ddes.console.rostest import run_rostest
from ddes.rospack import RosPack
from ddes.world import World

UPSTREAM = Path(__file__).resolve().parents[3] / "shared" / "upstream"
PATH = [UPSTREAM / "ros_tutorials", UPSTREAM / "actionlib", UPSTREAM / "common_tutorials"]

pytestmark = [pytest.mark.skipif(not UPSTREAM.is_dir(), reason="no ../shared/upstream here"),
              pytest.mark.filterwarnings("ignore::DeprecationWarning")]  # their assert_, assertEquals

#: (package, file) -> the test methods run, all passing on ddes.
PASSING = {
    ("rospy_tutorials", "test-talker-listener.launch"): 1,
    ("rospy_tutorials", "test-talker-listener-with-timer.launch"): 1,
    ("rospy_tutorials", "test-on-shutdown.launch"): 1,
    ("rospy_tutorials", "test-peer-subscribe-notify.launch"): 1,
    ("rospy_tutorials", "test-add-two-ints.launch"): 3,
    ("rospy_tutorials", "test-connection-header.launch"): 3,
    ("actionlib", "test_imports.launch"): 1,
    ("actionlib", "test_python_exercise_simple_client.launch"): 7,
    ("actionlib", "test_python_server2.launch"): 1,
    ("actionlib", "test_python_server3.launch"): 4,
    ("actionlib", "test_python_server_components.launch"): 3,
    ("actionlib", "test_python_simple_server.launch"): 1,
}


#: Files that pass with a link latency (``ddes rostest --latency S``): their nodes answer each
#: other as fast as the transport allows (docs/rostest.md, the deadlock row).
PASSING_WITH_LATENCY = {
    ("actionlib", "test_simple_action_server_deadlock_python.launch"): (1, "0.05"),
}


def _run(tmp_path: Path, *words: str) -> tuple[Any, list[str]]:
    out: list[str] = []
    report = run_rostest(["--results-dir", str(tmp_path), *words], rospack=RosPack(PATH),
                         world_class=World, out=out.append, err=out.append)
    return report, out


def test_upstream_packages_shadow_the_bundled_ones() -> None:
    rospack = RosPack(PATH)
    for name in ("rospy_tutorials", "actionlib", "roscpp_tutorials"):
        assert UPSTREAM in rospack.get_path(name).parents, name


@pytest.mark.parametrize("package, name", list(PASSING))
def test_upstream_file_passes(package: str, name: str, tmp_path: Path) -> None:
    report, out = _run(tmp_path, package, name)
    assert report.code == 0, "\n".join(out)
    assert (report.tests, report.errors, report.failures) == (PASSING[package, name], 0, 0)
    again, _ = _run(tmp_path / "again", package, name)
    assert again.digest == report.digest


@pytest.mark.parametrize("package, name", list(PASSING_WITH_LATENCY))
def test_upstream_file_passes_with_a_latency(package: str, name: str, tmp_path: Path) -> None:
    methods, latency = PASSING_WITH_LATENCY[package, name]
    report, out = _run(tmp_path, "--latency", latency, package, name)
    assert report.code == 0, "\n".join(out[-40:])
    assert (report.tests, report.errors, report.failures) == (methods, 0, 0)


def test_at_zero_latency_the_deadlock_file_is_a_zero_time_livelock(tmp_path: Path) -> None:
    report, out = _run(tmp_path, "--instant-budget", "2000", "actionlib",
                       "test_simple_action_server_deadlock_python.launch")
    assert report.code != 0
    assert any("zero-time livelock" in line for line in out)


#: rospy_tutorials' Python messages are not in Debian's ROS: genpy generates them for the real
#: rostest's processes (as tests/compat/test_rospy_interop.py does).
REAL_ROSTEST = textwrap.dedent("""
    import json, os, subprocess
    from genpy.generator import MsgGenerator, SrvGenerator
    pkg = {package!r}
    gen = {gen!r}
    for kind, make in (("msg", MsgGenerator), ("srv", SrvGenerator)):
        out = os.path.join(gen, "rospy_tutorials", kind)
        os.makedirs(out)
        names = sorted(f[:-4] for f in os.listdir(os.path.join(pkg, kind)))
        make().generate_messages("rospy_tutorials",
                                 [os.path.join(pkg, kind, n + "." + kind) for n in names], out,
                                 {{"rospy_tutorials": [os.path.join(pkg, "msg")],
                                  "std_msgs": ["/usr/share/std_msgs/msg"]}})
        with open(os.path.join(out, "__init__.py"), "w") as f:
            f.write("".join("from ._%s import *\\n" % n for n in names))
    open(os.path.join(gen, "rospy_tutorials", "__init__.py"), "w").close()
    env = dict(os.environ, ROS_PACKAGE_PATH={path!r}, ROS_HOME={home!r}, PYTHONPATH=gen)
    proc = subprocess.run(["rostest", "--results-base-dir", {results!r}, *{words!r}],
                          capture_output=True, text=True, timeout=240, env=env)
    print(json.dumps({{"code": proc.returncode, "out": proc.stdout, "err": proc.stderr}}))
""")


def _plain(text: str) -> list[str]:
    return re.sub(r"\x1b\[[0-9;]*m", "", text).split("\n")


def _summary(lines: list[str]) -> list[str]:
    start = lines.index("[ROSTEST]" + "-" * 71)
    end = next(i for i in range(start, len(lines)) if lines[i].startswith(" * FAILURES:"))
    return lines[start:end + 1]


@pytest.mark.ros
@pytest.mark.parametrize("package, name, test_name, methods", [
    ("rospy_tutorials", "test-talker-listener.launch", "talker_listener_test",
     ["test_talker_listener"]),
    ("rospy_tutorials", "test-add-two-ints.launch", "add_two_ints",
     ["test_add_two_ints", "test_add_two_ints_bad_then_good", "test_add_two_ints_bad_type"]),
])
def test_the_summary_is_real_rostests(package: str, name: str, test_name: str,
                                      methods: list[str], ros_python: Callable[..., Any],
                                      tmp_path: Path) -> None:
    try:
        ros_python("import rostest")
    except AssertionError:
        pytest.skip("Noetic's rostest is not installed (python3-rostest)")
    real_dir = tmp_path / "real"
    script = REAL_ROSTEST.format(
        package=str(UPSTREAM / "ros_tutorials" / "rospy_tutorials"), gen=str(tmp_path / "gen"),
        path=os.pathsep.join(map(str, PATH)), home=str(tmp_path / "home"),
        results=str(real_dir), words=[package, name])
    theirs = json.loads(ros_python(script, timeout=300))
    assert theirs["code"] == 0, theirs
    real_lines = _plain(theirs["out"])
    expected = ["[ROSTEST]" + "-" * 71, "",
                *[f"[{package}.rosunit-{test_name}/{m}][passed]" for m in methods], "",
                "SUMMARY", " * RESULT: SUCCESS", f" * TESTS: {len(methods)}", " * ERRORS: 0",
                " * FAILURES: 0"]
    assert _summary(real_lines) == expected
    ours, out = _run(tmp_path / "ddes", package, name)
    assert _summary(out) == expected
    assert ours.code == 0
    outer = "test" + test_name
    assert f"[Testcase: {outer}] ... ok" in real_lines and f"[Testcase: {outer}] ... ok" in out
    # the same files, with the same shape
    stem = name.rsplit(".", 1)[0]
    for file in (f"rostest-test_{stem}.xml", f"rosunit-{test_name}.xml"):
        real = ET.parse(real_dir / package / file).getroot()
        mine = ET.parse(tmp_path / "ddes" / package / file).getroot()
        assert real.tag == mine.tag == "testsuite"
        assert sorted(real.attrib) == sorted(mine.attrib)
        assert {k: real.get(k) for k in ("errors", "failures", "tests", "name")} == \
            {k: mine.get(k) for k in ("errors", "failures", "tests", "name")}
        assert [(c.get("classname"), c.get("name")) for c in real.iter("testcase")] == \
            [(c.get("classname"), c.get("name")) for c in mine.iter("testcase")]
        assert [c.tag for c in real] == [c.tag for c in mine]
