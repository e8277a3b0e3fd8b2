"""dynamic_reconfigure core: generator, start-up, clamping, level bitmask, errors, real-DR interop."""

from __future__ import annotations

import json
import math
import random
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ddes.dynamic_reconfigure.core import (
    ALL_LEVELS,
    Config,
    ConfigType,
    ParameterGenerator,
    ReconfigureCore,
    bool_t,
    decode_config,
    double_t,
    encode_config,
    encode_description,
    int_t,
    reconfigure_namespace,
    str_t,
)
from ddes.errors import (
    DdesKeyError,
    DdesTypeError,
    DdesValueError,
    DynamicReconfigureCallbackException,
)


def tutorial_type() -> ConfigType:
    """dynamic_tutorials' Tutorials.cfg, in ddes."""
    gen = ParameterGenerator()
    size = gen.enum([gen.const("Small", int_t, 0, "A small constant"),
                     gen.const("Medium", int_t, 1, "A medium constant"),
                     gen.const("Large", int_t, 2, "A large constant")], "An enum to set size")
    gen.add("int_param", int_t, 1, "An Integer parameter", 50, 0, 100)
    gen.add("double_param", double_t, 2, "A double parameter", 0.5, 0, 1)
    gen.add("str_param", str_t, 4, "A string parameter", "Hello World")
    gen.add("bool_param", bool_t, 8, "A Boolean parameter", True)
    gen.add("size", int_t, 16, "A size parameter which is edited via an enum", 1, 0, 2,
            edit_method=size)
    return gen.generate("dynamic_tutorials", "dynamic_tutorials", "Tutorials")


class Recorder:
    """A callback that records (config, level) and returns the config, optionally edited."""

    def __init__(self, edit: Any = None) -> None:
        self.calls: list[tuple[dict[str, Any], int]] = []
        self.edit = edit

    def __call__(self, config: Config, level: int) -> Any:
        self.calls.append((dict(config), level))
        return self.edit(config) if self.edit else config


# -- the generator -------------------------------------------------------------------------------------


def test_generated_type_has_the_generated_module_tables() -> None:
    t = tutorial_type()
    assert t.name == "TutorialsConfig"
    assert t.names == ["int_param", "double_param", "str_param", "bool_param", "size"]
    assert t.defaults == {"int_param": 50, "double_param": 0.5, "str_param": "Hello World",
                          "bool_param": True, "size": 1}
    assert t.min == {"int_param": 0, "double_param": 0.0, "str_param": "", "bool_param": False,
                     "size": 0}
    assert t.max["bool_param"] is True and t.max["str_param"] == ""
    assert t.level == {"int_param": 1, "double_param": 2, "str_param": 4, "bool_param": 8, "size": 16}
    assert t.all_level == 31
    assert t.constants == {"Small": 0, "Medium": 1, "Large": 2}
    em = eval(t.param("size").edit_method)  # DR's edit_method is a Python repr
    assert [c["name"] for c in em["enum"]] == ["Small", "Medium", "Large"]
    assert em["enum_description"] == "An enum to set size"


def test_unspecified_limits_take_the_type_defaults() -> None:
    gen = ParameterGenerator()
    gen.add("i", int_t, 0, "i")
    gen.add("d", double_t, 0, "d", 1)
    gen.add("s", str_t, 0, "s")
    gen.add("b", bool_t, 0, "b")
    t = gen.generate("p", "n", "X")
    assert t.defaults == {"i": 0, "d": 1.0, "s": "", "b": False}
    assert type(t.defaults["d"]) is float
    assert t.min["i"] == -(2**31) and t.max["i"] == 2**31 - 1
    assert t.min["d"] == -math.inf and t.max["d"] == math.inf


