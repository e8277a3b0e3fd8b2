"""The parameter server: rosmaster's rules, a model-based state machine, and real rosmaster."""

from __future__ import annotations

import copy
import json
import math
import random
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, invariant, precondition, rule

from ddes.errors import (
    DdesKeyError,
    DdesTypeError,
    DdesValueError,
    ROSNameException,
    ROSParamException,
)
from ddes.graph.params import ParamServer, to_xmlrpc

from ..docsnippets import run_snippet

# -- the tree rules ---------------------------------------------------------------------------------


def test_set_creates_namespaces_and_replaces_values_on_the_way() -> None:
    p = ParamServer()
    p.set_param("/a", 5)
    p.set_param("/a/b/c", 1)  # /a was an int: silently becomes a namespace
    assert p.get_param("/a") == {"b": {"c": 1}}
    p.set_param("/a/b", {"x": 2})  # a dict replaces the whole subtree
    assert p.get_param("/") == {"a": {"b": {"x": 2}}}
    p.set_param("relative/key", "v")  # relative keys are relative to /
    assert p.get_param("/relative/key") == "v"
    assert p.get_param("//a//b/") == {"x": 2}


def test_root_only_takes_a_dict() -> None:
    p = ParamServer()
    with pytest.raises(DdesTypeError, match="root"):
        p.set_param("/", 5)
    assert isinstance(DdesTypeError("x"), TypeError)
    p.set_param("/", {"k": 1})
    assert p.get_param("/") == {"k": 1}


def test_get_returns_copies_and_missing_keys_raise_key_error() -> None:
    p = ParamServer()
    p.set_param("/ns", {"l": [1, {"d": 2}]})
    got = p.get_param("/ns")
    got["l"][1]["d"] = 99
    got["new"] = 1
    assert p.get_param("/ns") == {"l": [1, {"d": 2}]}
    with pytest.raises(KeyError) as info:
        p.get_param("/ns/missing")
    assert isinstance(info.value, DdesKeyError)
    assert "/ns/missing" in str(info.value)
    with pytest.raises(KeyError):
        p.get_param("/ns/l/x")  # under a non-dict value
    assert p.get_param("/ns/missing", 7) == 7
    assert p.get_param("/ns/missing", None) is None


def test_delete_and_has() -> None:
    p = ParamServer()
    p.set_param("/a/b", 1)
    p.set_param("/s", "str")
    assert p.has_param("/") and p.has_param("/a") and p.has_param("/a/b")
    assert not p.has_param("/a/c") and not p.has_param("/s/t")
    with pytest.raises(KeyError, match="/a/c"):
        p.delete_param("/a/c")
    with pytest.raises(KeyError):
        p.delete_param("/s/t")  # rosmaster: TypeError inside, -1 to the client, KeyError in rospy
    with pytest.raises(KeyError, match="root"):
        p.delete_param("/")
    p.delete_param("/a")
    assert p.get_param("/") == {"s": "str"}


def test_search_param_walks_up_from_the_node() -> None:
    # rosmaster's own docstring example
    p = ParamServer()
    p.set_param("/robot_description", {"arm": 1, "base": 2})
    p.set_param("/pr2/robot_description", {"base": 3})
    assert p.search_param("/pr2/foo", "robot_description") == "/pr2/robot_description"
    assert p.search_param("/pr2/foo", "robot_description/arm") == "/pr2/robot_description/arm"
    assert p.search_param("/other/foo", "robot_description/arm") == "/robot_description/arm"
    assert p.search_param("/pr2/foo", "missing") is None
    assert p.search_param("/pr2/foo", "/robot_description") == "/robot_description"
    assert p.search_param("/pr2/foo", "/nope") is None
    p.set_param("/pr2/foo/robot_description", 0)  # the node's private namespace comes first
    assert p.search_param("/pr2/foo", "robot_description") == "/pr2/foo/robot_description"
    with pytest.raises(ROSNameException):
        p.search_param("/pr2", "~private")
    with pytest.raises(ROSNameException):
        p.search_param("relative", "key")
    with pytest.raises(ROSNameException):
        p.search_param("/pr2", "")


def test_get_param_names_sorted_leaves() -> None:
    p = ParamServer()
    p.set_param("/z", 1)
    p.set_param("/a", {"y": 1, "b": {}, "c": [{"d": 1}]})
    assert p.get_param_names() == ["/a/c", "/a/y", "/z"]


