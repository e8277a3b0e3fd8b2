"""The pure core of a dynamic_reconfigure server (DR ``src/dynamic_reconfigure/server.py``).

A configuration type is described in Python with :class:`ParameterGenerator`
(the API of a ``.cfg`` file: ``gen.add(name, type, level, description,
default, min, max, edit_method)``, ``gen.const``, ``gen.enum``), whose
:meth:`~ParameterGenerator.generate` returns a :class:`ConfigType`.

:class:`ReconfigureCore` is the server without topics or services:

1. the config starts from the defaults, overridden by the parameters
   already on the server (``param_get``), and is clamped to [min, max];
2. the callback runs once at start-up with ``level = 0xFFFFFFFF``
   (:data:`ALL_LEVELS`; rospy passes ``~0``, i.e. -1, which means the same
   bits; roscpp passes 0xFFFFFFFF);
3. each update merges the changes, clamps them, computes ``level`` as the
   OR of the levels of the parameters that changed, and calls the callback;
4. the config the callback returns becomes the new config and is written
   back with ``param_set``; a callback returning None raises
   :class:`~ddes.errors.DynamicReconfigureCallbackException`.

:func:`encode_config`, :func:`decode_config` and :func:`encode_description`
convert to and from the shape of ``dynamic_reconfigure/Config`` and
``ConfigDescription`` messages as plain dicts and tuples, for whoever wires
the ``set_parameters`` service and the latched ``parameter_updates`` /
``parameter_descriptions`` topics.

Deviations from rospy, on purpose: values are type-checked (a str for an
int parameter, or an unknown name, raises a typed error naming the
parameter; rospy merges anything); int values of double parameters become
floats (as in roscpp); a callback returning None leaves the previous config
in place (rospy sets it to None and breaks later updates); parameter groups
are not modelled (every parameter lives in the ``Default`` group, and
the config holds no ``groups`` entry).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import Literal, TypedDict

from ddes.errors import (
    DdesKeyError,
    DdesTypeError,
    DdesValueError,
    DynamicReconfigureCallbackException,
)

__all__ = [
    "ALL_LEVELS",
    "Config",
    "ConfigDescriptionDict",
    "ConfigMsgDict",
    "ConfigType",
    "EnumConstant",
    "ParamDescription",
    "ParamValue",
    "ParameterGenerator",
    "ReconfigureCallback",
    "ReconfigureCore",
    "bool_t",
    "decode_config",
    "double_t",
    "encode_config",
    "encode_description",
    "int_t",
    "reconfigure_namespace",
    "str_t",
]

str_t = "str"
bool_t = "bool"
int_t = "int"
double_t = "double"

#: The value of a parameter: ``bool_t``, ``int_t``, ``double_t`` or ``str_t``.
ParamValue = bool | int | float | str

#: The level of the start-up callback (roscpp's 0xFFFFFFFF; rospy's ~0 == -1).
ALL_LEVELS = 0xFFFFFFFF
_INT_MIN, _INT_MAX = -0x80000000, 0x7FFFFFFF
_PYTYPE: dict[str, type[ParamValue]] = {str_t: str, int_t: int, double_t: float, bool_t: bool}
_DEFVAL: dict[str, ParamValue] = {str_t: "", int_t: 0, double_t: 0.0, bool_t: False}
_MINVAL: dict[str, ParamValue] = {str_t: "", int_t: _INT_MIN, double_t: -math.inf, bool_t: False}
_MAXVAL: dict[str, ParamValue] = {str_t: "", int_t: _INT_MAX, double_t: math.inf, bool_t: True}
_NAME = re.compile(r"[a-zA-Z][a-zA-Z0-9_]*")
_REPLY_NONE = "Reconfigure callback should return a possibly updated configuration."


class Config(dict[str, ParamValue]):
    """A configuration: a dict whose items are also attributes (``config.speed``)."""

    def __getattr__(self, name: str) -> ParamValue:
        try:
            return self[name]
        except KeyError:
            raise AttributeError(f"config has no parameter {name!r}") from None

    def __setattr__(self, name: str, value: ParamValue) -> None:
        self[name] = value

    def copy(self) -> Config:
        """A shallow copy that is still a :class:`Config`."""
        return Config(self)


@dataclass(frozen=True)
class ParamDescription:
    """One parameter of a configuration type (a ``.cfg`` ``gen.add`` line)."""

    name: str
    type: str
    level: int
    description: str
    default: ParamValue
    min: ParamValue
    max: ParamValue
    edit_method: str = ""


@dataclass(frozen=True, eq=False)
class ConfigType:
    """A generated configuration type: parameters in declaration order, and constants."""

    name: str
    parameters: tuple[ParamDescription, ...]
    constants: dict[str, ParamValue] = field(default_factory=dict)

    def param(self, name: str) -> ParamDescription:
        """The description of ``name``; DdesKeyError naming the known parameters if absent."""
        for p in self.parameters:
            if p.name == name:
                return p
        known = ", ".join(p.name for p in self.parameters) or "none"
        raise DdesKeyError(
            f"unknown dynamic_reconfigure parameter {name!r} in {self.name}; known: {known}"
        )

    @property
    def names(self) -> list[str]:
        """Parameter names in declaration order."""
        return [p.name for p in self.parameters]

    @property
    def defaults(self) -> dict[str, ParamValue]:
        """name -> default (the generated ``defaults`` dict)."""
        return {p.name: p.default for p in self.parameters}

    @property
    def min(self) -> dict[str, ParamValue]:
        """name -> min (``""`` for str, False for bool)."""
        return {p.name: p.min for p in self.parameters}

    @property
    def max(self) -> dict[str, ParamValue]:
        """name -> max (``""`` for str, True for bool)."""
        return {p.name: p.max for p in self.parameters}

    @property
    def level(self) -> dict[str, int]:
        """name -> level bitmask."""
        return {p.name: p.level for p in self.parameters}

    @property
    def type(self) -> dict[str, str]:
        """name -> ``"int"``, ``"double"``, ``"str"`` or ``"bool"``."""
        return {p.name: p.type for p in self.parameters}

    @property
    def all_level(self) -> int:
        """The OR of every parameter's level."""
        out = 0
        for p in self.parameters:
            out |= p.level
        return out


