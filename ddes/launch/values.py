"""Turning launch-file text into parameter values, as roslaunch does.

:func:`convert_value` is roslaunch's ``loader.convert_value``: ``auto``
guesses float (a ``.`` in the text), then int (no ``_`` in the text), then
bool (``true``/``false`` in any case), else keeps the string.
:func:`parse_bool_attr` is the strict ``true``/``false`` rule of
attributes such as ``respawn``; ``if``/``unless`` use the looser
``convert_value(v, "bool")`` which also accepts ``1``/``0``.

:func:`load_rosparam_yaml` parses ``<rosparam>`` YAML with the extra tags
that importing ``rosparam`` installs: ``!degrees``, ``!radians``,
``deg(90)`` and ``rad(pi/2)``.  rosparam evaluates ``rad(...)`` with
Python's ``eval``; ddes evaluates only arithmetic on numbers and ``pi``.
The constructors live on a private ``SafeLoader`` subclass, so PyYAML's
global loaders are never modified.
"""

from __future__ import annotations

import ast
import math
import operator
import re
from collections.abc import Callable
from typing import TypeAlias

import yaml

from ddes.errors import ROSLaunchException

__all__ = ["ParamValue", "convert_value", "load_rosparam_yaml", "parse_bool_attr",
           "parse_float_attr"]

#: A parameter value as the parameter server holds it (XML-RPC types): bool, int, float, str,
#: bytes (``binfile``), and lists and string-keyed dicts of them (YAML).
ParamValue: TypeAlias = bool | int | float | str | bytes | list["ParamValue"] | dict[str, "ParamValue"]


def convert_value(value: str, type_: str) -> ParamValue:
    """Convert the text ``value`` to ``type_`` (auto, str, int, double, bool, yaml)."""
    t = type_.lower()
    if t == "auto":
        try:
            if "." in value:
                return float(value)
            if "_" not in value:
                return int(value)
        except ValueError:
            pass
        if value.lower() in ("true", "false"):
            return value.lower() == "true"
        return value
    if t in ("str", "string"):
        return value
    if t == "int":
        try:
            return int(value)
        except ValueError as exc:
            raise ROSLaunchException(f"{exc}; give an integer or change type=") from None
    if t == "double":
        try:
            return float(value)
        except ValueError as exc:
            raise ROSLaunchException(f"{exc}; give a number or change type=") from None
    if t in ("bool", "boolean"):
        v = value.lower().strip()
        if v in ("true", "1"):
            return True
        if v in ("false", "0"):
            return False
        raise ROSLaunchException(
            f"{value} is not a '{type_}' type; use true, false, 1 or 0"
        )
    if t == "yaml":
        try:
            loaded: ParamValue = yaml.safe_load(value)
            return loaded
        except yaml.YAMLError as exc:
            raise ROSLaunchException(f"invalid YAML value: {exc}") from None
    raise ROSLaunchException(
        f"Unknown type '{type_}'; use one of str, int, double, bool, yaml (or omit type=)"
    )


def parse_bool_attr(value: str | None, default: bool, label: str) -> bool:
    """roslaunch's ``_bool_attr``: only ``true``/``false`` (any case) are accepted."""
    if value is None:
        return default
    if value.lower() == "true":
        return True
    if value.lower() == "false":
        return False
    if not value:
        raise ROSLaunchException(f"bool value for {label} must be non-empty; use true or false")
    raise ROSLaunchException(f"invalid bool value for {label}: {value}; use true or false")


def parse_float_attr(value: str | None, default: float, label: str) -> float:
    """roslaunch's ``_float_attr``: a float, or ``default`` when absent."""
    if value is None:
        return default
    if not value:
        raise ROSLaunchException(f"float value for {label} must be non-empty")
    try:
        return float(value)
    except ValueError:
        raise ROSLaunchException(f"invalid float value for {label}: {value}") from None


# -- rosparam's YAML extensions ------------------------------------------------------------

_BINOPS: dict[type[ast.operator], Callable[[float, float], float]] = {
    ast.Add: operator.add,
    ast.Sub: operator.sub,
    ast.Mult: operator.mul,
    ast.Div: operator.truediv,
    ast.FloorDiv: operator.floordiv,
    ast.Mod: operator.mod,
    ast.Pow: operator.pow,
}
_UNOPS: dict[type[ast.unaryop], Callable[[float], float]] = {
    ast.UAdd: operator.pos,
    ast.USub: operator.neg,
}


def _arith(node: ast.AST) -> float:
    if isinstance(node, ast.Expression):
        return _arith(node.body)
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(
        node.value, bool
    ):
        return node.value
    if isinstance(node, ast.Name) and node.id == "pi":
        return math.pi
    if isinstance(node, ast.BinOp) and type(node.op) in _BINOPS:
        return _BINOPS[type(node.op)](_arith(node.left), _arith(node.right))
    if isinstance(node, ast.UnaryOp) and type(node.op) in _UNOPS:
        return _UNOPS[type(node.op)](_arith(node.operand))
    raise ValueError("only numbers, pi, + - * / // % ** and parentheses are allowed")


def _construct_radians(loader: yaml.SafeLoader, node: yaml.Node) -> float:
    value = str(loader.construct_scalar(node)).strip()  # type: ignore[arg-type]
    expr = value[4:-1] if value.startswith("rad(") else value
    try:
        return float(_arith(ast.parse(expr, mode="eval")))
    except (SyntaxError, ValueError, ArithmeticError) as exc:
        raise yaml.constructor.ConstructorError(
            None, None, f"invalid radian expression: {value} ({exc})", node.start_mark
        ) from None


def _construct_degrees(loader: yaml.SafeLoader, node: yaml.Node) -> float:
    value = str(loader.construct_scalar(node))  # type: ignore[arg-type]
    expr = value.strip()[4:-1] if value.startswith("deg(") else value
    try:
        return float(expr) * math.pi / 180.0
    except ValueError:
        raise yaml.constructor.ConstructorError(
            None, None, f"invalid degree value: {value}", node.start_mark
        ) from None


class _RosparamLoader(yaml.SafeLoader):
    """SafeLoader plus rosparam's angle tags (configured once, at import)."""


_RosparamLoader.add_constructor("!radians", _construct_radians)
_RosparamLoader.add_constructor("!degrees", _construct_degrees)
_RosparamLoader.add_implicit_resolver("!degrees", re.compile(r"^deg\([^\)]*\)$"), ["d"])
_RosparamLoader.add_implicit_resolver("!radians", re.compile(r"^rad\([^\)]*\)$"), ["r"])


def load_rosparam_yaml(text: str) -> ParamValue:
    """Parse ``<rosparam>`` YAML; empty text gives ``{}`` (roslaunch #3162)."""
    data = yaml.load(text, Loader=_RosparamLoader)  # noqa: S506 - a SafeLoader subclass
    return {} if data is None else data
