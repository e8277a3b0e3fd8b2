"""Parameter value conversion and rosparam's YAML extensions."""

from __future__ import annotations

import math

import pytest
import yaml
from hypothesis import given
from hypothesis import strategies as st

from ddes.errors import ROSLaunchException
from ddes.launch.values import (
    convert_value,
    load_rosparam_yaml,
    parse_bool_attr,
    parse_float_attr,
)


@pytest.mark.parametrize(("text", "expected"), [
    ("1", 1), ("-7", -7), (" 5 ", 5), ("1.5", 1.5), ("-.5", -0.5), ("1.", 1.0),
    ("1e3", "1e3"),              # no '.', not an int: a string (roslaunch)
    ("1_000", "1_000"),          # underscores stay strings
    ("1.0_0", 1.0),              # a '.' means float(), which accepts underscores
    ("true", True), ("False", False), ("TRUE", True),
    ("yes", "yes"), ("", ""), ("a.b", "a.b"), ("inf", "inf"), ("nan.0", "nan.0"),
])
def test_auto(text: str, expected: object) -> None:
    got = convert_value(text, "auto")
    assert got == expected and type(got) is type(expected)


@given(st.integers())
def test_auto_round_trips_ints(n: int) -> None:
    assert convert_value(str(n), "auto") == n


@pytest.mark.parametrize(("text", "type_", "expected"), [
    ("42", "str", "42"), ("42", "string", "42"), ("42", "int", 42), ("3", "double", 3.0),
    ("1", "bool", True), ("0", "bool", False), (" True ", "boolean", True),
    ("false", "BOOL", False), ("{a: [1, 2]}", "yaml", {"a": [1, 2]}), ("", "yaml", None),
])
def test_explicit_types(text: str, type_: str, expected: object) -> None:
    assert convert_value(text, type_) == expected


@pytest.mark.parametrize(("text", "type_", "message"), [
    ("x", "int", "invalid literal for int"),
    ("1.5", "int", "invalid literal for int"),
    ("x", "double", "could not convert string to float"),
    ("yes", "bool", "yes is not a 'bool' type"),
    ("[1", "yaml", "invalid YAML value"),
    ("1", "float", "Unknown type 'float'"),
])
def test_conversion_errors(text: str, type_: str, message: str) -> None:
    with pytest.raises(ROSLaunchException, match=message):
        convert_value(text, type_)


def test_bool_attributes_accept_only_true_false() -> None:
    assert parse_bool_attr(None, True, "respawn") is True
    assert parse_bool_attr("TRUE", False, "respawn") is True
    assert parse_bool_attr("false", True, "respawn") is False
    with pytest.raises(ROSLaunchException, match="invalid bool value for respawn: 1"):
        parse_bool_attr("1", False, "respawn")
    with pytest.raises(ROSLaunchException, match="must be non-empty"):
        parse_bool_attr("", False, "respawn")


def test_float_attributes() -> None:
    assert parse_float_attr(None, 0.0, "respawn_delay") == 0.0
    assert parse_float_attr("2.5", 0.0, "respawn_delay") == 2.5
    with pytest.raises(ROSLaunchException, match="invalid float value for respawn_delay: x"):
        parse_float_attr("x", 0.0, "respawn_delay")


def test_rosparam_angles() -> None:
    data = load_rosparam_yaml(
        "a: deg(90)\nb: rad(pi/2)\nc: !degrees 180\nd: !radians 2*pi\ne: !radians -(1+1)**2\n"
        "f: degrees\ng: 'deg(90)'\n"
    )
    assert data["a"] == pytest.approx(math.pi / 2)
    assert data["b"] == pytest.approx(math.pi / 2)
    assert data["c"] == pytest.approx(math.pi)
    assert data["d"] == pytest.approx(2 * math.pi)
    assert data["e"] == -4.0
    # the implicit rad(...) form stops at the first ')', as rosparam's pattern does
    assert load_rosparam_yaml("r: rad((1))") == {"r": "rad((1))"}
    assert data["f"] == "degrees"
    assert data["g"] == "deg(90)"  # quoted scalars are not resolved implicitly


def test_rosparam_rad_evaluates_only_arithmetic() -> None:
    with pytest.raises(yaml.YAMLError, match="invalid radian expression"):
        load_rosparam_yaml("a: !radians __import__('os')")
    with pytest.raises(yaml.YAMLError, match="invalid degree value"):
        load_rosparam_yaml("a: !degrees ninety")


def test_rosparam_empty_is_a_dict_and_pyyaml_is_untouched() -> None:
    assert load_rosparam_yaml("") == {}
    assert load_rosparam_yaml("# nothing\n") == {}
    assert yaml.safe_load("a: deg(90)") == {"a": "deg(90)"}
