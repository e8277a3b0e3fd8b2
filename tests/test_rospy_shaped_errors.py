"""ROS calls written the rospy way raise typed errors that show the ddes call to write.

ddes has no global node, so ``ddes.Rate(10)``, ``ddes.sleep(0.5)``,
``ddes.Publisher("/t", String)`` or ``SimpleActionServer("fib", ...)`` are
missing their node; rospy's module functions (``ddes.init_node``,
``ddes.spin`` ...) are node or world methods.  Each case names what the user
wrote and the ddes spelling.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import pytest

import ddes
from ddes.errors import (
    DdesTypeError,
    MissingNodeError,
    NoGlobalFunctionError,
    ROSInitException,
    RospyCallError,
)

String = ddes.get_message_class("std_msgs/String")
AddTwoInts = ddes.get_service_class("rospy_tutorials/AddTwoInts")
FIB = "actionlib_tutorials/FibonacciAction"
HINT = 'where node = world.create_node("my_node") and world = ddes.World().'
#: Every message ends by pointing at the other answer: plain rospy as a script node.
COMPAT_HINT_TAIL = ("\nOr `from ddes.compat import rospy` to write plain rospy: a rospy script "
                    "started as a node (rosrun PKG script.py) runs unchanged, its blocking calls "
                    "on simulated time (docs/rospy.md).")


def tick(event: Any) -> None:
    """A callback for the calls below."""


def handle(req: Any) -> None:
    """A service handler for the calls below."""


#: (the rospy-shaped call, what it echoes, the ddes lines the message must show)
CASES: list[tuple[Callable[[], object], str, list[str]]] = [
    (lambda: ddes.Rate(10), "ddes.Rate(10) is rospy's spelling",
     ["rate = ddes.Rate(node, 10)    # or node.create_rate(10)", "yield rate.sleep()"]),
    (lambda: ddes.Rate(2.5, reset=True), "ddes.Rate(2.5, reset=True)",
     ["rate = ddes.Rate(node, 2.5, reset=True)"]),
    (lambda: ddes.WallRate(10), "ddes.WallRate(10)",
     ["rate = ddes.WallRate(node, 10)    # or node.create_wall_rate(10)"]),
    (lambda: ddes.RoscppRate(10), "ddes.RoscppRate(10)",
     ["rate = ddes.RoscppRate(node, 10)    # or node.create_roscpp_rate(10)"]),
    (lambda: ddes.sleep(0.5), "ddes.sleep(0.5)",
     ["yield node.sleep(0.5)    # or: yield ddes.sleep(node, 0.5)"]),
    (lambda: ddes.sleep(ddes.Duration(1, 5)), "ddes.sleep(ddes.Duration(1, 5))",
     ["yield node.sleep(ddes.Duration(1, 5))"]),
    (lambda: ddes.duration_sleep(2), "ddes.duration_sleep(2)",
     ["yield node.duration_sleep(2)"]),
    (lambda: ddes.Time.now(), "ddes.Time.now()", ["ddes.Time.now(node)    # or node.get_rostime()"]),
    (lambda: ddes.Timer(ddes.Duration(1), tick), "ddes.Timer(ddes.Duration(1), tick)",
     ["timer = ddes.Timer(node, ddes.Duration(1), tick)    # or node.create_timer("
      "ddes.Duration(1), tick)"]),
    (lambda: ddes.Timer(0.5, tick, True), "ddes.Timer(0.5, tick, oneshot=True)",
     ["timer = ddes.Timer(node, 0.5, tick, oneshot=True)"]),
    (lambda: ddes.Publisher("/t", String), "ddes.Publisher('/t', String)",
     ["pub = ddes.Publisher(node, '/t', String)    # or node.advertise('/t', String)",
      "pub.publish(...)"]),
    (lambda: ddes.Publisher("chatter", String, queue_size=10, latch=True),
     "ddes.Publisher('chatter', String, latch=True, queue_size=10)",
     ["pub = ddes.Publisher(node, 'chatter', String, latch=True, queue_size=10)"]),
    (lambda: ddes.Subscriber("/t", String, tick, queue_size=1),
     "ddes.Subscriber('/t', String, tick, queue_size=1)",
     ["sub = ddes.Subscriber(node, '/t', String, tick, queue_size=1)    # or "
      "node.subscribe('/t', String, tick, queue_size=1)"]),
    (lambda: ddes.wait_for_message("/t", String, timeout=1),
     "ddes.wait_for_message('/t', String, timeout=1)",
     ["msg = yield node.wait_for_message('/t', String, timeout=1)"]),
    (lambda: ddes.SimpleActionServer("fib", FIB, execute_cb=tick, auto_start=False),
     f"ddes.SimpleActionServer('fib', '{FIB}', execute_cb=tick, auto_start=False)",
     [f"server = ddes.SimpleActionServer(node, 'fib', '{FIB}', execute_cb=tick, "
      "auto_start=False)", "server.start()"]),
    (lambda: ddes.SimpleActionServer("fib", FIB, tick), "ddes.SimpleActionServer",
     [f"server = ddes.SimpleActionServer(node, 'fib', '{FIB}', execute_cb=tick)"]),
    (lambda: ddes.SimpleActionClient("fib", FIB), f"ddes.SimpleActionClient('fib', '{FIB}')",
     [f"client = ddes.SimpleActionClient(node, 'fib', '{FIB}')"]),
    (lambda: ddes.ActionServer("fib", FIB, tick), "ddes.ActionServer",
     [f"server = ddes.ActionServer(node, 'fib', '{FIB}', tick)", "server.start()"]),
    (lambda: ddes.ActionClient("fib", FIB), "ddes.ActionClient",
     [f"client = ddes.ActionClient(node, 'fib', '{FIB}')"]),
    (lambda: ddes.Service("add", AddTwoInts, handle), "ddes.Service('add', AddTwoInts, handle)",
     ["srv = ddes.Service(node, 'add', AddTwoInts, handle)"]),
    (lambda: ddes.ServiceProxy("add", AddTwoInts), "ddes.ServiceProxy('add', AddTwoInts)",
     ["proxy = ddes.ServiceProxy(node, 'add', AddTwoInts)", "resp = yield proxy(req)"]),
    (lambda: ddes.wait_for_service("add", 1.0), "ddes.wait_for_service('add', timeout=1.0)",
     ["yield ddes.wait_for_service(node, 'add', timeout=1.0)"]),
]


@pytest.mark.parametrize("call,echo,lines", CASES, ids=[c[1].split(" is ")[0] for c in CASES])
def test_a_rospy_shaped_call_says_what_to_write(call: Callable[[], object], echo: str,
                                                lines: list[str]) -> None:
    with pytest.raises(MissingNodeError) as info:
        call()
    text = str(info.value)
    assert text.startswith(echo) and "rospy's spelling" in text
    assert "ddes has no global node (there is no rospy.init_node)" in text
    for line in lines:
        assert f"\n    {line}" in text, line
    assert text.endswith(HINT + COMPAT_HINT_TAIL)
    # the error is typed and catchable as what rospy (or Python) would raise
    assert isinstance(info.value, (RospyCallError, ROSInitException, ddes.ROSException, TypeError))


@pytest.mark.parametrize("name,line", [
    ("init_node", 'node = world.create_node("my_node")'),
    ("spin", "world.run(until=10.0)"),
    ("get_time", "node.get_time()"),
    ("get_rostime", "node.get_rostime()"),
    ("is_shutdown", "node.is_shutdown()"),
    ("on_shutdown", "node.on_shutdown(hook)"),
    ("loginfo", "node.loginfo(...)"),
    ("logwarn_throttle", "node.logwarn_throttle(...)"),
    ("logerr_throttle_identical", "node.logerr_throttle(period, ...)"),
    ("get_param", "node.get_param(...)"),
    ("search_param", "node.search_param(...)"),
    ("get_name", "node.get_name()"),
    ("myargv", "node.argv"),
])
def test_rospy_module_functions_name_the_node_method(name: str, line: str) -> None:
    with pytest.raises(NoGlobalFunctionError) as info:
        getattr(ddes, name)
    text = str(info.value)
    assert text.startswith(f"module 'ddes' has no attribute '{name}': rospy.{name} ")
    assert f"\n    {line}" in text
    assert text.endswith(COMPAT_HINT_TAIL)
    assert isinstance(info.value, AttributeError) and info.value.name == name
    assert not hasattr(ddes, name)  # an AttributeError: hasattr stays False


def test_init_node_shows_a_whole_program() -> None:
    with pytest.raises(NoGlobalFunctionError, match=r"ddes\.World\(seed=0\)[\s\S]*world\.run"):
        ddes.init_node("talker")  # type: ignore[attr-defined]


def test_other_missing_attributes_stay_plain() -> None:
    with pytest.raises(AttributeError) as info:
        ddes.no_such_thing  # type: ignore[attr-defined]  # noqa: B018
    assert type(info.value) is AttributeError
    assert str(info.value) == "module 'ddes' has no attribute 'no_such_thing'"


@pytest.mark.parametrize("call", [
    lambda: ddes.Rate("10"),
    lambda: ddes.sleep(object()),
    lambda: ddes.Timer(1.0, 2.0),
    lambda: ddes.Publisher(3, String),
    lambda: ddes.SimpleActionServer(4, FIB),
])
def test_other_wrong_first_arguments_are_type_errors(call: Callable[[], object]) -> None:
    with pytest.raises(DdesTypeError):
        call()


def test_the_ddes_spellings_work(world: ddes.World) -> None:
    node = world.create_node("n")
    ddes.Rate(node, 10)
    ddes.WallRate(node, 10)
    ddes.RoscppRate(node, 10)
    ddes.Timer(node, 1.0, tick)
    pub = ddes.Publisher(node, "/t", String, queue_size=1)
    ddes.Subscriber(node, "/t", String, tick)
    ddes.Service(node, "add", AddTwoInts, handle)
    ddes.ServiceProxy(node, "add", AddTwoInts)
    ddes.SimpleActionServer(node, "fib", FIB, auto_start=False)
    ddes.SimpleActionClient(node, "fib", FIB)
    assert ddes.Time.now(node) == ddes.Time(0)
    waiting = ddes.wait_for_message(node, "/t", String)

    def main() -> Any:
        yield ddes.wait_for_service(node, "add")
        yield ddes.sleep(node, 0.1)
        yield ddes.duration_sleep(node, 0.1)
        pub.publish("x")
        msg = yield waiting
        assert msg.data == "x"

    node.process(main())
    world.run(until=1.0)
    assert waiting.triggered


@pytest.mark.parametrize("call", [
    lambda node: ddes.Rate(node),
    lambda node: ddes.sleep(node),
])
def test_a_node_without_the_rest_is_a_type_error(world: ddes.World,
                                                 call: Callable[[Any], object]) -> None:
    with pytest.raises(DdesTypeError, match="needs a"):
        call(world.create_node("n"))
