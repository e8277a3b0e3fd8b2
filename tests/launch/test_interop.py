"""ddes's launch plans against real roslaunch (Noetic, system Python).

The same files are loaded by ``roslaunch.xmlloader.XmlLoader`` into a
``ROSLaunchConfig`` (no roscore.xml, no master contacted) and by
:func:`ddes.launch.load_launch`; parameters (names, values and order),
nodes (package, type, name, namespace, args, remappings, env, flags),
clear_params, rosparam delete/dump commands, the files read and the
SUMMARY print-out must agree.  ``rosgraph.names.anonymous_name`` is
replaced by a counter on the ROS side, and ddes gets a counting generator,
so ``$(anon)`` names (and their scoping) are compared too.
"""

from __future__ import annotations

import json
import random
import string
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ddes.errors import ROSLaunchException
from ddes.launch import SubstitutionContext, resolve_args

from .scenario import CASES, build
from .workspace import CountingRandom, Workspace, plan_as_json

ROS_LOAD = r"""
import base64, json, os, shlex, sys
data = json.load(sys.stdin)
os.environ["ROS_PACKAGE_PATH"] = data["rpp"]
os.environ["ROS_MASTER_URI"] = "http://localhost:1"  # never contacted
os.environ["ROS_HOME"] = data["home"]
os.environ.pop("ROS_NAMESPACE", None)
os.environ.update(data["env"])
import rosgraph.names
counter = [0]
def _anon(id):
    counter[0] += 1
    return "%s_%d" % (id, counter[0] - 1)
rosgraph.names.anonymous_name = _anon
import roslaunch.config, roslaunch.xmlloader
from xmlrpc.client import Binary

def enc(v):
    if isinstance(v, Binary):
        return {"__bin__": base64.b64encode(v.data).decode()}
    if isinstance(v, dict):
        return {k: enc(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [enc(x) for x in v]
    return v

def canon(name):
    return rosgraph.names.canonicalize_name(name)

out = []
real_stdout = sys.stdout
sys.stdout = sys.stderr
for case in data["cases"]:
    counter[0] = 0
    cfg = roslaunch.config.ROSLaunchConfig()
    loader = roslaunch.xmlloader.XmlLoader()
    loader.ignore_unset_args = False
    try:
        if "text" in case:
            loader.load_string(case["text"], cfg, verbose=False)
        else:
            loader.load(case["file"], cfg, argv=case["argv"], verbose=False)
    except Exception as e:
        out.append({"error": "%s: %s" % (type(e).__name__, e)})
        continue
    summary = cfg.summary().lstrip("\n").replace("\n\nMACHINES\n", "")
    out.append({
        "params": [[k, enc(p.value)] for k, p in cfg.params.items()],
        "nodes": [{"pkg": n.package, "type": n.type, "name": n.name, "namespace": n.namespace,
                   "args": shlex.split(n.args), "remaps": [list(r) for r in n.remap_args],
                   "env": [list(e) for e in n.env_args], "output": n.output,
                   "respawn": n.respawn, "respawn_delay": n.respawn_delay,
                   "required": n.required, "cwd": n.cwd} for n in cfg.nodes],
        "clear": cfg.clear_params,
        "commands": [[e.args[0], canon(e.args[-1])] + list(e.args[1:-1]) for e in cfg.executables],
        "files": cfg.roslaunch_files,
        "summary": summary,
    })
sys.stdout = real_stdout
print(json.dumps(out))
"""


def run_roslaunch(ros_python: Any, ws: Workspace, cases: list[dict[str, Any]]) -> list[Any]:
    """Load each case ({"file", "argv"} or {"text"}) with real roslaunch."""
    home = ws.root / "ros_home"
    home.mkdir(exist_ok=True)
    payload = {"rpp": str(ws.src), "home": str(home), "env": ws.environ, "cases": cases}
    return ros_python(ROS_LOAD, as_json=True, stdin=json.dumps(payload))  # type: ignore[no-any-return]


def ddes_json(ws: Workspace, source: str | Path, args: dict[str, str]) -> dict[str, Any]:
    plan = ws.load(source, CountingRandom(), **args)
    return json.loads(json.dumps(plan_as_json(plan)))  # type: ignore[no-any-return]