def test_values_are_xmlrpc_types() -> None:
    p = ParamServer()
    p.set_param("/t", (1, (2.5, "x")))
    assert p.get_param("/t") == [1, [2.5, "x"]]
    p.set_param("/b", b"\x00\x01")
    assert p.get_param("/b") == b"\x00\x01"
    p.set_param("/f", np.float64(1.5))
    assert type(p.get_param("/f")) is float
    p.set_param("/i", 2**31 - 1)
    for bad, err in [(None, DdesTypeError), (object(), DdesTypeError), (np.int64(3), DdesTypeError),
                     ({1: "a"}, DdesTypeError), ([1, None], DdesTypeError), (2**31, DdesValueError),
                     ({"a": {"b": -(2**31) - 1}}, DdesValueError)]:
        with pytest.raises(err) as info:
            p.set_param("/bad", bad)
        assert "/bad" in str(info.value)
    assert not p.has_param("/bad")


def test_names_are_checked_on_set_only() -> None:
    p = ParamServer()
    with pytest.raises(ROSNameException, match="foo-bar"):
        p.set_param("/foo-bar", 1)
    with pytest.raises(ROSNameException, match="private"):
        p.set_param("~x", 1)
    with pytest.raises(DdesTypeError):
        p.get_param(3)  # type: ignore[arg-type]
    p.load("base-link: {x: 1}")  # YAML keys are not graph names: stored as given
    assert p.get_param("/base-link/x") == 1


# -- notifications (rosmaster's compute_param_updates) ----------------------------------------------


def _recorder(log: list[Any], tag: str) -> Any:
    return lambda key, value: log.append((tag, key, value))


def test_subscribers_hear_changes_at_and_under_their_key() -> None:
    p = ParamServer()
    log: list[Any] = []
    p.subscribe(_recorder(log, "ab"), "/a/b")
    p.subscribe(_recorder(log, "all"))
    p.set_param("/a/b/c", 1)
    p.set_param("/a", {"b": {"d": 2}})
    p.set_param("/a", {"x": 3})
    p.set_param("/a/b/e", 4)
    p.delete_param("/a")
    p.set_param("/zz", 0)
    assert log == [
        ("ab", "/a/b/c", 1), ("all", "/a/b/c", 1),
        ("all", "/a", {"b": {"d": 2}}), ("ab", "/a/b", {"d": 2}),  # exact match inside the tree
        ("ab", "/a/b", {}), ("all", "/a", {"x": 3}),  # /a/b vanished
        ("ab", "/a/b/e", 4), ("all", "/a/b/e", 4),
        ("ab", "/a/b", {}), ("all", "/a", {}),  # deletion
        ("all", "/zz", 0),
    ]


def test_overwriting_a_parent_with_a_value_does_not_notify_deeper_subscribers() -> None:
    # rosmaster quirk, reproduced: only dict values are walked for deleted keys.
    p = ParamServer()
    log: list[Any] = []
    p.set_param("/a/b", 1)
    p.subscribe(_recorder(log, "ab"), "/a/b")
    p.set_param("/a", 5)
    assert log == []


def test_setter_is_not_notified_and_unsubscribe_stops_updates() -> None:
    p = ParamServer()
    log: list[Any] = []
    mine = p.subscribe(_recorder(log, "me"), "/x", caller_id="/me")
    p.subscribe(_recorder(log, "other"), "/x", caller_id="/other")
    p.set_param("/x", 1, caller_id="/me")
    assert log == [("other", "/x", 1)]
    mine.unsubscribe()
    mine.unsubscribe()
    p.set_param("/x", 2)
    assert log == [("other", "/x", 1), ("other", "/x", 2)]
    with pytest.raises(DdesTypeError):
        p.subscribe("not callable")  # type: ignore[arg-type]


def test_callbacks_get_copies() -> None:
    p = ParamServer()
    p.subscribe(lambda k, v: v.append(99) if isinstance(v, list) else None)
    p.set_param("/l", [1])
    assert p.get_param("/l") == [1]


# -- rosparam load / dump ------------------------------------------------------------------------------


