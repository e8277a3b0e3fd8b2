"""dynamic_reconfigure for plain scripts: ``from dynamic_reconfigure.server import Server``.

In a rospy script (:mod:`ddes.compat.scripts`) ``import dynamic_reconfigure...`` resolves here:

* ``dynamic_reconfigure.server.Server(type, callback, namespace="")``
  (:mod:`ddes.compat.dynamic_reconfigure.server`) on the node of the running script, over
  :class:`ddes.dynamic_reconfigure.DynamicReconfigureServer`;
* ``dynamic_reconfigure.parameter_generator_catkin`` (and the older ``parameter_generator``):
  the ``.cfg`` API (``ParameterGenerator``, ``int_t``, ``double_t``, ``str_t``, ``bool_t``);
* ``dynamic_reconfigure.msg`` / ``.srv``: the message classes, as for any package;
* ``from <pkg>.cfg import <Name>Config``: the config type that the package's
  ``cfg/*.cfg`` file generates (``gen.generate(PACKAGE, node, "<Name>")``).  ddes runs the
  ``.cfg`` file (it is Python) with the generator above, once per world, instead of generating
  Python and C++ sources at build time.  See docs/rospy.md.
"""

from __future__ import annotations

import builtins
import importlib
import os
import sys
import types
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ddes.dynamic_reconfigure.core import (
    ConfigType,
    ParameterGenerator,
    bool_t,
    double_t,
    int_t,
    str_t,
)
from ddes.errors import DdesValueError, DynamicReconfigureCallbackException
from ddes.rospack import PackageNotFound

if TYPE_CHECKING:
    from ddes.graph.world import World

__all__ = ["DynamicReconfigureCallbackException", "cfg_module", "generator_module",
           "resolve_import"]

_CFG_KEY = "compat.dynamic_reconfigure.cfg"
_SUBMODULES = ("server", "parameter_generator_catkin", "parameter_generator")


_CTYPE = {"str": "std::string", "int": "int", "double": "double", "bool": "bool"}
_CCONSTTYPE = {"str": "const char * const", "int": "const int", "double": "const double",
               "bool": "const bool"}


class _Group:
    """``gen.add_group(name)``: ddes does not model groups; its parameters join the config."""

    def __init__(self, gen: ParameterGenerator) -> None:
        self._gen = gen

    def add(self, name: str, paramtype: str, level: int, description: str, default: Any = None,
            min: Any = None, max: Any = None, edit_method: str = "") -> None:  # noqa: A002
        self._gen.add(name, paramtype, level, description, default, min, max, edit_method)

    def add_group(self, name: str, type: str = "", state: bool = True) -> _Group:  # noqa: A002
        return _Group(self._gen)


def generator_module(found: list[ConfigType] | None = None) -> types.ModuleType:
    """``dynamic_reconfigure.parameter_generator_catkin`` for a ``.cfg`` file or a script.

    Its ``ParameterGenerator.generate`` returns the :class:`ConfigType` (ddes writes no
    files); with ``found`` it also appends the type there and returns 0, for ``exit(...)``.
    """

    class CfgParameterGenerator(ParameterGenerator):
        __doc__ = ParameterGenerator.__doc__

        def const(self, name: str, type: str, value: Any,  # noqa: A002
                  descr: str) -> Any:
            """An enum constant with the keys catkin's generator gives it (its .cfg line and
            file, C++ types), so an enum's ``edit_method`` text is the real one."""
            checked = super().const(name, type, value, descr)
            caller = sys._getframe(1)
            return {"name": name, "type": type, "value": checked["value"],
                    "srcline": caller.f_lineno,
                    "srcfile": os.path.basename(caller.f_code.co_filename),
                    "description": descr, "ctype": _CTYPE[type],
                    "cconsttype": _CCONSTTYPE[type]}

        def add_group(self, name: str, type: str = "",  # noqa: A002
                      state: bool = True) -> _Group:
            """A group: its parameters join the config (ddes does not model groups)."""
            return _Group(self)

        def generate(self, pkgname: str, nodename: str, name: str) -> Any:
            config_type = super().generate(pkgname, nodename, name)
            if found is None:
                return config_type
            found.append(config_type)
            return 0

    module = types.ModuleType("dynamic_reconfigure.parameter_generator_catkin")
    module.__dict__.update(ParameterGenerator=CfgParameterGenerator, int_t=int_t,
                           double_t=double_t, str_t=str_t, bool_t=bool_t,
                           __all__=["ParameterGenerator", "bool_t", "double_t", "int_t",
                                    "str_t"])
    return module


#: ``dynamic_reconfigure.parameter_generator_catkin`` in a script: ``generate`` returns the type.
parameter_generator_catkin = parameter_generator = generator_module()