@pytest.mark.ros
def test_demo_package_matches_roslaunch(ros_python, ws: Workspace) -> None:  # type: ignore[no-untyped-def]
    build(ws)
    launch = ws.src / "demo_pkg" / "launch"
    cases = [{"file": str(launch / f), "argv": [f"{k}:={v}" for k, v in a.items()]}
             for f, a in CASES]
    theirs = run_roslaunch(ros_python, ws, cases)
    for (f, a), their in zip(CASES, theirs):
        ours = ddes_json(ws, launch / f, a)
        assert "error" not in their, (f, a, their)
        for key in ("params", "nodes", "clear", "commands", "files", "summary"):
            assert ours[key] == their[key], (f, a, key)


# -- errors: inputs roslaunch rejects too ---------------------------------------------------

REJECTED_BY_BOTH = [
    '<arg name="x" value="1" default="2"/>',
    '<arg name="x" default="1"/><arg name="x" default="2"/>',
    '<arg name="x" value="1"/><group><arg name="x" value="2"/></group>',
    '<param name="a" value="$(arg nope)"/>',
    '<arg name="x"/><param name="a" value="$(arg x)"/>',
    '<group><arg name="inner" default="1"/></group><param name="a" value="$(arg inner)"/>',
    '<param name="a" value="$(foo x)"/>',
    '<param name="a" value="$(eval 1) x"/>',
    '<param name="a" value="$(find $(arg x))"/>',
    '<param name="a" value="$(eval __import__)"/>',
    '<param name="a" value="$(env DDES_SURELY_UNSET_42)"/>',
    '<param name="a" value="$(arg a b)"/>',
    '<param name="a" value="$(anon)"/>',
    '<param name="a" value="x" if="maybe"/>',
    '<param name="a" value="x" if="1" unless="0"/>',
    '<group if="yes"/>',
    '<param name="a" type="int" value="1.5"/>',
    '<param name="a" type="double" value="x"/>',
    '<param name="a" type="bool" value="yes"/>',
    '<param name="a" type="float" value="1"/>',
    '<param name="a" value="1" textfile="/nonexistent/x"/>',
    '<param value="1"/>',
    '<rosparam>5</rosparam>',
    '<rosparam>a: [</rosparam>',
    '<rosparam command="bogus">a: 1</rosparam>',
    '<rosparam command="delete" file="x.yaml" param="a"/>',
    '<rosparam command="load" file="/nonexistent/x.yaml"/>',
    '<rosparam param="/">5</rosparam>',
    '<rosparam subst_value="yes">a: 1</rosparam>',
    '<remap from="a" to=""/>',
    '<remap from="a b" to="c"/>',
    '<remap from="a"/>',
    '<env name="" value="x"/>',
    '<group clear_params="true"/>',
    '<group ns=""/>',
    '<node pkg="p" type="t"/>',
    '<node pkg="p" name="n"/>',
    '<node pkg="p" type="t" name="a/b"/>',
    '<node pkg="p" type="t" name="n"/><node pkg="p" type="t" name="n"/>',
    '<node pkg="p" type="t" name="n" respawn="true" required="true"/>',
    '<node pkg="p" type="t" name="n" respawn="yes"/>',
    '<node pkg="p" type="t" name="n" respawn_delay="soon"/>',
    '<node pkg="p" type="t" name="n" output="file"/>',
    '<node pkg="p" type="t" name="n" cwd="here"/>',
    '<node pkg="" type="t" name="n"/>',
    '<node pkg="p" type="t" name="n" ns=""/>',
    '<test pkg="p" type="t" test-name="x" respawn="true"/>',
    '<test pkg="p" type="t" test-name="x" time-limit="-1"/>',
    '<include file="/nonexistent/x.launch"/>',
    '<include file="INC"><arg name="unused" value="1"/></include>',
    '<include file="INC"><arg name="declared_only"/></include>',
    '<include file="INC_NEEDS"/>',
    '<include file="INC" pass_all_args="maybe"/>',
    '<param name="a" value="$(eval 1 +)"/>',
    '<param name="a" value="$(eval undefined_name)"/>',
    '<param name="a" value="$(eval arg(\'nope\'))"/>',
]