def test_load_merges_documents_into_namespaces() -> None:
    p = ParamServer()
    p.set_param("/ns/keep", 1)
    loaded = p.load("a: 1\nsub: {b: 2, e: {}}\n---\n_ns: other\nc: [1, 2]\n---\n", "ns")
    assert p.get_param("/") == {"ns": {"keep": 1, "a": 1, "sub": {"b": 2}, "other": {"c": [1, 2]}}}
    assert loaded == [("/ns", {"a": 1, "sub": {"b": 2, "e": {}}}), ("/ns/other", {"c": [1, 2]}),
                      ("/ns", {})]
    p.load("5", "/ns/keep")  # a scalar replaces the value at ns
    assert p.get_param("/ns/keep") == 5
    p.load("/abs: 1\nrel: 2", "/ns2")  # rosparam's ns_join: global keys escape the namespace
    assert p.get_param("/abs") == 1 and p.get_param("/ns2/rel") == 2


def test_load_angles_like_rosparam() -> None:
    p = ParamServer()
    p.load("a: !degrees 180\nb: !radians pi/2\nc: deg(90)\nd: rad(2*pi)\ne: 'deg(90)'\nf: !radians 1.5")
    got = p.get_param("/")
    assert got["a"] == pytest.approx(math.pi)
    assert got["b"] == pytest.approx(math.pi / 2)
    assert got["c"] == pytest.approx(math.pi / 2)
    assert got["d"] == pytest.approx(2 * math.pi)
    assert got["e"] == "deg(90)"
    assert got["f"] == 1.5
    with pytest.raises(ROSParamException, match="radian"):
        p.load("x: !radians __import__('os')")
    with pytest.raises(ROSParamException, match="degree"):
        p.load("x: !degrees pi")
    # the global SafeLoader is untouched
    assert yaml.safe_load("c: deg(90)") == {"c": "deg(90)"}


def test_load_errors() -> None:
    p = ParamServer()
    with pytest.raises(ROSParamException, match="global / can only be set to a dictionary"):
        p.load("params.yaml")
    with pytest.raises(ROSParamException, match="invalid YAML"):
        p.load("a: [1,")
    with pytest.raises(ROSParamException, match="string keys"):
        p.load("1: a")
    with pytest.raises(DdesTypeError, match="/n"):
        p.load("n: ~")
    with pytest.raises(ROSParamException, match="does not exist"):
        p.load(Path("/nonexistent/params.yaml"))
    with pytest.raises(DdesTypeError):
        p.load(3)  # type: ignore[arg-type]


def test_load_file_and_dump(tmp_path: Path) -> None:
    f = tmp_path / "params.yaml"
    f.write_text("robot:\n  speed: 0.5\n  name: r2\n  wheels: [1, 2]\n", encoding="utf-8")
    p = ParamServer()
    p.load(f)
    assert p.dump("/robot") == "name: r2\nspeed: 0.5\nwheels:\n- 1\n- 2\n"
    assert p.dump("/robot/speed") == "0.5\n...\n"
    q = ParamServer()
    q.load(p.dump("/"), "/")
    assert q.get_param("/") == p.get_param("/")


xml_leaf = st.one_of(
    st.integers(-(2**31), 2**31 - 1), st.booleans(), st.text(max_size=5),
    st.floats(allow_nan=False, allow_infinity=False),
)
keys = st.sampled_from(["a", "b", "c"])
xml_value = st.recursive(
    xml_leaf,
    lambda inner: st.one_of(st.lists(inner, max_size=3), st.dictionaries(keys, inner, max_size=3)),
    max_leaves=8,
)


@given(st.dictionaries(keys, xml_value, max_size=3))
def test_dump_then_load_round_trips(tree: dict[str, Any]) -> None:
    p = ParamServer()
    p.set_param("/ns", tree)
    q = ParamServer()
    q.load(p.dump("/ns"), "/ns")

    def prune(v: Any) -> Any:  # loading merges leaves, so empty dicts do not come back
        if isinstance(v, dict):
            return {k: prune(x) for k, x in v.items() if not (isinstance(x, dict) and not prune(x))}
        return v

    assert q.get_param("/ns", {}) == prune(tree)


# -- the state machine against a flat model ---------------------------------------------------------------

Path_ = tuple[str, ...]