def _run_cfg(path: Path) -> list[ConfigType]:
    """The config types a ``.cfg`` file generates (it runs with ddes's generator)."""
    found: list[ConfigType] = []
    generator = generator_module(found)
    roslib = types.ModuleType("roslib")
    roslib.__dict__["load_manifest"] = lambda _package: None  # catkin: nothing to load
    real_import = builtins.__import__

    def cfg_import(name: str, globals: Any = None, locals: Any = None,  # noqa: A002
                   fromlist: Sequence[str] = (), level: int = 0) -> Any:
        if level == 0 and name in ("dynamic_reconfigure.parameter_generator_catkin",
                                   "dynamic_reconfigure.parameter_generator"):
            if fromlist:
                return generator
            top = types.ModuleType("dynamic_reconfigure")
            top.__dict__.update(parameter_generator_catkin=generator,
                                parameter_generator=generator)
            return top
        if level == 0 and name == "roslib":
            return roslib
        return real_import(name, globals, locals, fromlist, level)

    table = dict(builtins.__dict__)
    table["__import__"] = cfg_import
    scope: dict[str, Any] = {"__name__": "__main__", "__file__": str(path),
                             "__builtins__": table}
    argv = sys.argv
    try:
        code = compile(path.read_text(encoding="utf-8"), str(path), "exec")
        exec(code, scope)  # noqa: S102 - the package's own .cfg file, as catkin runs it
    except SystemExit:
        pass
    except Exception as exc:
        raise DdesValueError(f"{path}: the .cfg file failed: {type(exc).__name__}: {exc} "
                             "(ddes runs it with dynamic_reconfigure's ParameterGenerator API: "
                             "gen.add, gen.const, gen.enum, gen.add_group, gen.generate)"
                             ) from exc
    finally:
        sys.argv = argv
    return found


class _CfgModule(types.ModuleType):
    """``<pkg>.cfg``: the config types of a package's ``cfg/*.cfg`` files (``XConfig``)."""

    def __init__(self, package: str, folder: Path) -> None:
        super().__init__(f"{package}.cfg")
        self._folder = folder
        self._types: dict[str, ConfigType] | None = None

    def _generated(self) -> dict[str, ConfigType]:
        if self._types is None:
            table: dict[str, ConfigType] = {}
            for path in sorted(self._folder.glob("*.cfg")):
                for config_type in _run_cfg(path):
                    table[config_type.name] = config_type
            self._types = table
        return self._types

    def __getattr__(self, attr: str) -> Any:
        if attr.startswith("__"):
            raise AttributeError(attr)
        table = self._generated()
        if attr not in table:
            known = ", ".join(table) or "none"
            raise AttributeError(
                f"module '{self.__name__}' has no attribute '{attr}': the package's "
                f"{self._folder}/*.cfg files generate {known} (gen.generate(PACKAGE, node, "
                f"'{attr.removesuffix('Config')}') makes {attr})")
        setattr(self, attr, table[attr])
        return table[attr]


def cfg_module(world: World, package: str) -> types.ModuleType | None:
    """``<package>.cfg`` of the world's package path, or None without a ``cfg/`` folder."""
    table: dict[str, types.ModuleType | None] = world.extension(_CFG_KEY, _new_table)
    if package not in table:
        try:
            folder = world.rospack.get_path(package) / "cfg"
        except PackageNotFound:
            folder = None
        table[package] = _CfgModule(package, folder) if folder is not None and folder.is_dir() \
            else None
    return table[package]


def _new_table(_world: object) -> dict[str, types.ModuleType | None]:
    return {}


def resolve_import(world: World, top: str, rest: str,
                   fromlist: Sequence[str]) -> types.ModuleType | None:
    """What ``import top.rest`` gives a script, for ``dynamic_reconfigure.*`` and
    ``<pkg>.cfg``; None when it is not ours to resolve."""
    if top == "dynamic_reconfigure":
        this = sys.modules[__name__]
        if not rest:
            return this
        if rest not in _SUBMODULES:
            raise ModuleNotFoundError(
                f"No module named 'dynamic_reconfigure.{rest}' (ddes offers rospy scripts "
                "dynamic_reconfigure.server, .parameter_generator_catkin, .msg and .srv)",
                name=f"dynamic_reconfigure.{rest}")
        sub = parameter_generator_catkin if rest.startswith("parameter_generator") else \
            importlib.import_module(f"{__name__}.{rest}")
        if fromlist:
            return sub
        return this
    if rest == "cfg":
        module = cfg_module(world, top)
        if module is None or fromlist:
            for attr in fromlist if module is not None else ():
                if attr != "*":
                    try:
                        getattr(module, attr)
                    except AttributeError as exc:  # `from` would drop the text that says why
                        raise ImportError(f"cannot import name '{attr}' from '{top}.cfg': {exc}",
                                          name=f"{top}.cfg") from None
            return module
        package = types.ModuleType(top)
        package.__dict__["cfg"] = module
        return package
    return None