@pytest.mark.parametrize(
    ("args", "kwargs", "error", "match"),
    [
        (("1x", int_t, 0, "d"), {}, DdesValueError, "naming conventions"),
        (("x", "float", 0, "d"), {}, DdesValueError, "unknown type"),
        (("x", str_t, 0, "d"), {"min": "a"}, DdesValueError, "Max or min specified for x"),
        (("x", bool_t, 0, "d"), {"max": True}, DdesValueError, "Max or min specified"),
        (("x", int_t, 0, "d", "5"), {}, DdesTypeError, "'x' has type int, but default is '5'"),
        (("x", int_t, 0, "d", True), {}, DdesTypeError, "has type int"),
        (("x", double_t, 0, "d", 0.0, "a"), {}, DdesTypeError, "min"),
        (("x", int_t, 0, "d", 0, 0, 2**31), {}, DdesValueError, "32-bit"),
        (("x", int_t, -1, "d"), {}, DdesValueError, "level"),
        (("x", int_t, 2**32, "d"), {}, DdesValueError, "level"),
    ],
)
def test_generator_rejects_bad_declarations(args: tuple[Any, ...], kwargs: dict[str, Any],
                                            error: type[Exception], match: str) -> None:
    gen = ParameterGenerator()
    with pytest.raises(error, match=match):
        gen.add(*args, **kwargs)


def test_generator_rejects_duplicates_and_bad_enums() -> None:
    gen = ParameterGenerator()
    gen.add("x", int_t, 0, "d")
    with pytest.raises(DdesValueError, match="twice"):
        gen.add("x", double_t, 0, "d")
    a = gen.const("A", int_t, 0, "a")
    b = gen.const("B", str_t, "b", "b")
    with pytest.raises(DdesValueError, match="Inconsistent types"):
        gen.enum([a, b], "mixed")
    with pytest.raises(DdesValueError, match="quotes"):
        gen.const("C", int_t, 1, "it's")
    with pytest.raises(DdesTypeError):
        gen.const("D", int_t, "1", "d")


# -- the core ----------------------------------------------------------------------------------------------


def test_startup_defaults_overridden_by_params_clamped_then_one_callback() -> None:
    written: dict[str, Any] = {}
    published: list[Config] = []
    server_params = {"int_param": 500, "double_param": 1, "str_param": "from server"}
    cb = Recorder()
    core = ReconfigureCore(tutorial_type(), cb, server_params.__getitem__, written.__setitem__,
                           published.append)
    expected = {"int_param": 100, "double_param": 1.0, "str_param": "from server",
                "bool_param": True, "size": 1}
    assert cb.calls == [(expected, ALL_LEVELS)]
    assert ALL_LEVELS == 0xFFFFFFFF == (~0) & 0xFFFFFFFF  # rospy passes ~0 (-1): the same bits
    assert core.config == expected and type(core.config["double_param"]) is float
    assert written == expected
    assert published == [expected]


def test_update_merges_clamps_and_ors_the_levels_of_changed_params() -> None:
    cb = Recorder()
    core = ReconfigureCore(tutorial_type(), cb)
    new = core.update_configuration({"int_param": 50, "double_param": 7, "size": 2})
    # int_param is unchanged (50): its level does not count; double clamps to 1.0
    assert new["double_param"] == 1.0 and new["size"] == 2
    assert cb.calls[-1][1] == 2 | 16
    core.update_configuration({"double_param": 3.0})  # clamps to 1.0 again: no change
    assert cb.calls[-1][1] == 0
    core.update_configuration({"bool_param": False, "str_param": "x", "int_param": -5})
    assert cb.calls[-1] == ({"int_param": 0, "double_param": 1.0, "str_param": "x",
                             "bool_param": False, "size": 2}, 1 | 4 | 8)
    core.update_configuration({})
    assert cb.calls[-1][1] == 0


def test_the_callbacks_config_becomes_the_config_and_is_written_back() -> None:
    written: dict[str, Any] = {}

    def limit(config: Config) -> Config:
        if config.int_param > 10:
            config.int_param = 10
            config.str_param = "limited"
        return config

    core = ReconfigureCore(tutorial_type(), Recorder(limit), param_set=written.__setitem__)
    assert core.config.int_param == 10 and written["str_param"] == "limited"
    out = core.update_configuration({"int_param": 3})
    assert out.int_param == 3 and written["int_param"] == 3