@pytest.mark.ros
def test_roslaunch_rejects_the_same_inputs(ros_python, ws: Workspace) -> None:  # type: ignore[no-untyped-def]
    inc = ws.write("inc.launch", "<launch><param name='i' value='1'/></launch>")
    needs = ws.write("needs.launch", "<launch><arg name='n'/><param name='i' value='$(arg n)'/>"
                                     "</launch>")
    files = []
    for i, body in enumerate(REJECTED_BY_BOTH):
        body = body.replace("INC_NEEDS", str(needs)).replace("INC", str(inc))
        files.append(ws.write(f"bad{i}.launch", f"<launch>{body}</launch>"))
    theirs = run_roslaunch(ros_python, ws, [{"file": str(f), "argv": []} for f in files])
    for body, f, their in zip(REJECTED_BY_BOTH, files, theirs):
        assert "error" in their, f"roslaunch accepted {body}"
        with pytest.raises(ROSLaunchException):
            ws.load(f)


# -- substitution args on random text ---------------------------------------------------------

_TOKENS = ["$(", "$", "(", ")", "arg a", "arg b", "arg  a", "optenv DDES_SURELY_UNSET_42 d e",
           "env DDES_TEST_VAR", "anon n", "anon m", " ", "x", "/", "$(arg a)", "$(anon n)",
           "$(optenv DDES_TEST_VAR)", "dirname", "$(dirname)"]
_EVALS = ["a + 1", "b * 2", "arg('a') == 5", "anon('n')", "optenv('DDES_TEST_VAR')",
          "env('DDES_TEST_VAR') + 'x'", "sqrt(a)", "true and b", "len(str(a))", "[a, b]",
          "dict(x=a)", "max(a, b)", "round(pi, 3)", "nope", "a +", "'s' * 3", "a / 0",
          "arg('missing')", "1 if b else 2"]

ROS_SUBST = r"""
import json, os, sys
data = json.load(sys.stdin)
os.environ.pop("DDES_SURELY_UNSET_42", None)
os.environ.update(data["env"])
import rosgraph.names
counter = [0]
def _anon(id):
    counter[0] += 1
    return "%s_%d" % (id, counter[0] - 1)
rosgraph.names.anonymous_name = _anon
from roslaunch.substitution_args import resolve_args
out = []
for text in data["texts"]:
    counter[0] = 0
    ctx = {"arg": {"a": "5", "b": "2.5"}, "filename": data["filename"]}
    try:
        out.append(resolve_args(text, context=ctx))
    except Exception as e:
        out.append("ERROR")
print(json.dumps(out))
"""

text_strategy = st.one_of(
    st.lists(st.sampled_from(_TOKENS), max_size=8).map("".join),
    st.sampled_from(_EVALS).map(lambda e: f"$(eval {e})"),
    st.text(alphabet=string.ascii_letters + "$() ", max_size=12),
)


@pytest.mark.ros
@settings(max_examples=3, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow,
                                 HealthCheck.data_too_large])
@given(st.lists(text_strategy, min_size=120, max_size=120))
def test_substitutions_match_roslaunch(ros_python, tmp_path: Path,  # type: ignore[no-untyped-def]
                                       texts: list[str]) -> None:
    filename = str(tmp_path / "x.launch")
    env = {"DDES_TEST_VAR": "hello"}
    theirs = ros_python(ROS_SUBST, as_json=True,
                        stdin=json.dumps({"texts": texts, "env": env, "filename": filename}))
    ours = []
    for text in texts:
        ctx = SubstitutionContext(rospack=_NoPackages(), environ=env,
                                  anon_source=CountingRandom(), filename=filename,
                                  args={"a": "5", "b": "2.5"})
        try:
            ours.append(resolve_args(text, ctx))
        except ROSLaunchException:
            ours.append("ERROR")
    assert ours == theirs


class _NoPackages:
    def get_path(self, name: str) -> Path:
        raise AssertionError("no $(find) in these texts")


# -- random launch trees ----------------------------------------------------------------------

_NAMES = ["a", "b", "c", "ns1", "x/y", "~p", "/g", "q"]


