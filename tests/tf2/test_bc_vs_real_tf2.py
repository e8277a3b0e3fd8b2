"""ddes.tf2.BufferCore against the real tf2 (tf2_py under Debian's system Python).

Each randomised scenario (chains, stars, random trees, forests; static and dynamic links;
interpolation; extrapolation into the past and the future; unknown and invalid frames; parent
changes; old and repeated data; cache pruning with 1, 2 and 10 s caches; fixed-frame lookups;
clear) runs on both; every result agrees to 1e-9, every exception has the same class and text,
and every logged warning and error has tf2's text.
"""

from __future__ import annotations

import json
import logging
import math
from typing import Any

import pytest

from ddes.msg import get_message_class
from ddes.tf2 import BufferCore
from ddes.time import Duration, Time

from .tf2_scenarios import REAL_SCRIPT, RUNNER, loop_scenario, scenario

pytestmark = pytest.mark.ros

SEEDS = list(range(60))

_namespace: dict[str, Any] = {}
exec(compile(RUNNER, "tf2_scenarios.RUNNER", "exec"), _namespace)  # noqa: S102 - our own source
run_scenario = _namespace["run_scenario"]

TS = get_message_class("geometry_msgs/TransformStamped")


def make_ts(parent: str, child: str, stamp: int, tr: list[float], q: list[float]) -> Any:
    m = TS()
    m.header.frame_id = parent
    m.child_frame_id = child
    m.header.stamp = Time.from_nsec(stamp)
    m.transform.translation.x, m.transform.translation.y, m.transform.translation.z = tr
    (m.transform.rotation.x, m.transform.rotation.y, m.transform.rotation.z,
     m.transform.rotation.w) = q
    return m


def run_ddes(ops: list[list[Any]]) -> tuple[list[Any], list[str]]:
    records: list[str] = []

    class Grab(logging.Handler):
        def emit(self, record: logging.LogRecord) -> None:
            records.append(record.getMessage())

    logger = logging.getLogger("ddes.tf2")
    handler = Grab()
    logger.addHandler(handler)
    try:
        out = run_scenario(ops, lambda ns: BufferCore(Duration.from_nsec(ns)), make_ts,
                           Time.from_nsec)
    finally:
        logger.removeHandler(handler)
    return json.loads(json.dumps(out)), records


_REAL: dict[str, Any] = {}


@pytest.fixture
def real(ros_python: Any) -> dict[str, Any]:
    """Every scenario played once on the real tf2 (one system-Python run for the module)."""
    if not _REAL:
        scenarios = [scenario(s) for s in SEEDS] + [loop_scenario()]
        data = ros_python(REAL_SCRIPT, as_json=True, stdin=json.dumps(scenarios))
        _REAL.update(data, scenarios=scenarios)
    return _REAL


def assert_same(mine: Any, theirs: Any, where: str) -> None:
    if isinstance(theirs, float) or isinstance(mine, float):
        if math.isnan(theirs):
            assert math.isnan(mine), where
        else:
            assert abs(mine - theirs) <= 1e-9, f"{where}: {mine!r} != {theirs!r}"
    elif isinstance(theirs, list):
        assert isinstance(mine, list) and len(mine) == len(theirs), f"{where}: {mine} {theirs}"
        for k, (a, b) in enumerate(zip(mine, theirs, strict=True)):
            assert_same(a, b, f"{where}[{k}]")
    else:
        assert mine == theirs, f"{where}: {mine!r} != {theirs!r}"


@pytest.mark.parametrize("index", range(len(SEEDS) + 1))
def test_scenario_matches_real_tf2(real: dict[str, Any], index: int) -> None:
    ops = real["scenarios"][index]
    mine, logs = run_ddes(ops)
    theirs = real["results"][index]
    for k, (op, a, b) in enumerate(zip(ops, mine, theirs, strict=True)):
        assert_same(a, b, f"scenario {index} op {k} {op}")
    assert logs == real["logs"][index]


def test_the_scenarios_cover_every_outcome(real: dict[str, Any]) -> None:
    """The random scenarios do reach each behaviour the comparison claims to check."""
    seen: set[str] = set()
    for ops, results in zip(real["scenarios"], real["results"], strict=True):
        for op, res in zip(ops, results, strict=True):
            if res[0] == "err":
                seen.add(res[1])
                if "into the future" in res[2]:
                    seen.add("future")
                if "into the past" in res[2]:
                    seen.add("past")
                if "contains a loop" in res[2]:
                    seen.add("loop")
            elif op[0] == "lookup" and op[3] not in (0,) and op[1] != op[2]:
                seen.add("lookup ok")
            elif op[0] == "full":
                seen.add("full ok")
    for lines in real["logs"]:
        for line in lines:
            seen.add(line.split(" ")[0].rstrip(":"))
    for needed in ("LookupException", "ConnectivityException", "ExtrapolationException",
                   "InvalidArgumentException", "TransformException", "future", "past", "loop",
                   "lookup ok", "full ok", "TF_OLD_DATA", "TF_REPEATED_DATA", "TF_NAN_INPUT",
                   "TF_DENORMALIZED_QUATERNION", "TF_SELF_TRANSFORM"):
        assert needed in seen, f"no scenario reaches {needed}; seen {sorted(seen)}"
