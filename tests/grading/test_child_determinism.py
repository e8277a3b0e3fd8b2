"""The same submission gets the same grade every time: what its nodes read of the machine (the
clocks, entropy, hash and id() order) is pinned in the grading child (ddes.grading.determinism),
and no address reaches a report or a digest."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import Any

import pytest

from ddes.grading import Criterion, Exercise, grade
from ddes.grading.exercise import Facts

pytest.importorskip("numpy")

HERE = Path(__file__).resolve().parent

SAID: list[str] = []


def _build(world: Any, _scenario: Any) -> None:
    listener = world.create_node("/grader_listener")
    listener.subscribe("/chatter", world.messages.get_message_class("std_msgs/String"),
                       lambda m: None)
    # the student's log lines cross too, so their text reaches the grader's trace and digest
    listener.subscribe("/rosout", world.messages.get_message_class("rosgraph_msgs/Log"),
                       lambda m: None)


def _keep(facts: Facts) -> tuple[float, list[str]]:
    said = [m.data for _t, who, m in facts.messages("/chatter") if who in facts.student_nodes]
    SAID.extend(said)
    return (1.0, []) if said else (0.0, ["said nothing"])


EXERCISE = Exercise(id="pinned", title="Pinned", duration=1.0, build=_build,
                    scripts=(("talker.py", ()),), criteria=(Criterion("1", "says", 1, _keep),))

#: A node that reads every source of nondeterminism a node has and publishes what it got (as
#: JSON on /chatter at t=0.5 s), logs an object's repr, then raises with one in the text.
TALKER = """\
    import datetime
    import importlib
    import json
    import os
    import random
    import secrets
    import sys
    import time
    import uuid

    import numpy as np
    import rospy
    from std_msgs.msg import String

    real_time = importlib.import_module("time")          # as a module of the student's has it
    real_datetime = importlib.import_module("datetime")
    real_random = importlib.import_module("random")


    class Thing:
        pass


    def gather():
        got = {}
        got["time"] = [time.time(), time.time_ns(), time.monotonic(), time.perf_counter()]
        got["module time"] = [real_time.time(), real_time.time_ns(), real_time.monotonic(),
                              real_time.perf_counter_ns(), real_time.process_time(),
                              real_time.ctime(), real_time.strftime("%Y-%m-%d %H:%M:%S"),
                              real_time.localtime()[:6]]
        got["datetime"] = [datetime.datetime.now().isoformat(),
                           datetime.datetime.utcnow().isoformat(),
                           datetime.datetime.today().isoformat(), datetime.date.today().isoformat(),
                           real_datetime.datetime.now().isoformat(),
                           real_datetime.datetime.now(real_datetime.timezone.utc).isoformat(),
                           real_datetime.date.today().isoformat()]
        got["os.urandom"] = os.urandom(8).hex()
        got["os.getrandom"] = os.getrandom(8).hex()
        got["uuid4"] = str(uuid.uuid4())
        got["uuid1"] = str(uuid.uuid1())
        got["secrets"] = [secrets.token_hex(8), secrets.randbelow(10 ** 9)]
        got["SystemRandom"] = [random.SystemRandom().random(), real_random.SystemRandom().random()]
        got["random"] = [random.random(), real_random.random()]
        got["Random()"] = [random.Random().random(), real_random.Random().random()]
        random.seed()
        real_random.seed()
        got["seed()"] = [random.random(), real_random.random()]
        got["numpy"] = [np.random.default_rng().random(), np.random.rand(),
                        np.random.RandomState().rand()]
        with open("/dev/urandom", "rb") as f:
            got["/dev/urandom"] = f.read(8).hex()
        fd = os.open("/dev/urandom", os.O_RDONLY)
        got["os.open /dev/urandom"] = os.read(fd, 8).hex()
        os.close(fd)
        got["hash"] = [hash("abc"), sys.flags.hash_randomization]
        return got


    def tick(_event):
        pub.publish(json.dumps(gather(), sort_keys=True))
        rospy.loginfo("made %r", Thing())
        raise ValueError("broken %r" % (Thing(),))


    rospy.init_node("talker")
    pub = rospy.Publisher("chatter", String, queue_size=10)
    rospy.Timer(rospy.Duration(0.5), tick, oneshot=True)
    rospy.spin()
"""

#: A node that publishes what id() tells of its objects: their order, a set's, a repr, a hash.
ID_TALKER = """\
    import json

    import rospy
    from std_msgs.msg import String


    class Thing:
        pass


    def tick(_event):
        things = [Thing() for _ in range(20)]
        pub.publish(json.dumps([sorted(range(20), key=lambda i: id(things[i])),
                                [things.index(t) for t in set(things)],
                                repr(things[0]), hex(id(things[1])), hash(things[2])]))


    rospy.init_node("talker")
    pub = rospy.Publisher("chatter", String, queue_size=10)
    rospy.Timer(rospy.Duration(0.5), tick, oneshot=True)
    rospy.spin()