def _random_launch(rng: random.Random, depth: int = 0) -> str:
    """A random well-formed launch body with groups, params, remaps, nodes and rosparams."""
    parts = []
    for _ in range(rng.randint(1, 5)):
        kind = rng.choice(["param", "param", "remap", "node", "group", "rosparam", "arg"])
        name = rng.choice(_NAMES)
        if kind == "param":
            value = rng.choice(["1", "2.5", "true", "text", "1_0", "$(arg v)", "$(eval v * 2)"])
            parts.append(f'<param name="{name}" value="{value}"/>')
        elif kind == "remap":
            parts.append(f'<remap from="{name.lstrip("~")}" to="{rng.choice(_NAMES)}"/>')
        elif kind == "node":
            body = "".join(
                rng.choice([f'<param name="{rng.choice(_NAMES)}" value="{rng.randint(0, 9)}"/>',
                            f'<remap from="{rng.choice(["a", "b", "/g"])}" to="z"/>',
                            '<rosparam>{k: [1, 2], m: {n: 3}}</rosparam>',
                            '<env name="E" value="v"/>'])
                for _ in range(rng.randint(0, 3)))
            node_ns = rng.choice(["", ' ns="sub"', ' ns="/abs"'])
            parts.append(f'<node pkg="p" type="t" name="$(anon n)"{node_ns}>{body}</node>')
        elif kind == "group" and depth < 3:
            ns = rng.choice(["", ' ns="g1"', ' ns="/top"', ' ns="g2/g3"'])
            cond = rng.choice(["", ' if="$(arg flag)"', ' unless="$(arg flag)"'])
            parts.append(f"<group{ns}{cond}>{_random_launch(rng, depth + 1)}</group>")
        elif kind == "rosparam":
            p = rng.choice(["", f' param="{name.lstrip("~")}"', ' ns="r"'])
            parts.append(f"<rosparam{p}>{{a: 1, b: {{c: [x, y]}}, d: deg(90)}}</rosparam>")
        elif kind == "arg":
            parts.append(f'<arg name="a{rng.randint(0, 10**6)}" default="{rng.randint(0, 9)}"/>')
    return "".join(parts)


@pytest.mark.ros
@pytest.mark.parametrize("seed", [1, 2])
def test_random_launch_trees_match_roslaunch(ros_python, ws: Workspace,  # type: ignore[no-untyped-def]
                                             seed: int) -> None:
    rng = random.Random(seed)
    files = []
    for i in range(40):
        body = _random_launch(rng)
        head = '<arg name="v" default="3"/><arg name="flag" default="true"/>'
        files.append(ws.write(f"rand{i}.launch", f"<launch>{head}{body}</launch>"))
    flags = [rng.choice(["true", "false"]) for _ in files]
    theirs = run_roslaunch(ros_python, ws, [{"file": str(f), "argv": [f"flag:={fl}"]}
                                            for f, fl in zip(files, flags)])
    for f, fl, their in zip(files, flags, theirs):
        if "error" in their:
            with pytest.raises(ROSLaunchException):
                ws.load(f, CountingRandom(), flag=fl)
            continue
        ours = ddes_json(ws, f, {"flag": fl})
        for key in ("params", "nodes", "summary"):
            assert ours[key] == their[key], (f.read_text(), key)


ROS_RESOLVE = r"""
import json, os, sys
data = json.load(sys.stdin)
os.environ["ROS_PACKAGE_PATH"] = data["rpp"]
os.environ["ROS_HOME"] = data["home"]
import rosgraph.names
from roslaunch.rlutil import resolve_launch_arguments
out = []
for argv in data["argvs"]:
    try:
        files = resolve_launch_arguments(argv)
        out.append([files[0], rosgraph.names.load_mappings(argv)])
    except Exception as e:
        out.append("ERROR")
print(json.dumps(out))
"""


@pytest.mark.ros
def test_command_line_forms_match_roslaunch(ros_python, ws: Workspace) -> None:  # type: ignore[no-untyped-def]
    from ddes.launch import resolve_launch_args

    build(ws)
    ws.write("src/demo_pkg/other/twice.launch", "<launch/>")
    ws.write("src/demo_pkg/more/twice.launch", "<launch/>")
    main = str(ws.src / "demo_pkg" / "launch" / "main.launch")
    argvs = [["demo_pkg", "main.launch"], ["demo_pkg", "sub.launch", "who:=x", "_p:=1"],
             [main, "robot:=r2", "__ns:=/n"], ["demo_pkg", "twice.launch"],
             ["demo_pkg", "nope.launch"], ["no_such_pkg", "main.launch"], ["/nonexistent"]]
    home = ws.root / "ros_home"
    home.mkdir(exist_ok=True)
    theirs = ros_python(ROS_RESOLVE, as_json=True, stdin=json.dumps(
        {"rpp": str(ws.src), "home": str(home), "argvs": argvs}))
    assert [t == "ERROR" for t in theirs] == [False, False, False, True, True, True, True]
    for argv, their in zip(argvs, theirs):
        try:
            path, args = resolve_launch_args(argv, ws.rospack)
        except ROSLaunchException:
            assert their == "ERROR", argv
        else:
            assert [path, args] == their, argv
