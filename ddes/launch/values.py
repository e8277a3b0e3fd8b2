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
All launch YAML (``<rosparam>`` and ``<param type="yaml">``) goes through
the bounded loaders of :mod:`ddes.graph.yamlsafe`, which refuse alias
bombs, deep nesting and huge text with ``ResourceLimitError``; PyYAML's
global loaders are never modified.
"""

from __future__ import annotations

from typing import TypeAlias

import yaml

from ddes.errors import ROSLaunchException
from ddes.graph.yamlsafe import load_yaml

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
            loaded: ParamValue = load_yaml(value)
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


def load_rosparam_yaml(text: str) -> ParamValue:
    """Parse ``<rosparam>`` YAML; empty text gives ``{}`` (roslaunch #3162).

    Bounded by :mod:`ddes.graph.yamlsafe` (size, alias expansion, nesting):
    past a limit :class:`~ddes.errors.ResourceLimitError`, malformed YAML
    :class:`yaml.YAMLError`.
    """
    data = load_yaml(text, angles=True)
    return {} if data is None else data  # type: ignore[no-any-return,unused-ignore]
