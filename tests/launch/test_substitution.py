"""Substitution args: $(arg), $(env), $(optenv), $(anon), $(dirname), $(find), $(eval)."""

from __future__ import annotations

import math
import os
import random
import string
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ddes.errors import ROSLaunchException
from ddes.launch import SubstitutionContext, resolve_args
from ddes.rospack import RosPack

from .workspace import CountingRandom, Workspace


def ctx(ws: Workspace | None = None, *, filename: str | None = "/w/launch/x.launch",
        anon: random.Random | None = None, **args: str) -> SubstitutionContext:
    rospack = ws.rospack if ws is not None else RosPack([], use_env=False, bundled=False)
    return SubstitutionContext(rospack, {"HOME_X": "/home/x", "EMPTY": ""},
                               anon or CountingRandom(), filename, dict(args))


def test_text_without_dollar_is_returned_unchanged() -> None:
    assert resolve_args("plain (text)", ctx()) == "plain (text)"
    assert resolve_args("", ctx()) == ""


@given(st.text(alphabet=string.printable.replace("$", ""), max_size=40))
def test_no_dollar_means_no_change(text: str) -> None:
    assert resolve_args(text, ctx()) == text


@given(st.dictionaries(st.from_regex(r"[a-z][a-z0-9_]{0,6}", fullmatch=True),
                       st.text(alphabet=string.ascii_letters + "/ .", max_size=8),
                       min_size=1, max_size=4))
def test_arg_values_are_spliced_in(args: dict[str, str]) -> None:
    text = "|".join(f"$(arg {k})" for k in args)
    c = SubstitutionContext(RosPack([], use_env=False, bundled=False), {}, CountingRandom(),
                            None, dict(args))
    assert resolve_args(text, c) == "|".join(args.values())


def test_multiple_and_repeated_substitutions() -> None:
    c = ctx(robot="r1", n="3")
    assert resolve_args("$(arg robot)/$(arg robot)_$(arg n) $(env HOME_X)", c) == "r1/r1_3 /home/x"
    assert resolve_args("$(arg  robot)", c) == "r1"  # extra spaces between words are ignored


def test_env_and_optenv() -> None:
    c = ctx()
    assert resolve_args("$(env EMPTY)x", c) == "x"
    assert resolve_args("$(optenv NOPE)", c) == ""
    assert resolve_args("$(optenv NOPE a   b)", c) == "a b"  # default words joined by one space
    assert resolve_args("$(optenv HOME_X fallback)", c) == "/home/x"
    with pytest.raises(ROSLaunchException, match="environment variable 'NOPE' is not set"):
        resolve_args("$(env NOPE)", c)
    with pytest.raises(ROSLaunchException, match=r"only accepts one argument \[env A B\]"):
        resolve_args("$(env A B)", c)


def test_anon_is_deterministic_and_stable_within_a_scope() -> None:
    a = ctx(anon=random.Random(7))
    b = ctx(anon=random.Random(7))
    first = resolve_args("$(anon talker)", a)
    assert first == resolve_args("$(anon talker)", b)  # same seed, same name
    assert first.startswith("talker_") and first[len("talker_"):].isdigit()
    assert resolve_args("$(anon talker) $(anon talker)", a) == f"{first} {first}"
    assert resolve_args("$(anon other)", a) != first
    assert resolve_args("$(anon talker)", ctx(anon=random.Random(8))) != first


def test_anon_scoping_follows_roslaunch() -> None:
    parent = ctx()
    early = resolve_args("$(anon a)", parent)
    child = parent.child()
    assert resolve_args("$(anon a)", child) == early          # inherited
    made_in_child = resolve_args("$(anon b)", child)
    assert resolve_args("$(anon b)", parent) != made_in_child  # not leaked back


def test_dirname() -> None:
    assert resolve_args("$(dirname)/cfg.yaml", ctx()) == os.path.abspath("/w/launch") + "/cfg.yaml"
    with pytest.raises(ROSLaunchException, match=r"Cannot substitute \$\(dirname\)"):
        resolve_args("$(dirname)", ctx(filename=None))