def _typed(name: str, drtype: str, field_: str, value: object) -> ParamValue:
    """``value`` as the Python type of ``drtype`` (an int is fine for double), else DdesTypeError."""
    pytype = _PYTYPE[drtype]
    if type(value) is not pytype and not (pytype is float and type(value) is int):
        raise DdesTypeError(
            f"'{name}' has type {drtype}, but {field_} is {value!r} "
            f"({type(value).__name__}); give a {pytype.__name__}"
        )
    assert isinstance(value, (bool, int, float, str))  # checked just above
    converted = pytype(value)
    if isinstance(converted, int) and drtype == int_t and not _INT_MIN <= converted <= _INT_MAX:
        raise DdesValueError(
            f"'{name}' is a 32-bit int, but {field_} is {value}; "
            f"keep it within {_INT_MIN}..{_INT_MAX}"
        )
    return converted


class EnumConstant(TypedDict):
    """A named constant of an enum (``gen.const(name, type, value, descr)``)."""

    name: str
    type: str
    value: ParamValue
    description: str


def _check_description(description: str) -> None:
    if not isinstance(description, str):
        raise DdesTypeError(f"description must be a str, got {description!r}")
    for quote in ('"', "'"):
        if quote in description:
            raise DdesValueError(f"quotes not allowed in description string `{description}`")