def test_callback_returning_none_raises_and_keeps_the_config() -> None:
    answers: list[Any] = []

    def cb(config: Config, level: int) -> Any:
        return answers.pop(0) if answers else config

    core = ReconfigureCore(tutorial_type(), cb)
    answers.append(None)
    with pytest.raises(DynamicReconfigureCallbackException, match="should return"):
        core.update_configuration({"int_param": 1})
    assert core.config.int_param == 50
    assert core.update_configuration({"int_param": 2}).int_param == 2
    with pytest.raises(DynamicReconfigureCallbackException):
        ReconfigureCore(tutorial_type(), lambda c, level: None)


def test_callback_must_return_a_full_config() -> None:
    with pytest.raises(DdesKeyError, match="size"):
        ReconfigureCore(tutorial_type(), lambda c, level: {k: v for k, v in c.items() if k != "size"})
    with pytest.raises(DdesTypeError, match="return the"):
        ReconfigureCore(tutorial_type(), lambda c, level: 5)
    with pytest.raises(DdesTypeError, match="int_param"):
        ReconfigureCore(tutorial_type(), lambda c, level: dict(c, int_param="many"))


@pytest.mark.parametrize(
    ("changes", "error", "match"),
    [
        ({"int_param": "10"}, DdesTypeError, "int_param"),
        ({"int_param": 1.5}, DdesTypeError, "int_param"),
        ({"int_param": True}, DdesTypeError, "int_param"),
        ({"double_param": "0.1"}, DdesTypeError, "double_param"),
        ({"bool_param": 1}, DdesTypeError, "bool_param"),
        ({"str_param": 3}, DdesTypeError, "str_param"),
        ({"speed": 1}, DdesKeyError, "speed"),
    ],
)
def test_bad_updates_raise_typed_errors_naming_the_parameter(
        changes: dict[str, Any], error: type[Exception], match: str) -> None:
    cb = Recorder()
    core = ReconfigureCore(tutorial_type(), cb)
    with pytest.raises(error, match=match):
        core.update_configuration(changes)
    assert len(cb.calls) == 1 and core.config == tutorial_type().defaults


def test_bad_parameter_server_values_raise_at_startup() -> None:
    with pytest.raises(DdesTypeError, match="parameter server value of parameter 'bool_param'"):
        ReconfigureCore(tutorial_type(), Recorder(), {"bool_param": "yes"}.__getitem__)
    with pytest.raises(DdesTypeError):
        ReconfigureCore("not a type", Recorder())  # type: ignore[arg-type]
    with pytest.raises(DdesTypeError):
        ReconfigureCore(tutorial_type(), "not callable")  # type: ignore[arg-type]
    with pytest.raises(DdesTypeError):
        ReconfigureCore(tutorial_type(), Recorder()).update_configuration([("a", 1)])  # type: ignore[arg-type]


def test_config_attribute_access() -> None:
    c = Config(a=1)
    c.b = 2
    assert c == {"a": 1, "b": 2} and c.a == 1
    assert isinstance(c.copy(), Config)
    with pytest.raises(AttributeError):
        _ = c.missing


# -- message shapes ----------------------------------------------------------------------------------------


def test_encode_decode_config_and_set_parameters() -> None:
    t = tutorial_type()
    core = ReconfigureCore(t, Recorder())
    msg = encode_config(core.config, t)
    assert msg == {
        "bools": [("bool_param", True)],
        "ints": [("int_param", 50), ("size", 1)],
        "strs": [("str_param", "Hello World")],
        "doubles": [("double_param", 0.5)],
        "groups": [("Default", True, 0, 0)],
    }
    assert decode_config(msg) == core.config

    class P:
        def __init__(self, name: str, value: Any) -> None:
            self.name, self.value = name, value

    class Msg:
        bools: list[Any] = []
        ints = [P("int_param", 70)]
        strs: list[Any] = []
        doubles = [P("double_param", 2.0)]

    reply = core.set_parameters(Msg())
    assert dict(reply["ints"]) == {"int_param": 70, "size": 1}
    assert dict(reply["doubles"]) == {"double_param": 1.0}
    reply = core.set_parameters({"ints": [{"name": "size", "value": 0}]})
    assert dict(reply["ints"])["size"] == 0
    with pytest.raises(DdesTypeError):
        decode_config({"ints": [3]})


