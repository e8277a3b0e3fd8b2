"""``<param>`` and ``<rosparam>``: how launch files fill the parameter plan.

Names follow roslaunch: a ``<param>`` at launch or group level is set at
``ns_join(scope namespace, name)``; a ``~name`` there is kept for the
nodes declared later in the scope.  Inside a ``<node>`` every ``<param>``
is private to the node, even one written ``/abs`` (roslaunch prepends the
node's namespace to the name as written).  A ``<rosparam>`` loads YAML at
``ns_join(scope namespace, ns/param)``: dictionaries are unrolled into leaf
parameters, so loading ``{a: {b: 1}}`` sets ``/a/b`` and leaves its
siblings alone.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any

import yaml

from ddes.errors import ROSLaunchException
from ddes.graph.names import canonicalize_name, is_private, ns_join
from ddes.graph.yamlsafe import read_bounded
from ddes.launch.plan import LaunchPlan, RosparamCommand
from ddes.launch.scope import SCOPE_COST, LoadBudget
from ddes.launch.substitution import resolve_args
from ddes.launch.values import ParamValue, convert_value, load_rosparam_yaml, parse_bool_attr
from ddes.launch.xmltree import Element

if TYPE_CHECKING:
    from ddes.launch.loader import _Loader
    from ddes.launch.scope import Scope

__all__ = ["ParamLoader"]

_PARAM_ATTRS = ("name", "value", "type", "textfile", "binfile", "command")
#: The key marking a parameter in :class:`ParamLoader`'s tree (never a name part).
_IS_PARAM = None
_ROSPARAM_ATTRS = ("command", "ns", "file", "param", "subst_value")


class ParamLoader:
    """Adds parameters to a plan with roslaunch's naming and override rules.

    While a node is being read, :attr:`sink` collects the parameters it
    sets, for :attr:`~ddes.launch.plan.NodeSpec.params`.
    """

    def __init__(self, plan: LaunchPlan, budget: LoadBudget | None = None) -> None:
        self.plan = plan
        self.budget = budget if budget is not None else LoadBudget()
        self.sink: dict[str, ParamValue] | None = None
        #: The names in the plan as a tree of their parts (``_IS_PARAM`` marks a parameter),
        #: so a name's parents are found in one walk, not one slice per level.
        self._tree: dict[str | None, Any] = {}

    def add(self, key: str, value: ParamValue) -> None:
        """Set ``key`` in the plan (later values win; the first position is kept)."""
        key = canonicalize_name(key)
        self.budget.charge(len(key), f"setting parameter {key[:80]}")
        parts = [p for p in key.split("/") if p]
        node = self._tree
        if _IS_PARAM in node:
            self._conflict(key, "/")
        for i, part in enumerate(parts):
            child = node.get(part)
            if child is None:
                self.budget.charge(SCOPE_COST, f"setting parameter {key[:80]}")
                child = node[part] = {}
            node = child
            if i < len(parts) - 1 and _IS_PARAM in node:
                self._conflict(key, "/" + "/".join(parts[:i + 1]))
        node[_IS_PARAM] = True
        self.plan.params[key] = value
        if self.sink is not None:
            self.sink[key] = value

    def _conflict(self, key: str, parent: str) -> None:
        warning = f"parameter [{key}] conflicts with parent parameter [{parent}]"
        self.budget.charge(len(warning), f"setting parameter {key[:80]}")
        self.plan.warnings.append(warning)

    def add_tree(self, name: str, value: ParamValue) -> None:
        """Set ``value`` at ``name``, unrolling dictionaries into leaf parameters."""
        if not name:
            raise ROSLaunchException("no parameter name specified")
        if name == "/" and not isinstance(value, dict):
            raise ROSLaunchException(
                "Cannot load non-dictionary types into global namespace '/'; set param=\"...\""
            )
        if isinstance(value, dict):
            for k, v in value.items():
                if not isinstance(k, str):
                    raise ROSLaunchException(
                        f"YAML key {k!r} under [{name}] is not a string; parameter names are "
                        "strings (quote the key)"
                    )
                self.add_tree(ns_join(name, k), v)
        else:
            self.add(name, value)

    # -- tags ------------------------------------------------------------------------------

    def param_tag(self, ld: _Loader, el: Element, scope: Scope, *, force_local: bool) -> None:
        """One ``<param>`` (roslaunch ``_param_tag`` and ``Loader.param_value``)."""
        ld.check_attrs(el, _PARAM_ATTRS)
        ptype = (el.attrs.get("type") or "auto").lower().strip()
        value, textfile, binfile, command = (ld.opt(el, scope, a) for a in
                                             ("value", "textfile", "binfile", "command"))
        given = [v for v in (value, textfile, binfile, command) if v is not None]
        if len(given) != 1:
            raise ROSLaunchException(
                "<param> tag must have one and only one of value/textfile/binfile."
            )
        if "name" not in el.attrs:
            raise ROSLaunchException("<param> tag is missing required attribute: 'name'; add "
                                     "name=\"...\"")
        name = resolve_args(el.attrs["name"].strip(), scope.subst)  # stripped, then resolved
        if not name:
            raise ROSLaunchException("parameter name must be non-empty")
        result: ParamValue
        if command is not None:
            raise ROSLaunchException(
                f"command=\"{command}\" is not supported: ddes runs no external processes. "
                "Run the command once and load its output with textfile=\"...\" "
                "(e.g. xacro's URDF), or write the value with value=\"...\""
            )
        if value is not None:
            result = convert_value(value.strip(), ptype)
        elif textfile is not None:
            result = convert_value(_read_text(textfile, "textfile"), ptype)
        else:
            assert binfile is not None
            result = _read_bytes(binfile, "binfile")
        key = canonicalize_name(name)
        if is_private(key) or force_local:
            scope.add_private_param(key, result)
        else:
            self.add(ns_join(scope.ns, name), result)

    def rosparam_tag(self, ld: _Loader, el: Element, scope: Scope) -> None:
        """One ``<rosparam>`` (roslaunch ``_rosparam_tag`` and ``Loader.load_rosparam``)."""
        ld.check_attrs(el, _ROSPARAM_ATTRS)
        cmd, ns, file_, param, subst = (ld.opt(el, scope, a) for a in _ROSPARAM_ATTRS)
        subst_value = parse_bool_attr(subst, False, "subst_value")
        param = ns_join(ns or "", param or "")
        cmd = cmd or "load"
        if cmd not in ("load", "dump", "delete"):
            raise ROSLaunchException("command must be 'load', 'dump', or 'delete'")
        if file_ is not None:
            if cmd == "load" and not os.path.exists(file_):
                raise ROSLaunchException(f"file does not exist [{file_}]")
            if cmd == "delete":
                raise ROSLaunchException("'file' attribute is invalid with 'delete' command.")
        full = ns_join(scope.ns, param) if param else scope.ns
        source = f"{scope.filename or '<string>'}:{el.line}"
        if cmd == "dump":
            if not file_:
                raise ROSLaunchException("<rosparam command=\"dump\"> needs file=\"...\"")
            self.plan.rosparam_commands.append(
                RosparamCommand("dump", canonicalize_name(full), file_, source))
            return
        if cmd == "delete":
            self.plan.rosparam_commands.append(
                RosparamCommand("delete", canonicalize_name(full), None, source))
            return
        text = _read_text(file_, "file") if file_ else el.text
        if subst_value:
            text = resolve_args(text, scope.subst)
        try:
            data = load_rosparam_yaml(text)
        except yaml.YAMLError as exc:
            where = f"file {file_} contains invalid YAML" if file_ else "Error within YAML block"
            raise ROSLaunchException(f"{where}: {exc}") from None
        if not param and not isinstance(data, dict):
            raise ROSLaunchException(
                "'param' attribute must be set for non-dictionary values; add param=\"name\""
            )
        self.plan.rosparam_loads.append((canonicalize_name(full), data))
        self.add_tree(full, data)


def _read_bytes(path: str, what: str) -> bytes:
    """A file for ``textfile=``/``binfile=``/``<rosparam file=>``: regular, at most 16 MiB.

    ``/dev/zero``, FIFOs, directories and devices are refused before they are opened.
    """
    if not os.path.lexists(path):
        raise ROSLaunchException(
            f"cannot read {what} [{path}]: No such file or directory; check the path "
            "($(find pkg)/config/x.yaml names a file inside a package)"
        )
    return read_bounded(path, what=what, error=ROSLaunchException)


def _read_text(path: str, what: str) -> str:
    data = _read_bytes(path, what)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ROSLaunchException(f"{what} [{path}] is not UTF-8 text: {exc}") from None