class ParameterGenerator:
    """Describe a configuration the way a dynamic_reconfigure ``.cfg`` file does.

    Example::

        gen = ParameterGenerator()
        size = gen.enum([gen.const("Small", int_t, 0, "small"),
                         gen.const("Large", int_t, 1, "large")], "sizes")
        gen.add("speed", double_t, 1, "max speed", 0.5, 0.0, 2.0)
        gen.add("size", int_t, 2, "a size", 0, 0, 1, edit_method=size)
        TutorialsConfig = gen.generate("my_pkg", "my_node", "Tutorials")
    """

    def __init__(self) -> None:
        self._params: list[ParamDescription] = []
        self._constants: list[EnumConstant] = []

    def add(
        self,
        name: str,
        paramtype: str,
        level: int,
        description: str,
        default: ParamValue | None = None,
        min: ParamValue | None = None,  # noqa: A002 - the .cfg API's own argument names
        max: ParamValue | None = None,  # noqa: A002
        edit_method: str = "",
    ) -> None:
        """Declare a parameter; missing default/min/max take the type's defaults."""
        if not isinstance(name, str) or _NAME.fullmatch(name) is None:
            raise DdesValueError(
                f"The name of field '{name}' does not follow the ROS naming conventions "
                f"(^[a-zA-Z][a-zA-Z0-9_]*$), see http://wiki.ros.org/ROS/Patterns/Conventions"
            )
        if any(p.name == name for p in self._params):
            raise DdesValueError(f"parameter '{name}' is declared twice; give each a unique name")
        if paramtype not in _PYTYPE:
            raise DdesValueError(
                f"'{name}' has unknown type {paramtype!r}; use int_t, double_t, str_t or bool_t"
            )
        if paramtype in (str_t, bool_t) and (max is not None or min is not None):
            raise DdesValueError(f"Max or min specified for {name}, which is of '{paramtype}' type")
        if isinstance(level, bool) or not isinstance(level, int) or not 0 <= level <= ALL_LEVELS:
            raise DdesValueError(f"'{name}' has level {level!r}; give an int in 0..0xFFFFFFFF")
        if not isinstance(description, str):
            raise DdesTypeError(f"'{name}' needs a str description, got {description!r}")
        if not isinstance(edit_method, str):
            raise DdesTypeError(f"'{name}' edit_method must be a str (gen.enum(...)), got {edit_method!r}")

        def fill(value: ParamValue | None, field_: str, default_: ParamValue) -> ParamValue:
            return default_ if value is None else _typed(name, paramtype, field_, value)

        self._params.append(
            ParamDescription(
                name=name,
                type=paramtype,
                level=int(level),
                description=description,
                default=fill(default, "default", _DEFVAL[paramtype]),
                min=fill(min, "min", _MINVAL[paramtype]),
                max=fill(max, "max", _MAXVAL[paramtype]),
                edit_method=edit_method,
            )
        )

    def const(self, name: str, type: str, value: ParamValue,  # noqa: A002
              descr: str) -> EnumConstant:
        """A named constant for an enum; also exported as ``ConfigType.constants[name]``."""
        _check_description(descr)
        if type not in _PYTYPE:
            raise DdesValueError(f"constant '{name}' has unknown type {type!r}")
        newconst: EnumConstant = {"name": name, "type": type,
                                  "value": _typed(name, type, "value", value),
                                  "description": descr}
        self._constants.append(newconst)
        return newconst

    def enum(self, constants: Iterable[Mapping[str, object]], description: str) -> str:
        """An ``edit_method`` string listing ``constants`` (all of one type)."""
        consts = [dict(c) for c in constants]
        if len({c["type"] for c in consts}) != 1:
            raise DdesValueError("Inconsistent types in enum! Every constant needs the same type")
        _check_description(description)
        return repr({"enum": consts, "enum_description": description})

    def generate(self, pkgname: str, nodename: str, name: str) -> ConfigType:
        """The :class:`ConfigType` ``<name>Config`` (DR writes files; ddes returns the type)."""
        return ConfigType(
            name=f"{name}Config",
            parameters=tuple(self._params),
            constants={c["name"]: c["value"] for c in self._constants},
        )


def reconfigure_namespace(namespace: str = "") -> str:
    """The namespace a Server uses: ``""`` -> ``~``, ``x`` -> ``~x/``, ``/x`` -> ``/x/`` (DR)."""
    if not namespace:
        return "~"
    if namespace[0] not in ("/", "~"):
        namespace = "~" + namespace
    return (namespace + "/").replace("//", "/")


# -- message shapes -----------------------------------------------------------------------------

_Section = Literal["bools", "ints", "strs", "doubles"]
_SECTIONS: dict[str, _Section] = {bool_t: "bools", int_t: "ints", str_t: "strs",
                                  double_t: "doubles"}
#: A ``dynamic_reconfigure/GroupState``: (name, state, id, parent).
GroupState = tuple[str, bool, int, int]
_DEFAULT_GROUP: GroupState = ("Default", True, 0, 0)


class ConfigMsgDict(TypedDict):
    """A ``dynamic_reconfigure/Config`` message as a dict: (name, value) pairs per type."""

    bools: list[tuple[str, ParamValue]]
    ints: list[tuple[str, ParamValue]]
    strs: list[tuple[str, ParamValue]]
    doubles: list[tuple[str, ParamValue]]
    groups: list[GroupState]


