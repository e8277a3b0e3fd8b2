"""Parameter YAML against hostile input: bombs, deep nesting, eval, huge and odd files (issue 13)."""

from __future__ import annotations

import os
import tracemalloc
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ddes.errors import DdesError, ResourceLimitError, ROSParamException
from ddes.graph.params import ParamServer
from ddes.graph.yamlsafe import YamlLimits, evaluate_angle, load_yaml, load_yaml_all, read_bounded

_MB = 1 << 20


@contextmanager
def traced_peak() -> Iterator[list[int]]:
    """Yields a list that holds, after the block, the peak bytes it allocated (tracemalloc).

    Memory, not CPU time, shows a bomb refused before it is built, and it holds on a loaded
    machine (the developers' guide: no timed assertions in tests).
    """
    peak: list[int] = []
    tracemalloc.start()
    try:
        yield peak
    finally:
        peak.append(tracemalloc.get_traced_memory()[1])
        tracemalloc.stop()


def billion_laughs(levels: int = 9, width: int = 9) -> str:
    lines = ["a0: &a0 [" + ",".join(["lol"] * width) + "]"]
    for i in range(1, levels):
        lines.append(f"a{i}: &a{i} [" + ",".join([f"*a{i - 1}"] * width) + "]")
    return "\n".join(lines) + "\n"


def test_a_billion_laughs_alias_bomb_is_refused_before_it_expands() -> None:
    with traced_peak() as peak:
        with pytest.raises(ResourceLimitError, match="alias bomb"):
            load_yaml(billion_laughs())
        with pytest.raises(ResourceLimitError, match="alias bomb"):
            ParamServer().load(billion_laughs())
    assert peak[0] < 8 * _MB, peak  # expanded, it would be 9**9 (387 million) values


def test_small_aliases_still_load() -> None:
    data = load_yaml("base: &b {x: 1, y: 2}\nleft: *b\nright: {<<: *b, y: 3}\n")
    assert data == {"base": {"x": 1, "y": 2}, "left": {"x": 1, "y": 2}, "right": {"x": 1, "y": 3}}


def test_a_recursive_alias_is_refused() -> None:
    with pytest.raises(ResourceLimitError, match="recursive YAML alias"):
        load_yaml("a: &a [1, *a]")


def test_deep_nesting_is_refused_not_a_recursion_error() -> None:
    with pytest.raises(ResourceLimitError, match="nested more than 64 deep"):
        load_yaml("[" * 5000 + "]" * 5000)
    # aliases can multiply depth too: each level doubles it
    text = "a0: &a0 [[[[[[[[[[1]]]]]]]]]]\n" + "".join(
        f"a{i}: &a{i} [*a{i - 1}, [[[[[[[[[[*a{i - 1}]]]]]]]]]]]\n" for i in range(1, 9))
    with pytest.raises(ResourceLimitError, match="once its aliases are expanded"):
        load_yaml(text)
    assert load_yaml("[" * 60 + "]" * 60) is not None


def test_command_line_node_params_are_bounded_yaml() -> None:
    """``_p:=VALUE`` of a node (a launch file's args=, rosrun) goes through the bounded loader:
    before issue 38 plain yaml.safe_load ended in a RecursionError or kept the bomb."""
    from ddes.graph.names import load_command_line_node_params

    deep = "[" * 5000 + "]" * 5000
    with pytest.raises(ResourceLimitError, match=r"command-line parameter _p: YAML nested more "
                                                 "than 64 deep"):
        load_command_line_node_params(["_p:=" + deep])
    bomb = "[" + ",".join(["&a0 [x,x,x,x,x,x,x,x,x]"] + [
        f"&a{i} [" + ",".join([f"*a{i - 1}"] * 9) + "]" for i in range(1, 9)]) + "]"
    with traced_peak() as peak:
        with pytest.raises(ResourceLimitError, match=r"command-line parameter _b: .*alias bomb"):
            load_command_line_node_params(["_b:=" + bomb])
    assert peak[0] < 8 * _MB, peak
    assert load_command_line_node_params(["_rate:=10", "_l:=[1, {a: 2}]"]) == {
        "rate": 10, "l": [1, {"a": 2}]}


def test_too_many_values_or_documents_and_too_much_text_are_refused() -> None:
    with pytest.raises(ResourceLimitError, match="more than 100 values"):
        load_yaml("[" + ",".join(["1"] * 200) + "]", limits=YamlLimits(max_nodes=100))
    with pytest.raises(ResourceLimitError, match="more than 1000 documents"):
        load_yaml_all("--- 1\n" * 1001)
    with pytest.raises(ResourceLimitError, match="larger than the 10"):
        load_yaml("x: 12345678901", limits=YamlLimits(max_bytes=10))
    assert load_yaml("[" + ",".join(["1"] * 200) + "]", limits=YamlLimits(max_nodes=1000))


