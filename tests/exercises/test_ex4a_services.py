"""Exercise 4a: the reference earns everything over a few seeds, the starter (exercise 3 working,
the service part to write) at most 20 %, the
console script is parsed as rosservice fills a SetBool request, a hard-coded service name loses
the hidden scenarios; one grading's wall time is printed."""

from __future__ import annotations

import shutil
import time
from pathlib import Path

import pytest

from ddes.grading import REGISTRY, grade
from ddes.grading.exercises.ex4a_services import parse_script, scenarios

ROOT = Path(__file__).resolve().parents[2]
SOLUTION = ROOT / "solutions" / "ex4a_services"
STARTER = ROOT / "exercises" / "ex4a_services"
NODE = "smb_highlevel_controller/scripts/smb_highlevel_controller_node.py"
EX = REGISTRY.get("ex4a_services")


def points(report):  # type: ignore[no-untyped-def]
    return {c.id: c.points for c in report.criteria}


def test_reference_earns_everything_and_one_grading_is_timed() -> None:
    start = time.perf_counter()
    report = grade(EX, SOLUTION, seed=0)
    wall = time.perf_counter() - start
    print(f"ex4a_services: one grading (3 scenarios of {EX.duration:g} s) took {wall:.2f} s wall")
    assert report.score == 100, [c.evidence for c in report.criteria]


@pytest.mark.slow
@pytest.mark.ci  # CI sweeps seeds 0-4 in tests/exercises/test_sensitivity.py as well
def test_reference_has_no_false_failure_over_a_few_seeds() -> None:
    for seed in (1, 2, 3):
        report = grade(EX, SOLUTION, seed=seed)
        assert report.score == 100, (seed, [c.evidence for c in report.criteria])


def test_starter_earns_at_most_20_percent() -> None:
    assert grade(EX, STARTER, seed=0).score <= 20


def test_starter_is_exercise_3_working_with_only_the_service_part_to_write() -> None:
    """"You start from your package of exercise 3": the starter drives into the pillar and marks
    it (exercise 3's grader gives it full marks); what is left to write is the service part."""
    assert grade(REGISTRY.get("ex3_pillar"), STARTER, seed=0).score == 100
    text = (STARTER / NODE).read_text()
    stubs = text.count("your code here")
    assert stubs == 4, text  # the Service, ~stop_service_name, stop_callback, the stopped test
    assert "def stop_callback" in text and "rospy.Service(" not in text


def test_a_hard_coded_service_name_loses_the_hidden_scenarios(tmp_path: Path) -> None:
    sub = tmp_path / "sub"
    shutil.copytree(SOLUTION, sub)
    node = sub / NODE
    text = node.read_text()
    old = 'rospy.Service(self.stop_service_name, SetBool'
    assert old in text
    node.write_text(text.replace(old, 'rospy.Service("/emergency_stop", SetBool'))
    got = points(grade(EX, sub, seed=0))
    # the public scenario keeps its points, the two hidden ones lose theirs
    assert round(got["4a.1"], 3) == round(20 / 3, 3) and round(got["4a.3"], 3) == round(10 / 3, 3)
    assert round(got["4a.4"], 3) == round(20 / 3, 3) and round(got["4a.6"], 3) == round(10 / 3, 3)


def test_the_script_is_parsed_as_rosservice_fills_a_request() -> None:
    lines = parse_script('# comment\nrosservice call /estop "data: true"\nsleep 2\n'
                         "rosservice call /estop '{data: false}'\nrosservice call /estop true\n"
                         "rosservice call estop \"data: true\"\nrostopic pub /x\nsleep 99\n"
                         'rosservice call /estop "dat: true"\n')
    assert [(x.number, x.name, x.data, x.sleep, bool(x.error)) for x in lines] == [
        (2, "/estop", True, 0.0, False), (3, "", None, 2.0, False),
        (4, "/estop", False, 0.0, False), (5, "/estop", True, 0.0, False),
        (6, "", None, 0.0, True), (7, "", None, 0.0, True), (8, "", None, 0.0, True),
        (9, "", None, 0.0, True)]


def test_hidden_scenarios_come_from_the_seed() -> None:
    a, b = scenarios(5, False), scenarios(5, False)
    assert a == b and a[1].params != scenarios(6, False)[1].params
    assert a[1].params["service"] != a[2].params["service"] or a[1].params != a[2].params


# -- 4a.1's class rule accepts every correct form (docs/grading.md, "Source checks") -------------

from ddes.grading.exercise import Facts  # noqa: E402
from ddes.grading.exercises.ex4a_services import _class_rule  # noqa: E402

ME = "/smb_highlevel_controller"
NODE_CLASS = '''import functools
import rospy
import rospy as r
from rospy import Service as RosService
from std_srvs.srv import SetBool


class Controller:
    def __init__(self):
        self.name = rospy.get_param({param})
        {service}

    def stop(self, request):
        pass


def handler(request):
    pass


if __name__ == "__main__":
    rospy.init_node("smb_highlevel_controller")
    controller = Controller()
    {main}
    rospy.spin()
'''


def rule(tmp_path: Path, service: str, main: str = "pass",
         param: str = '"~stop_service_name"', read: str = "stop_service_name") -> str:
    (tmp_path / NODE).parent.mkdir(parents=True)
    (tmp_path / NODE).write_text(NODE_CLASS.format(service=service, main=main, param=param))
    facts = Facts(exercise=None, scenario=None, world=None, outcome=None, refused=[],
                  submission=tmp_path, student_nodes=[ME],
                  param_reads=[(0, ME, f"{ME}/{read}", True)])
    return _class_rule(facts)


@pytest.mark.parametrize("service", [
    "rospy.Service(self.name, SetBool, self.stop)",
    "rospy.Service(self.name, SetBool, handler=self.stop)",
    "RosService(self.name, SetBool, handler=lambda req: self.stop(req))",
    "r.Service(self.name, SetBool, functools.partial(self.stop))",
    "cb = self.stop; self.srv = rospy.Service(self.name, SetBool, cb)",
])
def test_the_class_s_service_in_any_spelling(tmp_path: Path, service: str) -> None:
    assert rule(tmp_path, service) == ""


def test_the_parameter_read_by_any_name(tmp_path: Path) -> None:
    service = "rospy.Service(self.name, SetBool, self.stop)"
    assert rule(tmp_path, service, param='rospy.get_name() + "/stop_service_name"') == ""
    assert "does not read the private parameter" in rule(tmp_path / "b", service,
                                                         read="other")


@pytest.mark.parametrize("service, main, why", [
    ("rospy.Service(self.name, SetBool, handler)", "pass", "one of its methods"),
    ("rospy.Service(self.name, SetBool, lambda req: handler(req))", "pass",
     "one of its methods"),
    ("pass", "rospy.Service('/estop', SetBool, controller.stop)", "main part advertises"),
    ("pass", "RosService('/estop', SetBool, controller.stop)", "main part advertises"),
    ("pass", "pass", "advertises no Service"),
])
def test_a_service_outside_the_class_or_not_bound_loses(tmp_path: Path, service: str,
                                                        main: str, why: str) -> None:
    assert why in rule(tmp_path, service, main)