class ParamDescriptionDict(TypedDict):
    """A ``dynamic_reconfigure/ParamDescription`` as a dict."""

    name: str
    type: str
    level: int
    description: str
    edit_method: str


class GroupDict(TypedDict):
    """A ``dynamic_reconfigure/Group`` as a dict."""

    name: str
    type: str
    parameters: list[ParamDescriptionDict]
    parent: int
    id: int


class ConfigDescriptionDict(TypedDict):
    """A ``dynamic_reconfigure/ConfigDescription`` as a dict."""

    groups: list[GroupDict]
    max: ConfigMsgDict
    min: ConfigMsgDict
    dflt: ConfigMsgDict


def _encode(values: Mapping[str, ParamValue], ct: ConfigType, groups: bool) -> ConfigMsgDict:
    msg: ConfigMsgDict = {"bools": [], "ints": [], "strs": [], "doubles": [], "groups": []}
    for p in ct.parameters:
        if p.name in values:
            msg[_SECTIONS[p.type]].append((p.name, values[p.name]))
    if groups:
        msg["groups"].append(_DEFAULT_GROUP)
    return msg


def encode_config(config: Mapping[str, ParamValue], config_type: ConfigType) -> ConfigMsgDict:
    """``dynamic_reconfigure/Config`` as a dict: ``{"bools": [(name, value)], "ints": ...,
    "strs": ..., "doubles": ..., "groups": [(name, state, id, parent)]}``, parameters in
    declaration order."""
    return _encode(config, config_type, groups=True)


def _pairs(section: Iterable[object] | None) -> list[tuple[str, ParamValue]]:
    """The (name, value) entries of one section, whatever their shape (values unchecked:
    :meth:`ReconfigureCore.update_configuration` checks them)."""
    out = []
    for item in section or ():
        if isinstance(item, Mapping):
            out.append((item["name"], item["value"]))
        elif isinstance(item, (tuple, list)) and len(item) == 2:
            out.append((item[0], item[1]))
        elif hasattr(item, "name") and hasattr(item, "value"):
            out.append((item.name, item.value))
        else:
            raise DdesTypeError(
                f"cannot read a (name, value) parameter entry from {item!r}; "
                f"use a pair, a dict with 'name'/'value', or a *Parameter message"
            )
    return out


def decode_config(msg: object) -> Config:
    """A :class:`Config` from a ``Config`` message, dict-shaped or a message object.

    Entries are read from bools, ints, strs, doubles in that order (as
    rospy's ``decode_config``); groups are ignored.
    """
    config = Config()
    for section in ("bools", "ints", "strs", "doubles"):
        raw = msg.get(section) if isinstance(msg, Mapping) else getattr(msg, section, None)
        for name, value in _pairs(raw):
            config[name] = value
    return config


def encode_description(config_type: ConfigType) -> ConfigDescriptionDict:
    """``dynamic_reconfigure/ConfigDescription`` as a dict (one ``Default`` group)."""
    group: GroupDict = {
        "name": "Default",
        "type": "",
        "parameters": [
            {"name": p.name, "type": p.type, "level": p.level,
             "description": p.description, "edit_method": p.edit_method}
            for p in config_type.parameters
        ],
        "parent": 0,
        "id": 0,
    }
    return {
        "groups": [group],
        "max": _encode(config_type.max, config_type, groups=False),
        "min": _encode(config_type.min, config_type, groups=False),
        "dflt": _encode(config_type.defaults, config_type, groups=False),
    }


# -- the server core ------------------------------------------------------------------------------

#: ``callback(config, level) -> config`` (a mapping with every parameter; None raises).
ReconfigureCallback = Callable[[Config, int], object]