def test_encode_description() -> None:
    d = encode_description(tutorial_type())
    (group,) = d["groups"]
    assert (group["name"], group["type"], group["id"], group["parent"]) == ("Default", "", 0, 0)
    assert group["parameters"][0] == {"name": "int_param", "type": "int", "level": 1,
                                      "description": "An Integer parameter", "edit_method": ""}
    assert d["max"]["ints"] == [("int_param", 100), ("size", 2)]
    assert d["min"]["doubles"] == [("double_param", 0.0)]
    assert d["dflt"]["strs"] == [("str_param", "Hello World")]
    assert d["dflt"]["groups"] == []
    assert ReconfigureCore(tutorial_type(), Recorder()).description() == d


def test_reconfigure_namespace_like_the_server() -> None:
    assert reconfigure_namespace("") == "~"
    assert reconfigure_namespace("pid") == "~pid/"
    assert reconfigure_namespace("/abs/") == "/abs/"
    assert reconfigure_namespace("~x") == "~x/"


# -- property: a model of merge, clamp and level -------------------------------------------------------------

updates = st.lists(st.fixed_dictionaries({}, optional={
    "int_param": st.integers(-200, 200),
    "double_param": st.floats(-3, 3, allow_nan=False),
    "str_param": st.sampled_from(["a", "b"]),
    "bool_param": st.booleans(),
    "size": st.integers(-1, 3),
}), max_size=8)


@given(updates)
def test_updates_match_a_model(changes_list: list[dict[str, Any]]) -> None:
    t = tutorial_type()
    cb = Recorder()
    core = ReconfigureCore(t, cb)
    model = dict(t.defaults)
    for changes in changes_list:
        merged = dict(model)
        for k, v in changes.items():
            lo, hi = t.min[k], t.max[k]
            merged[k] = min(max(v, lo), hi) if t.type[k] in (int_t, double_t) else v
        level = 0
        for k in t.names:
            if merged[k] != model[k]:
                level |= t.level[k]
        model = merged
        assert core.update_configuration(changes) == model
        assert cb.calls[-1] == (model, level)
    assert len(cb.calls) == 1 + len(changes_list)


# -- against the real dynamic_reconfigure Server (rospy patched: no master needed) --------------------------

PREAMBLE = r"""
import json, sys
import rospy
from dynamic_reconfigure.encoding import extract_params
from dynamic_reconfigure.cfg import TestConfig as T
"""

DESCRIBE_SCRIPT = PREAMBLE + r"""
from dynamic_reconfigure.encoding import encode_description
d = encode_description(T)
pairs = lambda c: {s: [[p.name, p.value] for p in getattr(c, s)] for s in ("bools", "ints", "strs", "doubles")}
print(json.dumps({
    "params": [{k: p[k] for k in ("name", "type", "level", "description", "default", "min", "max",
                                  "edit_method")} for p in extract_params(T.config_description)],
    "described": [[p.name, p.type, p.level, p.description, p.edit_method] for g in d.groups for p in g.parameters],
    "max": pairs(d.max), "min": pairs(d.min), "dflt": pairs(d.dflt)}))
"""