"""

_ADDRESS = re.compile(r"0x[0-9a-f]{4,}")


def _submission(tmp_path: Path, name: str, source: str) -> Path:
    sub = tmp_path / name
    sub.mkdir()
    (sub / "talker.py").write_text(textwrap.dedent(source))
    return sub


def _grade(sub: Path) -> tuple[dict[str, Any], Any]:
    SAID.clear()
    report = grade(EXERCISE, sub)
    assert len(SAID) == 1, report.to_text()
    out = report.to_gradescope()
    out.pop("execution_time")
    return out, json.loads(SAID[0])


def test_every_source_answers_the_same_on_every_grade(tmp_path: Path) -> None:
    first, got = _grade(_submission(tmp_path, "a", TALKER))
    second, again = _grade(_submission(tmp_path, "b", TALKER))
    assert got == again
    assert first == second  # the score, the problem lines, the digest
    assert not _ADDRESS.search(json.dumps(first)), first  # no address reaches the report
    assert "ValueError: broken <__main__.Thing object at 0x…>" in first["output"]
    # the clocks read the simulated instant (0.5 s after 1970-01-01 00:00 UTC)
    assert got["time"] == [0.5, 500_000_000, 0.5, 0.5]
    assert got["module time"] == [0.5, 500_000_000, 0.5, 500_000_000, 0.5,
                                  "Thu Jan  1 00:00:00 1970", "1970-01-01 00:00:00",
                                  [1970, 1, 1, 0, 0, 0]]
    assert got["datetime"] == ["1970-01-01T00:00:00.500000"] * 3 + ["1970-01-01"] + [
        "1970-01-01T00:00:00.500000", "1970-01-01T00:00:00.500000+00:00", "1970-01-01"]
    assert got["hash"] == [_hash_seed_0("abc"), 0]  # PYTHONHASHSEED=0 in the child
    # the entropy is a stream's, not the machine's: every draw differs from the others
    draws = [got["os.urandom"], got["os.getrandom"], got["/dev/urandom"],
             got["os.open /dev/urandom"], got["secrets"][0]]
    assert len(set(draws)) == len(draws)
    assert got["uuid4"][14] == "4" and got["uuid1"][14] == "1"


def _hash_seed_0(text: str) -> int:
    out = subprocess.run([sys.executable, "-c", f"print(hash({text!r}))"], check=True,
                         capture_output=True, text=True, env={"PYTHONHASHSEED": "0"})
    return int(out.stdout)


def _aslr_can_be_switched_off() -> bool:
    from ddes.grading.determinism import aslr_off

    out = subprocess.run(["cat", "/proc/self/personality"], capture_output=True, text=True,
                         preexec_fn=aslr_off(), check=False)
    return out.returncode == 0 and bool(int(out.stdout, 16) & 0x0040000)


def test_id_order_repeats_on_every_grade(tmp_path: Path) -> None:
    """With address-space randomisation off (the sandbox's pre-exec step), objects lie at the
    same addresses on every grade: an order by id(), a set of objects, a repr, a default hash
    repeat."""
    if not _aslr_can_be_switched_off():
        pytest.skip("this kernel (or container) refuses personality(ADDR_NO_RANDOMIZE)")
    first, got = _grade(_submission(tmp_path, "a", ID_TALKER))
    second, again = _grade(_submission(tmp_path, "b", ID_TALKER))
    assert got == again
    assert first == second


GRADE_IN_A_PROCESS = """
import json, sys
sys.path.insert(0, sys.argv[1])
import test_child_determinism as t
from ddes.grading import grade
report = grade(t.EXERCISE, sys.argv[2]).to_gradescope()
report.pop("execution_time")
print(json.dumps(report, sort_keys=True))
"""


def test_a_grade_has_one_digest_in_two_processes(tmp_path: Path) -> None:
    """The same grade in two grader processes (other hash seeds, other addresses): the same
    report and digest, though the node logs and raises with an object's repr."""
    sub = _submission(tmp_path, "a", TALKER)
    reports = []
    for hash_seed in ("1", "2"):
        out = subprocess.run([sys.executable, "-c", GRADE_IN_A_PROCESS, str(HERE), str(sub)],
                             capture_output=True, text=True, check=True,
                             env=dict(os.environ, PYTHONHASHSEED=hash_seed))
        reports.append(json.loads(out.stdout))
    assert reports[0] == reports[1]
    assert reports[0]["extra_data"]["digests"]["public"]