class ReconfigureCore:
    """A dynamic_reconfigure server without transport.

    Parameters
    ----------
    config_type:
        From :meth:`ParameterGenerator.generate`.
    callback:
        ``callback(config, level) -> config``; it may change the config
        it returns.  Returning None raises DynamicReconfigureCallbackException.
    param_get:
        ``param_get(name)`` reads a parameter of the server's namespace,
        raising KeyError when it is not set (like ``rospy.get_param``).
    param_set:
        ``param_set(name, value)`` writes it back after every change.
    on_update:
        Called with the new config after every change (start-up
        included): the hook that publishes ``parameter_updates``.
    """

    def __init__(
        self,
        config_type: ConfigType,
        callback: ReconfigureCallback,
        param_get: Callable[[str], object] | None = None,
        param_set: Callable[[str, ParamValue], object] | None = None,
        on_update: Callable[[Config], object] | None = None,
    ) -> None:
        if not isinstance(config_type, ConfigType):
            raise DdesTypeError(f"config_type must be a ConfigType (gen.generate(...)), got {config_type!r}")
        if not callable(callback):
            raise DdesTypeError(f"callback must be callable, got {callback!r}")
        self.type = config_type
        self.callback = callback
        self._param_set = param_set
        self._on_update = on_update
        config = Config(config_type.defaults)
        if param_get is not None:
            for p in config_type.parameters:
                try:
                    value = param_get(p.name)
                except KeyError:
                    continue
                config[p.name] = self._coerce(p, value, "the parameter server value")
        self._clamp(config)
        self._config = Config(config)
        self._change_config(config, ALL_LEVELS)

    @property
    def config(self) -> Config:
        """The current configuration (a copy)."""
        return Config(self._config)

    def update_configuration(self, changes: Mapping[str, object]) -> Config:
        """Merge ``changes``, clamp, call the callback with the changed levels; the new config."""
        if not isinstance(changes, Mapping):
            raise DdesTypeError(f"changes must be a mapping name -> value, got {changes!r}")
        new = Config(self._config)
        for name, value in changes.items():
            new[name] = self._coerce(self.type.param(name), value, "the new value")
        self._clamp(new)
        return self._change_config(new, self._calc_level(new, self._config))

    def set_parameters(self, config_msg: object) -> ConfigMsgDict:
        """The ``set_parameters`` service: a Config message in, the resulting one out."""
        return encode_config(self.update_configuration(decode_config(config_msg)), self.type)

    def description(self) -> ConfigDescriptionDict:
        """What ``parameter_descriptions`` carries (see :func:`encode_description`)."""
        return encode_description(self.type)

    # -- internals ---------------------------------------------------------------------------
    @staticmethod
    def _coerce(p: ParamDescription, value: object, what: str) -> ParamValue:
        """``value`` as the type of ``p`` (an int for a double becomes a float), else an error."""
        if p.type == bool_t:
            if isinstance(value, bool):
                return value
        elif p.type == str_t:
            if isinstance(value, str):
                return str(value)
        elif isinstance(value, int) and not isinstance(value, bool):
            return int(value) if p.type == int_t else float(value)
        elif p.type == double_t and isinstance(value, float):
            return float(value)
        raise DdesTypeError(
            f"{what} of parameter '{p.name}' is {value!r} ({type(value).__name__}), "
            f"but '{p.name}' has type {p.type}; give a {_PYTYPE[p.type].__name__}"
        )

    def _clamp(self, config: Config) -> None:
        for p in self.type.parameters:
            if p.type in (int_t, double_t):
                val = config[p.name]
                if isinstance(val, str) or isinstance(p.min, str) or isinstance(p.max, str):
                    continue  # never: a numeric parameter holds numbers
                if val > p.max:
                    config[p.name] = p.max
                elif val < p.min:
                    config[p.name] = p.min

    def _calc_level(self, new: Mapping[str, ParamValue], old: Mapping[str, ParamValue]) -> int:
        level = 0
        for p in self.type.parameters:
            if new[p.name] != old[p.name]:
                level |= p.level
        return level

    def _change_config(self, config: Config, level: int) -> Config:
        result = self.callback(config, level)
        if result is None:
            raise DynamicReconfigureCallbackException(_REPLY_NONE)
        if not isinstance(result, Mapping):
            raise DdesTypeError(
                f"the reconfigure callback returned {result!r}; return the (possibly updated) config"
            )
        accepted = Config()
        for p in self.type.parameters:
            if p.name not in result:
                raise DdesKeyError(
                    f"the reconfigure callback returned a config without parameter '{p.name}'; "
                    f"return the config it was given, updated"
                )
            accepted[p.name] = self._coerce(p, result[p.name], "the callback's value")
        self._config = accepted
        if self._param_set is not None:
            for p in self.type.parameters:
                self._param_set(p.name, accepted[p.name])
        if self._on_update is not None:
            self._on_update(Config(accepted))
        return Config(accepted)

    def __repr__(self) -> str:
        return f"ReconfigureCore({self.type.name}, {dict(self._config)!r})"