SERVER_SCRIPT = PREAMBLE + r"""
class Pub:
    def __init__(self, *a, **k): pass
    def publish(self, msg): pass
params = {}
def get_param(name):
    if name in params:
        return params[name]
    raise KeyError(name)
rospy.Publisher = Pub
rospy.Service = Pub
rospy.get_param = get_param
rospy.set_param = params.__setitem__
rospy.logerr = lambda *a: None
from dynamic_reconfigure.server import Server
names = [p["name"] for p in extract_params(T.config_description)]

out = []
for case in json.load(sys.stdin):
    params.clear()
    params.update({"~" + k: v for k, v in case["initial"].items()})
    calls = []
    def cb(config, level):
        calls.append([{k: config[k] for k in names}, level & 0xFFFFFFFF])
        if config["int_"] == 7:
            config["str_"] = "seven"
        if config["str_"] == "none":
            return None
        return config
    steps = []
    try:
        s = Server(T, cb)
        for changes in case["updates"]:
            s.update_configuration(changes)
            steps.append({k: s.config[k] for k in names})
    except Exception as e:
        steps.append(type(e).__name__)
    out.append({"calls": calls, "steps": steps, "params": {k[1:]: v for k, v in params.items()}})
print(json.dumps(out))
"""


def type_from_description(params: list[dict[str, Any]]) -> ConfigType:
    gen = ParameterGenerator()
    for p in params:
        numeric = p["type"] in (int_t, double_t)
        gen.add(p["name"], p["type"], p["level"], p["description"], p["default"],
                p["min"] if numeric else None, p["max"] if numeric else None, p["edit_method"])
    return gen.generate("dynamic_reconfigure", "test", "Test")


def random_cases(t: ConfigType, seed: int, n: int) -> list[dict[str, Any]]:
    rng = random.Random(seed)

    def value(name: str) -> Any:
        kind = t.type[name]
        if kind == int_t:
            return rng.choice([rng.randint(-15, 15), 7])
        if kind == double_t:
            return rng.choice([round(rng.uniform(-15, 15), 3), rng.randint(-3, 12)])
        if kind == str_t:
            return rng.choice(["a", "b", "none", "foo"]) if rng.random() < 0.3 else "x"
        return rng.random() < 0.5

    cases = []
    for _ in range(n):
        initial = {k: value(k) for k in rng.sample(t.names, rng.randint(0, 4))}
        upd = [{k: value(k) for k in rng.sample(t.names, rng.randint(0, 3))}
               for _ in range(rng.randint(1, 6))]
        cases.append({"initial": initial, "updates": upd})
    return cases


def run_on_ddes(t: ConfigType, case: dict[str, Any]) -> dict[str, Any]:
    params: dict[str, Any] = dict(case["initial"])
    calls: list[Any] = []

    def cb(config: Config, level: int) -> Any:
        calls.append([dict(config), level])
        if config["int_"] == 7:
            config["str_"] = "seven"
        return None if config["str_"] == "none" else config

    steps: list[Any] = []
    try:
        core = ReconfigureCore(t, cb, params.__getitem__, params.__setitem__)
        for changes in case["updates"]:
            steps.append(dict(core.update_configuration(changes)))
    except DynamicReconfigureCallbackException as e:
        steps.append(type(e).__name__)
    return {"calls": calls, "steps": steps, "params": params}


@pytest.mark.ros
def test_agrees_with_the_real_server(ros_python) -> None:  # type: ignore[no-untyped-def]
    described = ros_python(DESCRIBE_SCRIPT, as_json=True)
    t = type_from_description(described["params"])
    ours = encode_description(t)
    assert [[p["name"], p["type"], p["level"], p["description"], p["edit_method"]]
            for p in ours["groups"][0]["parameters"]] == described["described"]
    for section in ("max", "min", "dflt"):
        for kind in ("bools", "ints", "strs", "doubles"):
            assert [list(x) for x in ours[section][kind]] == described[section][kind], (section, kind)

    cases = random_cases(t, seed=11, n=150)
    theirs = ros_python(SERVER_SCRIPT, as_json=True, stdin=json.dumps(cases))
    assert len(theirs) == len(cases)
    for case, th in zip(cases, theirs):
        mine = json.loads(json.dumps(run_on_ddes(t, case)))
        assert mine == th, case