def test_find_joins_the_following_path(ws: Workspace) -> None:
    pkg = ws.package("my_pkg")
    c = ctx(ws)
    assert resolve_args("$(find my_pkg)", c) == str(pkg)
    assert resolve_args("$(find my_pkg)/launch/a.launch x", c) == f"{pkg}/launch/a.launch x"
    assert resolve_args("$(find my_pkg)cfg", c) == f"{pkg}/cfg"  # os.path.join, as roslaunch
    # $(find) runs after $(arg), so an arg value may name the package path
    assert resolve_args("$(arg p)/x", ctx(ws, p="$(find my_pkg)")) == f"{pkg}/x"
    with pytest.raises(ROSLaunchException, match="package 'nope' not found"):
        resolve_args("$(find nope)", c)


def test_unknown_and_malformed_substitutions() -> None:
    c = ctx(x="1")
    with pytest.raises(ROSLaunchException, match=r"Unknown substitution command \[foo x\]"):
        resolve_args("$(foo x)", c)
    with pytest.raises(ROSLaunchException, match="must be the whole attribute value"):
        resolve_args("a $(eval 1)", c)
    with pytest.raises(ROSLaunchException, match="Dollar signs '\\$' cannot be inside"):
        resolve_args("$(find $(arg x))", c)
    with pytest.raises(ROSLaunchException, match="Invalid left parenthesis"):
        resolve_args("$(arg (x)", c)
    with pytest.raises(ROSLaunchException, match=r"\$\(arg var\) must specify a variable name"):
        resolve_args("$(arg)", c)
    with pytest.raises(ROSLaunchException, match=r"may only specify one arg \[arg x y\]"):
        resolve_args("$(arg x y)", c)
    with pytest.raises(ROSLaunchException, match=r"\$\(anon var\) must specify a name"):
        resolve_args("$(anon)", c)


def test_text_that_only_looks_like_substitution_is_kept() -> None:
    c = ctx(x="1")
    assert resolve_args("$ (x) $() $$(arg x) $(unclosed", c) == "$ (x) $() $1 $(unclosed"


def test_missing_arg_message() -> None:
    with pytest.raises(ROSLaunchException, match="arg 'robot' is not defined.*robot:=VALUE"):
        resolve_args("$(arg robot)", ctx())


@pytest.mark.parametrize(("expr", "expected"), [
    ("1 + 2", "3"),
    ("arg('n') * 2", "6"),          # args are converted like type="auto"
    ("n * 2", "6"),                 # bare names are args too
    ("f / 2", "1.25"),
    ("b and true", "True"),
    ("s + '_x'", "robot_x"),
    ("sqrt(16)", "4.0"),            # math module names
    ("pi", str(math.pi)),
    ("len(s)", "5"),
    ("max(n, 7)", "7"),
    ("optenv('NOPE', 'd')", "d"),
    ("env('HOME_X')", "/home/x"),
    ("'yes' if n > 2 else 'no'", "yes"),
    ("[n, f]", "[3, 2.5]"),
    ("dirname()", os.path.abspath("/w/launch")),
    ("e", str(math.e)),             # math shadows an arg called e, as in roslaunch
])
def test_eval(expr: str, expected: str) -> None:
    c = ctx(n="3", f="2.5", b="true", s="robot", e="arg value")
    assert resolve_args(f"$(eval {expr})", c) == expected


def test_eval_anon_shares_the_scope_names() -> None:
    c = ctx()
    name = resolve_args("$(anon w)", c)
    assert resolve_args("$(eval anon('w'))", c) == name


@pytest.mark.parametrize(("expr", "message"), [
    ("__import__('os')", "may not contain double underscore"),
    ("open('/etc/passwd')", "NameError: name 'open' is not defined"),
    ("nope + 1", "NameError: name 'nope' is not defined"),
    ("arg('nope')", "arg 'nope' is not defined"),
    ("1 +", "SyntaxError"),
    ("1 / 0", "ZeroDivisionError"),
])
def test_eval_errors(expr: str, message: str) -> None:
    with pytest.raises(ROSLaunchException, match=message):
        resolve_args(f"$(eval {expr})", ctx())


def test_eval_find(ws: Workspace) -> None:
    pkg = ws.package("p1")
    assert resolve_args("$(eval find('p1') + '/x')", ctx(ws)) == f"{pkg}/x"


def test_child_context_copies_args(tmp_path: Path) -> None:
    parent = ctx(a="1")
    child = parent.child()
    child.args["b"] = "2"
    child.args["a"] = "changed"
    assert parent.args == {"a": "1"}