class FlatModel:
    """Leaves and namespaces keyed by component tuples: an independent statement of the rules."""

    def __init__(self) -> None:
        self.leaves: dict[Path_, Any] = {}
        self.spaces: set[Path_] = {()}

    def _drop_under(self, path: Path_) -> None:
        n = len(path)
        self.leaves = {p: v for p, v in self.leaves.items() if p[:n] != path}
        self.spaces = {p for p in self.spaces if p[:n] != path or p == ()}

    def _put(self, path: Path_, value: Any) -> None:
        if isinstance(value, dict):
            self.spaces.add(path)
            for k, v in value.items():
                self._put(path + (k,), v)
        else:
            self.leaves[path] = copy.deepcopy(value)

    def set(self, path: Path_, value: Any) -> None:
        if path == () and not isinstance(value, dict):
            raise TypeError
        self._drop_under(path)
        for i in range(1, len(path)):
            self.leaves.pop(path[:i], None)  # a value on the way becomes a namespace
            self.spaces.add(path[:i])
        self._put(path, value)

    def has(self, path: Path_) -> bool:
        return path in self.leaves or path in self.spaces

    def get(self, path: Path_) -> Any:
        if path in self.leaves:
            return self.leaves[path]
        if path not in self.spaces:
            raise KeyError(path)
        out: dict[str, Any] = {}
        n = len(path)
        for p in sorted(self.spaces):
            if len(p) > n and p[:n] == path:
                d = out
                for c in p[n:]:
                    d = d.setdefault(c, {})
        for p, v in self.leaves.items():
            if len(p) > n and p[:n] == path:
                d = out
                for c in p[n:-1]:
                    d = d.setdefault(c, {})
                d[p[-1]] = v
        return out

    def delete(self, path: Path_) -> None:
        if path == () or not self.has(path):
            raise KeyError(path)
        self._drop_under(path)

    def search(self, ns: Path_, key: Path_) -> Path_ | None:
        for i in range(len(ns), -1, -1):
            if self.has(ns[:i] + key[:1]):
                return ns[:i] + key
        return None

    def names(self) -> list[str]:
        return sorted("/" + "/".join(p) for p in self.leaves)


paths = st.lists(keys, max_size=3).map(tuple)


def _key(path: Path_) -> str:
    return "/" + "/".join(path)


class ParamTreeMachine(RuleBasedStateMachine):
    """Every operation of ParamServer against :class:`FlatModel`, checked after each step."""

    def __init__(self) -> None:
        super().__init__()
        self.server = ParamServer()
        self.model = FlatModel()

    @rule(path=paths, value=xml_value)
    def set(self, path: Path_, value: Any) -> None:
        try:
            self.model.set(path, value)
        except TypeError:
            with pytest.raises(TypeError):
                self.server.set_param(_key(path), value)
        else:
            self.server.set_param(_key(path), value)

    @rule(path=paths)
    def get(self, path: Path_) -> None:
        try:
            expected = self.model.get(path)
        except KeyError:
            with pytest.raises(KeyError):
                self.server.get_param(_key(path))
            assert not self.server.has_param(_key(path))
        else:
            assert self.server.get_param(_key(path)) == expected
            assert self.server.has_param(_key(path))

    @rule(path=paths)
    def delete(self, path: Path_) -> None:
        try:
            self.model.delete(path)
        except KeyError:
            with pytest.raises(KeyError):
                self.server.delete_param(_key(path))
        else:
            self.server.delete_param(_key(path))

    @rule(ns=paths, key=st.lists(keys, min_size=1, max_size=2).map(tuple))
    def search(self, ns: Path_, key: Path_) -> None:
        found = self.model.search(ns, key)
        assert self.server.search_param(_key(ns), "/".join(key)) == (None if found is None else _key(found))

    @precondition(lambda self: len(self.model.leaves) > 0)
    @rule(data=st.data())
    def get_existing_leaf(self, data: st.DataObject) -> None:
        path = data.draw(st.sampled_from(sorted(self.model.leaves)))
        assert self.server.get_param(_key(path)) == self.model.leaves[path]

    @invariant()
    def whole_tree_and_names_agree(self) -> None:
        assert self.server.get_param("/") == self.model.get(())
        assert self.server.get_param_names() == self.model.names()


TestParamTree = ParamTreeMachine.TestCase
TestParamTree.settings = settings(max_examples=150, stateful_step_count=30, deadline=None)


# -- against real rosmaster.paramserver.ParamDictionary -----------------------------------------------------

