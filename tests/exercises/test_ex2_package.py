"""Exercise 2: the reference earns 100 %, the starter at most 20 %, typical bugs lose their
criteria; the starter generator and ``ddes course build --check``."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from ddes.cli.main import main
from ddes.errors import GradingError
from ddes.grading import REGISTRY, grade
from ddes.grading.starter import starter_text

REPO = Path(__file__).resolve().parents[2]
SOLUTION = REPO / "solutions" / "ex2_package"
STARTER = REPO / "exercises" / "ex2_package"
NODE = "smb_highlevel_controller/scripts/smb_highlevel_controller_node.py"


def points(report):
    return {c.id: c.points for c in report.criteria}


def variant(tmp_path: Path, old: str, new: str, rel: str = NODE) -> Path:
    dst = tmp_path / "submission"
    shutil.copytree(SOLUTION, dst)
    text = (dst / rel).read_text()
    assert old in text
    (dst / rel).write_text(text.replace(old, new))
    return dst


def test_course_build_check_is_clean(capsys):
    assert main(["course", "build", "--check", "--root", str(REPO)]) == 0
    assert "up to date" in capsys.readouterr().out


def test_course_build_check_names_a_stale_file(tmp_path, capsys):
    shutil.copytree(REPO / "solutions" / "ex2_package", tmp_path / "solutions" / "ex2_package")
    assert main(["course", "build", "--root", str(tmp_path)]) == 0
    (tmp_path / "exercises" / "ex2_package" / "README.md").write_text("edited\n")
    (tmp_path / "exercises" / "ex2_package" / "extra.txt").write_text("extra\n")
    capsys.readouterr()
    assert main(["course", "build", "--check", "--root", str(tmp_path)]) == 1
    out = capsys.readouterr().out
    assert "out of date: exercises/ex2_package/README.md" in out
    assert "out of date: exercises/ex2_package/extra.txt" in out


def test_starter_text_stubs():
    py = "def f():\n    ### BEGIN SOLUTION\n    return 1\n    ### END SOLUTION\n"
    assert starter_text(py, "a.py") == 'def f():\n    raise NotImplementedError("your code here")\n'
    custom = "    ### BEGIN SOLUTION stub: pass  # your code here\n    x = 1\n    ### END SOLUTION\n"
    assert starter_text(custom, "a.py") == "    pass  # your code here\n"
    xml = "<a>\n  <!-- ### BEGIN SOLUTION -->\n  <b/>\n  <!-- ### END SOLUTION -->\n</a>\n"
    assert starter_text(xml, "x.launch") == "<a>\n  <!-- your code here -->\n</a>\n"
    assert starter_text("### BEGIN SOLUTION\nk: 1\n### END SOLUTION\n", "c.yaml") == \
        "# your code here\n"
    with pytest.raises(GradingError, match="a.py:1: BEGIN SOLUTION is never closed"):
        starter_text("### BEGIN SOLUTION\nx\n", "a.py")
    with pytest.raises(GradingError, match="END SOLUTION without"):
        starter_text("### END SOLUTION\n", "a.py")


def test_reference_scores_full_marks():
    report = grade(REGISTRY.get("ex2_package"), SOLUTION)
    assert points(report) == {"2.1": 40, "2.2": 30, "2.3": 15, "2.4": 15}, report.to_text()
    # one grading's wall time (3 scenarios of 8 simulated seconds, a sandboxed child each)
    print(f"ex2_package reference: {report.execution_time:.2f} s wall")
    assert report.execution_time < 60


def test_starter_scores_at_most_20_percent():
    report = grade(REGISTRY.get("ex2_package"), STARTER)
    assert report.score <= 0.2 * report.max_score
    assert points(report) == {"2.1": 0, "2.2": 6, "2.3": 0, "2.4": 0}, report.to_text()


def test_hard_coded_topic_and_queue_size_lose_2_3(tmp_path):
    sub = variant(tmp_path, 'self.scan_topic = rospy.get_param("~scan_topic")',
                  'self.scan_topic = "/scan"')
    got = points(grade(REGISTRY.get("ex2_package"), sub))
    # the public scenario uses the student's own file; the two hidden ones move the laser
    assert got["2.3"] == pytest.approx(5 + 10 / 3, abs=1e-3)
    assert got["2.1"] == pytest.approx(40 / 3, abs=1e-3)
    assert got["2.2"] == 30 and got["2.4"] == 15


def test_largest_range_and_wrong_frame_lose_2_1_and_2_4(tmp_path):
    sub = variant(tmp_path, "return min(valid) if valid else math.inf",
                  "return max(valid) if valid else math.inf",
                  rel="smb_highlevel_controller/src/smb_highlevel_controller/algorithm.py")
    rviz = sub / "smb_highlevel_controller/rviz/smb_highlevel_controller.rviz"
    rviz.write_text(rviz.read_text().replace("Fixed Frame: odom", "Fixed Frame: map"))
    got = points(grade(REGISTRY.get("ex2_package"), sub, public=True))
    assert got == {"2.1": 0, "2.2": 30, "2.3": 15, "2.4": 10}


# -- 2.2's source checks accept every correct form (docs/grading.md, "Source checks") ------------

from ddes.grading.exercise import Facts  # noqa: E402
from ddes.grading.exercises.common import (  # noqa: E402
    argument,
    bound_to_self,
    rospy_subscribers,
    student_script,
)
from ddes.grading.exercises.ex2_package import check_structure  # noqa: E402

ME = "/smb_highlevel_controller"
HEAD = "import rospy\nfrom sensor_msgs.msg import LaserScan\n"


def source_facts(root: Path, files: dict[str, str]) -> Facts:
    """Facts of a submission made of ``files`` that read the node's private ~scan_topic (only
    the source checks and the parameters read are used)."""
    for rel, text in files.items():
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        (root / rel).write_text(text)
    return Facts(exercise=None, scenario=None, world=None, outcome=None, refused=[],
                 submission=root, student_nodes=[ME],
                 param_reads=[(0, ME, f"{ME}/scan_topic", True)])


def with_reference(tmp_path: Path, node: str, extra: dict[str, str] | None = None) -> Facts:
    root = tmp_path / "submission"
    shutil.copytree(SOLUTION, root)
    return source_facts(root, {NODE: node, **(extra or {})})


def bound_subscribers(facts: Facts) -> list[bool]:
    node = student_script(facts, NODE)
    return [bound_to_self(src, argument(c, 2, "callback"), m)
            for src, c, m in rospy_subscribers(node)]


CLASS = '''
class Controller:
    def __init__(self):
        self.topic = rospy.get_param("~scan_topic")
        {sub}

    def on_scan(self, scan, extra=None):
        pass


def plain(scan):
    pass


if __name__ == "__main__":
    rospy.init_node("smb_highlevel_controller")
    Controller()
    rospy.spin()
'''


@pytest.mark.parametrize("sub, bound", [
    ("rospy.Subscriber(self.topic, LaserScan, self.on_scan)", True),
    ("rospy.Subscriber(self.topic, LaserScan, callback=self.on_scan, queue_size=1)", True),
    ("rospy.Subscriber(self.topic, LaserScan, lambda scan: self.on_scan(scan))", True),
    ("rospy.Subscriber(self.topic, LaserScan, functools.partial(self.on_scan, extra=1))", True),
    ("rospy.Subscriber(self.topic, LaserScan, partial(self.on_scan))", True),
    ("rospy.Subscriber(self.topic, LaserScan, getattr(self, 'on_scan'))", True),
    ("cb = self.on_scan; rospy.Subscriber(self.topic, LaserScan, cb)", True),
    ("Sub(self.topic, LaserScan, self.on_scan)", True),
    ("r.Subscriber(self.topic, LaserScan, self.on_scan)", True),
    ("rospy.Subscriber(self.topic, LaserScan, plain)", False),
    ("rospy.Subscriber(self.topic, LaserScan, lambda scan: plain(scan))", False),
    ("cb = plain; rospy.Subscriber(self.topic, LaserScan, cb)", False),
])
def test_a_subscriber_bound_to_a_method_in_any_spelling(tmp_path: Path, sub: str,
                                                        bound: bool) -> None:
    head = (HEAD + "import functools\nfrom functools import partial\nimport rospy as r\n"
            "from rospy import Subscriber as Sub\n")
    facts = source_facts(tmp_path, {NODE: head + CLASS.format(sub=sub)})
    assert bound_subscribers(facts) == [bound]


@pytest.mark.parametrize("files", [
    {  # from the package's module
        NODE: HEAD + "from smb_highlevel_controller.node import Controller\n"
        "rospy.init_node('smb_highlevel_controller')\nController()\nrospy.spin()\n"},
    {  # the module under an alias
        NODE: HEAD + "import smb_highlevel_controller.node as n\n"
        "def main():\n    n.Controller()\n    rospy.spin()\n\nmain()\n"},
    {  # re-exported by the package's __init__
        NODE: HEAD + "from smb_highlevel_controller import Controller as C\nC()\n",
        "smb_highlevel_controller/src/smb_highlevel_controller/__init__.py":
            "from .node import Controller\n"},
    {  # a class of the script inheriting the module's
        NODE: HEAD + "from smb_highlevel_controller.node import Controller\n"
        "class Mine(Controller):\n    pass\n\nMine()\n"},
])
def test_the_class_may_come_from_a_module_of_the_package(tmp_path: Path,
                                                        files: dict[str, str]) -> None:
    module = "smb_highlevel_controller/src/smb_highlevel_controller/node.py"
    sub = ("self.sub = rospy.Subscriber(self.topic, LaserScan, self.on_scan)\n"
           "        smallest_range([1.0], 0.0, 2.0)")
    klass = CLASS.format(sub=sub).split("\n\ndef plain")[0]
    facts = with_reference(tmp_path, "", {
        module: HEAD + "from .algorithm import smallest_range\n" + klass, **files})
    node = student_script(facts, NODE)
    assert node.built and "Controller" in [c.name for _s, c in node.classes]
    assert bound_subscribers(facts) == [True]
    points, lines = check_structure(facts)
    assert points == 30, lines


def test_a_class_that_is_not_built_or_not_there_loses(tmp_path: Path) -> None:
    facts = with_reference(tmp_path, HEAD + "from smb_highlevel_controller.node import X\n"
                           "X()\n")  # no such module: nothing to resolve
    points, lines = check_structure(facts)
    assert "does not define (or import) a class" in "\n".join(lines)
    assert points <= 12


@pytest.mark.parametrize("imports, call, used", [
    ("from smb_highlevel_controller.algorithm import smallest_range", "smallest_range", True),
    ("from smb_highlevel_controller.algorithm import smallest_range as low", "low", True),
    ("import smb_highlevel_controller.algorithm as alg", "alg.smallest_range", True),
    ("from smb_highlevel_controller import algorithm", "algorithm.smallest_range", True),
    ("import smb_highlevel_controller.algorithm", "smb_highlevel_controller.algorithm."
     "smallest_range", True),
    ("from smb_highlevel_controller.algorithm import *", "smallest_range", True),
    ("from math import fsum as low", "low", False),
])
def test_the_algorithm_called_through_any_import(tmp_path: Path, imports: str, call: str,
                                                 used: bool) -> None:
    sub = (f"self.sub = rospy.Subscriber(self.topic, LaserScan, self.on_scan)\n"
           f"        {call}([1.0], 0.0, 2.0)")
    facts = with_reference(tmp_path, HEAD + imports + "\n" + CLASS.format(sub=sub))
    points, lines = check_structure(facts)
    assert (points == 30) is used, lines
    if not used:
        assert "the class calls no function of algorithm.py" in lines
