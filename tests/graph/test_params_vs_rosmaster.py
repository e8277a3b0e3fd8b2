"""A node's parameter calls against rospy's client talking XML-RPC to a real rosmaster.

The same operations — ``get_param`` (with and without a default),
``has_param``, ``search_param``, ``delete_param``, ``set_param`` and
``get_param_names`` on edge-case keys (``""``, ``"/"``, ``"~"``, ``"~x"``,
``"a/b"``, ``"a//b"``, ``"x/sub"`` below a value ...) from nodes in the root
namespace and in nested ones — run on a ddes node and, on the ROS side,
through ``rospy.get_param`` & co. (rospy's own name resolution and
``MasterProxy``) against a private ``rosmaster``.  Every result (value, or
the kind of error) and the parameter tree after each change must agree,
except the deliberate deviations of docs/parameters.md, which are checked to
be exactly what the docs say.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from typing import Any

import pytest

import ddes
from ddes.errors import ROSException, ROSParamException
from ddes.graph.names import canonicalize_name

from .rosmaster_script import MASTER

TREE: dict[str, Any] = {
    "a": {"b": 1, "c": {"d": 2}}, "x": 10, "s": "str",
    "node": {"x": 11, "p": {"q": 3}},
    "ns": {"a": {"z": 5}, "node": {"x": 12, "p": {"q": 4}}, "y": 6, "deep": {"k": 1}},
}
CALLERS = ["/node", "/ns/node", "/ns/deep/node", "/other"]
KEYS = ["", "/", "~", "~x", "~/x", "x", "/x", "a", "a/b", "a/b/", "a//b", "/a/b", "y", "k",
        "missing", "missing/sub", "x/sub", "s/t", "~p/q", "p/q", "//", "a/c", "ns", "/ns/"]


def operations() -> list[list[Any]]:
    ops: list[list[Any]] = []
    for caller in CALLERS:
        for key in KEYS:
            ops += [[caller, "get_param", [key]], [caller, "get_param", [key, "DEF"]],
                    [caller, "has_param", [key]], [caller, "search_param", [key]],
                    [caller, "delete_param", [key]], [caller, "set_param", [key, 7]],
                    [caller, "set_param", [key, {"k": 1}]]]
        ops.append([caller, "get_param_names", []])
    return ops


def _category(exc: BaseException) -> str:
    for cls, name in ((KeyError, "KeyError"), (ROSException, "ROSException"),
                      (TypeError, "TypeError"), (ValueError, "ValueError")):
        if isinstance(exc, cls):
            return name
    return type(exc).__name__


def replay_on_ddes(ops: list[list[Any]]) -> list[dict[str, Any]]:
    """Each operation on a fresh copy of TREE, from a ddes node named as the caller."""
    world = ddes.World(seed=0)
    nodes: dict[str, ddes.Node] = {}
    results = []
    for caller, fn, args in ops:
        world.params.set_param("/", TREE)
        node = nodes.get(caller) or nodes.setdefault(caller, world.create_node(caller))
        try:
            out: dict[str, Any] = {"ok": getattr(node, fn)(*args)}
        except Exception as exc:  # noqa: BLE001 - the kind of error is the result
            out = {"err": _category(exc)}
        if fn in ("set_param", "delete_param"):
            out["tree"] = world.params.get_param("/")
        results.append(out)
    return json.loads(json.dumps(results))


ROSPY_CLIENT = MASTER + r'''
import json, sys, warnings
import rospy, rospy.names
from rospy.exceptions import ROSException
master = xmlrpc.client.ServerProxy(MASTER_URI)

def category(exc):
    for cls, name in ((KeyError, "KeyError"), (ROSException, "ROSException"),
                      (TypeError, "TypeError"), (ValueError, "ValueError")):
        if isinstance(exc, cls):
            return name
    return type(exc).__name__

data = json.load(sys.stdin)
results = []
for caller, fn, args in data["ops"]:
    master.setParam("/reset", "/", data["tree"])
    rospy.names._set_caller_id(caller)  # what init_node sets: rospy resolves against it
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # rospy warns about illegal names
        try:
            out = {"ok": getattr(rospy, fn)(*args)}
        except Exception as e:
            out = {"err": category(e)}
    if fn in ("set_param", "delete_param"):
        out["tree"] = master.getParam("/reset", "/")[2]
    results.append(out)
print(json.dumps(results))
'''


def deviation(op: list[Any]) -> str | None:
    """The docs/parameters.md deviation an operation falls under, or None."""
    caller, fn, args = op
    key = args[0] if args else None
    if fn == "get_param_names":
        return "sorted names"
    if isinstance(key, str) and key.startswith("~/"):
        return "rospy resolves ~/x to /x"
    root = key in ("/", "//") or (key == "" and caller.count("/") == 1)
    if fn == "set_param" and root and not isinstance(args[1], dict):
        return "set_param of the root to a non-dict raises"
    if fn == "search_param" and isinstance(key, str) and key and not key.startswith("~") \
            and canonicalize_name(key) != key:
        return "search_param returns canonical names"
    return None


def check_deviation(op: list[Any], ours: dict[str, Any], theirs: dict[str, Any]) -> None:
    """``ours`` differs from ``theirs`` exactly as the documented deviation says."""
    caller, fn, args = op
    why = deviation(op)
    if why == "sorted names":
        assert ours["ok"] == sorted(theirs["ok"]) != theirs["ok"]
    elif why == "rospy resolves ~/x to /x":
        # rospy.names.resolve_name("~/x") is "/x" (rospy #3044); ddes resolves as rosgraph
        # does, to the node's own x.  ddes given "/x" answers what rospy answered.
        as_rospy_read_it = [caller, fn, ["/" + args[0][2:], *args[1:]]]
        assert replay_on_ddes([as_rospy_read_it])[0] == theirs
    elif why == "set_param of the root to a non-dict raises":
        assert ours == {"err": "TypeError", "tree": TREE}
        assert theirs == {"ok": None, "tree": TREE}  # the master refused; rospy ignored it
    elif why == "search_param returns canonical names":
        assert theirs["ok"] is not None and ours["ok"] == canonicalize_name(theirs["ok"])
    else:
        raise AssertionError(f"{op}: no documented deviation covers ddes {ours} / rospy {theirs}")


def test_the_replay_runs_without_ros() -> None:
    ops = [["/ns/node", "search_param", [""]], ["/ns/node", "search_param", ["~x"]],
           ["/ns/node", "get_param", [""]], ["/node", "set_param", ["/", 5]],
           ["/ns/node", "search_param", ["a/b"]], ["/ns/node", "delete_param", ["/"]]]
    assert replay_on_ddes(ops) == [
        {"ok": None}, {"err": "ROSException"}, {"ok": TREE["ns"]},
        {"err": "TypeError", "tree": TREE}, {"ok": "/ns/a/b"}, {"err": "KeyError", "tree": TREE}]


@pytest.mark.ros
def test_parameter_calls_agree_with_rospy_and_rosmaster(ros_python: Callable[..., Any]) -> None:
    ops = operations()
    theirs = ros_python(ROSPY_CLIENT, as_json=True,
                        stdin=json.dumps({"tree": TREE, "ops": ops}), timeout=300)
    ours = replay_on_ddes(ops)
    assert len(theirs) == len(ours) == len(ops)
    mismatches = []
    deviations = 0
    for op, o, t in zip(ops, ours, theirs):
        if o == t:
            assert deviation(op) is None or deviation(op) == "rospy resolves ~/x to /x", op
            continue
        deviations += 1
        try:
            check_deviation(op, o, t)
        except AssertionError as exc:
            mismatches.append(f"{op}: ddes {o}, rospy {t} ({exc})")
    assert not mismatches, "\n".join(mismatches[:20])
    assert deviations < len(ops) // 10


# -- the edge cases, without ROS -----------------------------------------------------------------


def test_search_param_edge_cases() -> None:
    world = ddes.World()
    world.params.set_param("/", TREE)
    root, nested = world.create_node("node"), world.create_node("node", namespace="/ns")
    assert root.search_param("") is None and nested.search_param("") is None
    assert root.search_param("/") == "/" and nested.search_param("/") == "/"
    assert nested.search_param("x") == "/ns/node/x"         # the node's own namespace first
    assert nested.search_param("a/anything") == "/ns/a/anything"  # first component decides
    assert root.search_param("a/b") == "/a/b"
    assert nested.search_param("missing") is None
    assert nested.search_param("/a/b") == "/a/b" and nested.search_param("/nope") is None
    for key in ("~", "~x", "~p/q"):
        with pytest.raises(ROSParamException, match="cannot search for parameter: Internal "
                                                   "failure: invalid key"):
            nested.search_param(key)


def test_get_has_delete_set_edge_cases() -> None:
    world = ddes.World()
    world.params.set_param("/", TREE)
    root, nested = world.create_node("node"), world.create_node("node", namespace="/ns")
    assert root.get_param("") == TREE and nested.get_param("") == TREE["ns"]  # the namespace
    assert nested.get_param("~") == TREE["ns"]["node"] and nested.get_param("~p/q") == 4
    assert root.has_param("/") and root.has_param("") and not root.has_param("x/sub")
    assert nested.get_param("x/sub", "DEF") == "DEF"  # below a value: not set
    with pytest.raises(KeyError):
        nested.get_param("missing/sub")
    with pytest.raises(KeyError):
        root.delete_param("/")
    with pytest.raises(KeyError):
        root.delete_param("")  # the root namespace, as rosmaster refuses
    nested.delete_param("")  # the node's namespace /ns goes
    assert not root.has_param("/ns")
    nested.set_param("", {"k": 1})  # sets the namespace, replacing it
    assert root.get_param("/ns") == {"k": 1}
    with pytest.raises(TypeError):
        root.set_param("", 7)  # the root only takes a dict (rospy would ignore the error)
    root.set_param("x/sub", 3)  # a value on the way becomes a namespace
    assert root.get_param("x") == {"sub": 3}