REPLAY_SCRIPT = r"""
import json, sys
from rosgraph.names import canonicalize_name
from rosmaster.paramserver import ParamDictionary
from rosmaster.registrations import RegistrationManager

def run(ops):
    reg = RegistrationManager(None)
    pd = ParamDictionary(reg)
    out, notes = [], []
    def notify(updates):
        for apis, key, value in updates:
            for caller_id, _api in apis:
                # copy now: rosmaster hands out references into its live tree
                notes.append([caller_id, canonicalize_name(key) or "/", json.loads(json.dumps(value))])
    for op in ops:
        kind = op[0]
        try:
            if kind == "set":
                pd.set_param(op[1], op[2], notify, op[3])
                out.append(None)
            elif kind == "get":
                out.append(json.dumps(pd.get_param(op[1])))
            elif kind == "has":
                out.append(pd.has_param(op[1]))
            elif kind == "delete":
                pd.delete_param(op[1], notify)
                out.append(None)
            elif kind == "search":
                r = pd.search_param(op[1], op[2])
                out.append(None if r is None else canonicalize_name(r))
            elif kind == "names":
                out.append(sorted(pd.get_param_names()))
            elif kind == "sub":
                pd.subscribe_param(op[1], (op[2], "http://" + op[2]))
                out.append(None)
            elif kind == "unsub":
                pd.unsubscribe_param(op[1], (op[2], "http://" + op[2]))
                out.append(None)
        except KeyError:
            out.append("KeyError")
        except TypeError:
            # getParam/deleteParam on the master turn this into code -1: KeyError in rospy
            out.append("TypeError" if kind == "set" else "KeyError")
    return {"out": out, "notes": notes}

print(json.dumps([run(ops) for ops in json.load(sys.stdin)]))
"""


def _random_value(rng: random.Random, depth: int = 0) -> Any:
    r = rng.random()
    if depth < 2 and r < 0.25:
        return {rng.choice("abc"): _random_value(rng, depth + 1) for _ in range(rng.randint(0, 3))}
    if depth < 2 and r < 0.35:
        return [_random_value(rng, depth + 1) for _ in range(rng.randint(0, 2))]
    return rng.choice([rng.randint(-5, 5), rng.random(), rng.choice(["x", "yz", ""]), True, False])


def random_ops(seed: int, n: int = 80) -> list[list[Any]]:
    rng = random.Random(seed)
    callers = ["/n1", "/n2", "/n3"]
    subs: list[tuple[str, str]] = []

    def key() -> str:
        return "/" + "/".join(rng.choice("abc") for _ in range(rng.randint(0, 3)))

    ops: list[list[Any]] = []
    for _ in range(n):
        kind = rng.choice(["set", "set", "set", "get", "has", "delete", "search", "names", "sub", "unsub"])
        if kind == "set":
            k = key()
            value = _random_value(rng) if k != "/" or rng.random() < 0.3 else {"a": _random_value(rng)}
            ops.append(["set", k, value, rng.choice(callers + [None])])
        elif kind == "search":
            ops.append(["search", key(), "/".join(rng.choice("abc") for _ in range(rng.randint(1, 2)))])
        elif kind == "names":
            ops.append(["names"])
        elif kind == "sub":
            pair = (key(), rng.choice(callers))
            if pair not in subs:
                subs.append(pair)
                ops.append(["sub", pair[0], pair[1]])
        elif kind == "unsub":
            if subs:
                pair = subs.pop(rng.randrange(len(subs)))
                ops.append(["unsub", pair[0], pair[1]])
        else:
            ops.append([kind, key()])
    return ops


def replay_on_ddes(ops: list[list[Any]]) -> dict[str, Any]:
    p = ParamServer()
    out: list[Any] = []
    notes: list[Any] = []
    handles: dict[tuple[str, str], Any] = {}
    for op in ops:
        kind = op[0]
        try:
            if kind == "set":
                p.set_param(op[1], op[2], caller_id=op[3])
                out.append(None)
            elif kind == "get":
                out.append(json.dumps(p.get_param(op[1])))
            elif kind == "has":
                out.append(p.has_param(op[1]))
            elif kind == "delete":
                p.delete_param(op[1])
                out.append(None)
            elif kind == "search":
                out.append(p.search_param(op[1], op[2]))
            elif kind == "names":
                out.append(p.get_param_names())
            elif kind == "sub":
                caller = op[2]

                def note(k: str, v: Any, c: str = caller) -> None:
                    notes.append([c, k, v])

                handles[(op[1], caller)] = p.subscribe(note, op[1], caller_id=caller)
                out.append(None)
            elif kind == "unsub":
                handles.pop((op[1], op[2])).unsubscribe()
                out.append(None)
        except KeyError:
            out.append("KeyError")
        except TypeError:
            out.append("TypeError")
    return {"out": out, "notes": notes}