@pytest.mark.parametrize("expr", ["9**9**9", "10**400", "2**2**2**2**2", "(-8)**(1/3)", "1/0",
                                  "__import__('os').system('true')", "pi.real", "(1)*10**9**9",
                                  "-" * 300 + "1", "(" * 150 + "1" + ")" * 150, "1" * 5000])
def test_hostile_radian_expressions_are_refused_quickly(expr: str) -> None:
    with traced_peak() as peak:
        with pytest.raises(yaml.YAMLError, match="invalid radian expression"):
            load_yaml(f"x: !radians {expr}", angles=True)
        with pytest.raises(ROSParamException, match="radian"):
            ParamServer().load(f"x: !radians {expr}")
    assert peak[0] < 8 * _MB, peak  # 9**9**9, computed, would take ~140 MiB


def test_degrees_take_one_number_as_rosparam_does() -> None:
    with pytest.raises(ROSParamException, match="invalid degree value: 9\\*\\*9\\*\\*9"):
        ParamServer().load("x: !degrees 9**9**9")
    assert load_yaml("x: !degrees 180", angles=True)["x"] == pytest.approx(3.141592653589793)
    assert evaluate_angle("-(1+1)**2") == -4.0
    assert evaluate_angle("pi/2 + 2*pi % 3 // 1") == pytest.approx(1.5707963267948966 + 0.0)


@pytest.mark.parametrize("text", ["x: 1" + "0" * 5000, "x: 2001-13-45", "x: !!binary 'zz'",
                                  "x: !!python/object/apply:os.system [true]", "{[1]: 2}",
                                  "x: !!set {a, b}", "x: 2001-01-01"])
def test_odd_values_end_in_typed_errors(text: str) -> None:
    with pytest.raises(DdesError):
        ParamServer().load(text)


def test_files_that_are_not_regular_are_refused_before_reading(tmp_path: Path) -> None:
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    for path, kind in [(Path("/dev/zero"), "a device"), (tmp_path, "a directory"),
                       (fifo, "a FIFO")]:
        with pytest.raises(ROSParamException, match=kind):
            ParamServer().load(path)
    big = tmp_path / "big.yaml"
    big.write_text("x: 1\n" * 100)
    with pytest.raises(ResourceLimitError, match="larger than 100 bytes"):
        read_bounded(big, what="file", error=ROSParamException, limit=100)
    with pytest.raises(ResourceLimitError, match="larger than 100"):
        ParamServer().load(big, limits=YamlLimits(max_bytes=100))
    (tmp_path / "latin1.yaml").write_bytes(b"x: \xff\n")
    with pytest.raises(ROSParamException, match="not UTF-8"):
        ParamServer().load(tmp_path / "latin1.yaml")


_SNIPPETS = ["a: 1", "- x", "&a [1, 2]", "*a", "!radians pi", "!degrees 90", "deg(45)", "rad(2*pi)",
             "{", "}", "[", "]", ":", "---", "...", "<<: *a", "!!int", "!!str", "? ", "'q'", '"\\u00e9"',
             "\n", "  ", ",", "#c", "!!binary AAAA", "1e999", "2001-01-01", "~", "&b", "*b"]


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.one_of(st.text(max_size=200),
                 st.lists(st.sampled_from(_SNIPPETS), max_size=40).map(" ".join),
                 st.lists(st.sampled_from(_SNIPPETS), max_size=40).map("\n".join)))
def test_fuzz_parameter_yaml_loads_or_fails_typed_within_the_bound(text: str) -> None:
    with traced_peak() as peak:
        try:
            ParamServer().load(text, "/fuzz")
        except DdesError:
            pass
        try:
            load_yaml_all(text, angles=True)
        except (DdesError, yaml.YAMLError):
            pass
    assert peak[0] < 16 * _MB, (text, peak)


@settings(max_examples=50, deadline=None)
@given(st.integers(1, 12), st.integers(1, 12))
def test_fuzz_alias_bombs_of_any_shape_are_refused_or_small(levels: int, width: int) -> None:
    sizes = [1 + width]
    for _ in range(1, levels):
        sizes.append(1 + width * sizes[-1])
    expanded = 1 + levels + sum(sizes)  # the mapping, its keys, every list expanded
    with traced_peak() as peak:
        try:
            ParamServer().load(billion_laughs(levels, width))
            assert expanded <= 100_000
        except ResourceLimitError as exc:
            assert "more than 100000" in str(exc)
            assert expanded > 100_000
    assert peak[0] < 16 * _MB, (levels, width, peak)
