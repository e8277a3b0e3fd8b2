"""``rosparam``: get, set, list, load, dump, delete; formats against real rosparam."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
import yaml

from ddes.console.rosparam import dump_text, get_text, pretty_text
from ddes.console.shell import Console


def test_fresh_core_parameters(console: Console) -> None:
    assert console.run("rosparam list") == "/rosdistro\n/rosversion\n/run_id\n"
    assert console.run("rosparam get /rosdistro") == "'noetic\n\n  '\n\n"
    run_id = console.run("rosparam get run_id").strip()
    assert len(run_id) == 36 and run_id == Console(seed=0).run("rosparam get /run_id").strip()
    assert run_id != Console(seed=1).run("rosparam get /run_id").strip()


def test_set_get_scalars_and_dicts(console: Console) -> None:
    console.run("rosparam set /a 5")
    console.run("rosparam set b -2.5")
    console.run("rosparam set /s ''")
    console.run("rosparam set /gains '{P: 1.0, I: 0}'")
    console.run("rosparam set /gains '{D: 3}'")  # merged, as rosparam does
    assert console.run("rosparam get /a") == "5\n"
    assert console.run("rosparam get /b") == "-2.5\n"
    assert console.run("rosparam get /s") == "''\n\n"  # yaml.dump has no '...' here
    assert console.run("rosparam get /gains") == "D: 3\nI: 0\nP: 1.0\n\n"
    assert console.run("rosparam get -p /gains") == "D: 3\nI: 0\nP: 1.0\n"
    assert console.run("rosparam list /gains") == "/gains/D\n/gains/I\n/gains/P\n"
    assert console.run("rosparam set -v /c true") == "set parameter [/c] to [True]\n"


def test_pretty_multiline_and_nested() -> None:
    assert pretty_text({"b": {"x": 1}, "a": "two\nlines"}) == "a: |\n  two\n  lines\nb:\n  x: 1\n"


def test_load_dump_delete(console: Console, tmp_path: Path) -> None:
    src = tmp_path / "p.yaml"
    src.write_text("utterance: hi\ngains: {P: 1, I: 2}\nangle: !degrees 180\n---\n_ns: other\n"
                   "x: 1\n")
    console.run(f"rosparam load {src} /robot")
    assert console.run("rosparam list /robot") == (
        "/robot/angle\n/robot/gains/I\n/robot/gains/P\n/robot/other/x\n/robot/utterance\n")
    assert console.run("rosparam get /robot/angle") == "3.141592653589793\n"
    out = console.run("rosparam dump")
    assert yaml.safe_load(out)["robot"]["gains"] == {"I": 2, "P": 1}
    dump = tmp_path / "d.yaml"
    console.run(f"rosparam dump {dump} /robot")
    assert dump.read_text() == dump_text(console.world.params.get_param("/robot"))
    console.run("rosparam delete /robot/gains")
    assert "/robot/gains/P" not in console.run("rosparam list")
    console.run("rosparam delete /")
    assert console.run("rosparam list") == "\n"


@pytest.mark.parametrize("line, text", [
    ("rosparam get /nope", "Parameter [/nope] is not set"),
    ("rosparam delete /nope", "parameter [/nope] is not set"),
    ("rosparam set /x", "Please specify a parameter value"),
    ("rosparam set /x '[1, 2'", "invalid YAML value"),
    ("rosparam load /no/such.yaml", "file [/no/such.yaml] does not exist"),
    ("rosparam get", "Please specify a parameter name"),
    ("rosparam frob", "unknown command 'rosparam frob'"),
    ("rosparam set /x 4294967296", "/x"),
])
def test_errors(console: Console, line: str, text: str) -> None:
    result = console.execute(line)
    assert result.code == 1
    assert result.err.startswith("ERROR: ") and text in result.err
    assert result.err.count("\n") == 1


def test_usage(console: Console) -> None:
    assert console.run("rosparam").startswith("rosparam is a command-line tool for getting, "
                                              "setting, and deleting parameters")


_VALUES: list[Any] = [5, -2.5, True, "text", "two\nlines", "", [1, 2.5, "x"],
                      {"P": 1.0, "nested": {"a": [1, 2]}, "s": "x y"}, {}, 2**31 - 1]

_ROS_PARAM = r'''
import contextlib, io, json, sys
import rosparam
values = json.loads(sys.stdin.read())
out = []
for v in values:
    rosparam.get_param = lambda name, v=v: v
    row = []
    for pretty in (False, True):
        buf = io.StringIO()
        with contextlib.redirect_stdout(buf):
            rosparam._rosparam_cmd_get_param("/p", pretty=pretty)
        row.append(buf.getvalue())
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        rosparam.dump_params(None, "/p")
    row.append(buf.getvalue())
    out.append(row)
print(json.dumps(out))
'''


@pytest.mark.ros
def test_get_and_dump_text_match_rosparam(ros_python: Any) -> None:
    theirs = json.loads(ros_python(_ROS_PARAM, stdin=json.dumps(_VALUES)))
    for value, (plain, pretty, dump) in zip(_VALUES, theirs):
        console = Console(out=lambda _line: None)
        console.world.params.set_param("/p", value)
        assert get_text(value) == plain
        assert console.run("rosparam get /p") == plain
        assert console.run("rosparam get -p /p") == pretty
        assert console.run("rosparam dump '' /p") == dump