def test_replay_harness_runs_locally() -> None:
    r = replay_on_ddes([["sub", "/a", "/n1"], ["set", "/a/b", 1, None], ["get", "/a"], ["set", "/", 3, None],
                        ["delete", "/"], ["search", "/a/x", "b"]])
    assert r == {"out": [None, None, '{"b": 1}', "TypeError", "KeyError", "/a/b"],
                 "notes": [["/n1", "/a/b", 1]]}


@pytest.mark.ros
@pytest.mark.parametrize("seed", [1, 2, 3, 4])
def test_agrees_with_rosmaster_on_random_operations(ros_python, seed: int) -> None:  # type: ignore[no-untyped-def]
    batches = [random_ops(seed * 1000 + i) for i in range(40)]
    theirs = ros_python(REPLAY_SCRIPT, as_json=True, stdin=json.dumps(batches))
    assert len(theirs) == len(batches)
    for ops, t in zip(batches, theirs):
        ours = json.loads(json.dumps(replay_on_ddes(ops)))
        assert len(ours["out"]) == len(t["out"]) == len(ops)
        for i, (o, th) in enumerate(zip(ours["out"], t["out"])):
            assert o == th, f"step {i} {ops[i]}: ddes {o!r}, rosmaster {th!r}\n{ops[:i + 1]}"
        assert ours["notes"] == t["notes"], ops


LOAD_SCRIPT = r"""
import json, sys
import rosparam
from rosgraph.names import resolve_name
from rosmaster.paramserver import ParamDictionary

results = []
for text, ns in json.load(sys.stdin):
    pd = ParamDictionary(None)
    class Fake:
        def setParam(self, key, value):
            pd.set_param(resolve_name(key, "/rosparam"), value)
    rosparam.get_param_server = lambda: Fake()
    try:
        for params, target in rosparam.load_str(text, "-", default_namespace=ns):
            rosparam.upload_params(target, params)
        results.append(json.dumps(pd.get_param("/")))
    except Exception as e:
        results.append(type(e).__name__)
print(json.dumps(results))
"""

LOAD_CASES = [
    ("a: 1\nb: {c: 2, d: [1, 2]}\n", "/"),
    ("a: 1\n---\n_ns: sub\nb: 2\n", "/ns"),
    ("x: !degrees 90\ny: rad(pi/4)\nz: !radians 2*pi\n", "/"),
    ("e: {}\nf: {g: {}}\nh: 1\n", "/n"),
    ("[1, 2, 3]\n", "/list"),
    ("hello\n", "/s"),
    ("/abs: 1\nrel: {x: 1}\n", "/n"),
    ("a: 1\nb: 2\n---\na: {c: 3}\n", "/"),
    ("k: 'deg(90)'\nl: 1e3\nm: 0x10\nn: yes\no: '2'\n", "/"),
]


@pytest.mark.ros
def test_load_agrees_with_rosparam(ros_python) -> None:  # type: ignore[no-untyped-def]
    theirs = ros_python(LOAD_SCRIPT, as_json=True, stdin=json.dumps(LOAD_CASES))
    for (text, ns), t in zip(LOAD_CASES, theirs):
        p = ParamServer()
        p.load(text, ns)
        assert json.dumps(p.get_param("/")) == t, text


@pytest.mark.ros
def test_dump_agrees_with_rosparam(ros_python) -> None:  # type: ignore[no-untyped-def]
    p = ParamServer()
    p.load("robot:\n  z: 1\n  a: [1, {q: 2.5}]\n  s: 'multi\n\n    line'\n  b: true\n  u: 'é'\n")
    script = r"""
import json, sys, yaml
print(json.dumps(yaml.dump(json.load(sys.stdin))))
"""
    theirs = ros_python(script, as_json=True, stdin=json.dumps(p.get_param("/robot")))
    assert p.dump("/robot") == theirs


def test_to_xmlrpc_names_the_path() -> None:
    with pytest.raises(DdesTypeError, match=r"v/a\[1\]"):
        to_xmlrpc({"a": [1, None]}, "v")


# -- docs/parameters.md: every snippet runs ---------------------------------------------------------------

DOC = Path(__file__).resolve().parents[2] / "docs" / "parameters.md"


def _snippets() -> list[str]:
    import re

    return re.findall(r"```python\n(.*?)```", DOC.read_text(encoding="utf-8"), flags=re.S)


def test_docs_have_snippets() -> None:
    assert len(_snippets()) >= 5


@pytest.mark.parametrize("index", range(len(_snippets())))
def test_docs_snippet_runs(index: int) -> None:
    run_snippet(_snippets()[index], DOC, index)
