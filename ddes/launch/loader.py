"""Load a roslaunch XML file into a :class:`~ddes.launch.plan.LaunchPlan`.

The loader follows ``roslaunch/xmlloader.py`` and ``roslaunch/loader.py``
tag by tag (see ``docs/launch.md`` for the supported XML).  It never runs
anything: it resolves substitutions, namespaces, remaps and parameters and
returns plain data.

Where roslaunch only *warns* (an unknown tag or attribute, a child tag it
does not understand) ddes raises :class:`~ddes.errors.ROSLaunchException`,
so a typo never silently drops part of a launch file.  Every error names
the file, the line and the element, plus the ``<include>`` chain that led
there.  Other deliberate differences: ``<param command=...>`` is rejected
(ddes runs no external processes); ``launch-prefix`` and ``<machine>`` are
recorded and ignored with a warning; ``<test>`` is checked and ignored (as
plain roslaunch ignores it) with a warning; command-line args that the
top-level file does not declare are an error ("unused args"), as they are
for ``<include>``.

The loader never recurses (``<group>`` and ``<include>`` push their elements
on its own stack), so a deep file costs memory and work, which the budgets
bound (:data:`MAX_NESTING`, :data:`MAX_INCLUDE_DEPTH`, :data:`MAX_LOAD_FILES`,
:data:`MAX_LOAD_BYTES`, ``ddes.launch.scope.MAX_LOAD_WORK`` and
``ddes.launch.xmltree.MAX_XML_ELEMENTS``), each above what roslaunch itself
reads before its ``RecursionError``.
"""

from __future__ import annotations

import os
import random
import shlex
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, fields

from ddes.errors import DdesValueError, ResourceLimitError, ROSLaunchException
from ddes.graph.names import canonicalize_name, get_ros_namespace, is_legal_name
from ddes.graph.yamlsafe import read_bounded
from ddes.launch.params import ParamLoader
from ddes.launch.plan import TEST_TIME_LIMIT_DEFAULT, LaunchPlan, NodeSpec, TestSpec
from ddes.launch.scope import ENTRY_COST, LoadBudget, Scope
from ddes.launch.substitution import (
    CostlyLaunchExpression,
    LaunchLimitError,
    PackageFinder,
    SubstitutionContext,
    UnsafeLaunchExpression,
    resolve_args,
)
from ddes.launch.values import ParamValue, convert_value, parse_bool_attr, parse_float_attr
from ddes.launch.xmltree import Element, ElementBudget, parse_xml
from ddes.rospack import RosPack

__all__ = ["MAX_INCLUDE_DEPTH", "MAX_LOAD_BYTES", "MAX_LOAD_FILES", "MAX_NESTING", "chain_text",
           "load_launch"]

#: How deep ``<include>`` may nest (a file including itself would recurse for ever); roslaunch
#: dies with RecursionError near 330 (three Python calls per level, on a 1000-frame limit).
MAX_INCLUDE_DEPTH = 1000
#: How deep ``<group>`` and ``<include>`` may nest in all, across files.  The loader keeps its
#: own stack (no Python recursion), so this bounds only the memory of the open scopes; what a
#: deep file costs is bounded by the budgets (``ddes.launch.scope.MAX_LOAD_WORK``, the
#: elements of ``ddes.launch.xmltree.MAX_XML_ELEMENTS``).  roslaunch dies with RecursionError
#: near 990 empty groups (490 with a node inside).
MAX_NESTING = 5000
#: The launch XML one load may read in all, the file and its includes (each time one is read).
MAX_LOAD_BYTES = 64 << 20
#: How many launch files one load may read, counting an include each time it is read (a file
#: that includes another one 20 times, which includes another 20 times ..., multiplies them).
MAX_LOAD_FILES = 5000
#: How many ``included from`` lines an error shows at each end of a long include chain.
_CHAIN_SHOWN = 10


def chain_text(chain: Sequence[str]) -> str:
    """The ``included from`` lines of an error, innermost first; a chain longer than 20 shows
    its 10 innermost and 10 outermost files around a count of the rest."""
    lines = [f"\n  included from {c}" for c in reversed(chain)]
    if len(lines) > 2 * _CHAIN_SHOWN:
        skipped = len(lines) - 2 * _CHAIN_SHOWN
        lines[_CHAIN_SHOWN:-_CHAIN_SHOWN] = [f"\n  ... {skipped} more includes ..."]
    return "".join(lines)


@dataclass
class _Enter:
    """What a ``<group>`` or ``<include>`` asks the loader to read next: ``elements`` in
    ``scope``, then ``done()`` (the include's unused-args check)."""

    elements: list[Element]
    scope: Scope
    done: Callable[[], None] | None = None


@dataclass
class _Level:
    """One open level of the loader's stack: the elements of a <launch>, <group> or file."""

    elements: list[Element]
    scope: Scope
    done: Callable[[], None] | None = None
    index: int = 0

_NODE_ATTRS = ("pkg", "type", "machine", "name", "args", "output", "respawn", "respawn_delay",
               "cwd", "ns", "clear_params", "launch-prefix", "required")
_TEST_ATTRS = _NODE_ATTRS + ("test-name", "time-limit", "retry")
_ATTRS: dict[str, tuple[str, ...]] = {
    "launch": ("deprecated",),
    "arg": ("name", "value", "default", "doc"),
    "group": ("ns", "clear_params"),
    "include": ("file", "ns", "clear_params", "pass_all_args"),
    "remap": ("from", "to"),
    "env": ("name", "value"),
    "machine": ("name", "address", "env-loader", "ssh-port", "user", "password", "default",
                "timeout"),
}


def load_launch(
    source: str | os.PathLike[str],
    args: Mapping[str, str] | None = None,
    rospack: PackageFinder | None = None,
    *,
    environ: Mapping[str, str] | None = None,
    anon_seed: int | random.Random = 0,
) -> LaunchPlan:
    """Load a launch file (a path, or XML text starting with ``<``) into a plan.

    ``args`` are the ``name:=value`` command-line args (``__ns`` sets the
    root namespace, as roslaunch).  ``rospack`` resolves ``$(find)``
    (default: ``RosPack()``).  ``environ`` is what ``$(env)``/``$(optenv)``
    read (default ``os.environ``).  ``anon_seed`` seeds ``$(anon)`` names.
    """
    for k, v in (args or {}).items():
        if not isinstance(k, str) or not isinstance(v, str):
            raise ROSLaunchException(
                f"launch args are strings, as on the command line: got {k!r}: {v!r}; "
                f"pass {k}:={v!s} as str"
            )
    loader = _Loader(rospack if rospack is not None else RosPack(),
                     os.environ if environ is None else environ,
                     anon_seed if isinstance(anon_seed, random.Random)
                     else random.Random(anon_seed))
    return loader.load_root(source, dict(args or {}))


class _Loader:
    """One load: the plan being filled and the state shared by all scopes."""

    def __init__(self, rospack: PackageFinder, environ: Mapping[str, str],
                 anon: random.Random) -> None:
        self.rospack = rospack
        self.environ = environ
        self.anon = anon
        self.plan = LaunchPlan()
        self.budget = LoadBudget()
        self.elements = ElementBudget()
        self.bytes_read = 0
        self.files_read = 0
        self.params = ParamLoader(self.plan, self.budget)
        self._node_names: set[str] = set()
        self._machines: list[str] = []
        self._located: BaseException | None = None

    # -- errors ----------------------------------------------------------------------------

    @contextmanager
    def at(self, el: Element, scope: Scope) -> Iterator[None]:
        """Re-raise errors from inside as ROSLaunchException naming file, line and element."""
        try:
            yield
        except (ROSLaunchException, DdesValueError) as exc:
            if exc is self._located:
                raise
            where = f"{scope.filename or '<string>'}:{el.line}"
            err = _located_kind(exc)(f"{where}: {el.start_tag()}: {exc}{chain_text(scope.chain)}")
            self._located = err
            raise err from None

    def opt(self, el: Element, scope: Scope, name: str) -> str | None:
        """The resolved attribute ``name``, or None when absent."""
        raw = el.attrs.get(name)
        return None if raw is None else resolve_args(raw, scope.subst)

    def req(self, el: Element, scope: Scope, name: str) -> str:
        """The resolved required attribute ``name``."""
        if name not in el.attrs:
            raise ROSLaunchException(
                f"<{el.tag}> tag is missing required attribute: '{name}'; add {name}=\"...\""
            )
        return resolve_args(el.attrs[name], scope.subst)

    def check_attrs(self, el: Element, allowed: Sequence[str]) -> None:
        """Reject attributes the tag does not have (roslaunch only warns)."""
        for a in el.attrs:
            if a not in allowed and a not in ("if", "unless"):
                raise ROSLaunchException(
                    f"unknown <{el.tag}> attribute '{a}'; <{el.tag}> takes "
                    f"{', '.join(allowed)}, if, unless"
                )

    def enabled(self, el: Element, scope: Scope) -> bool:
        """Evaluate ``if``/``unless`` (true/false/1/0 after substitution)."""
        with self.at(el, scope):
            if_val, unless_val = self.opt(el, scope, "if"), self.opt(el, scope, "unless")
            if if_val is not None and unless_val is not None:
                raise ROSLaunchException("cannot set both 'if' and 'unless' on the same tag")
            if if_val is not None:
                return bool(convert_value(if_val, "bool"))
            if unless_val is not None:
                return not convert_value(unless_val, "bool")
            return True

    # -- files -------------------------------------------------------------------------------

    def read_launch(self, path: str, site: tuple[Element, Scope] | None = None,
                    chain: tuple[str, ...] = ()) -> Element:
        """Parse launch file ``path`` (included at ``site``); its root must be <launch>."""
        included = chain_text(chain)
        error: type[ROSLaunchException] = ROSLaunchException
        try:
            self.files_read += 1
            if self.files_read > MAX_LOAD_FILES:
                raise LaunchLimitError(
                    f"reading {path} would make more than {MAX_LOAD_FILES} launch files read in "
                    "one load (ddes.launch.loader.MAX_LOAD_FILES; every include counts each time "
                    "it is read); include files fewer times")
            if not os.path.lexists(path):
                raise FileNotFoundError(path)
            # A regular file of at most 16 MiB: /dev/zero, FIFOs and directories are
            # refused before they are opened.
            data = read_bounded(path, what="launch file", error=ROSLaunchException)
            self.bytes_read += len(data)
            if self.bytes_read > MAX_LOAD_BYTES:
                raise LaunchLimitError(
                    f"reading {path} makes {self.bytes_read} bytes of launch XML in one load, "
                    f"more than {MAX_LOAD_BYTES} (ddes.launch.loader.MAX_LOAD_BYTES; every "
                    "include counts each time it is read); include large files fewer times")
        except FileNotFoundError:
            msg = (f"launch file not found: {path}. Check the path; "
                   "$(find pkg)/launch/x.launch names a file inside a package")
        except (ROSLaunchException, ResourceLimitError) as exc:
            msg = str(exc)
            if isinstance(exc, ResourceLimitError):
                error = LaunchLimitError
        else:
            try:
                return self.parse_root(data, path)
            except ROSLaunchException as exc:
                raise _located_kind(exc)(str(exc) + included) from None
        msg += included if site is None else ""
        if site is not None:
            with self.at(*site):
                raise error(msg)
        raise error(msg)

    def parse_root(self, data: bytes, filename: str) -> Element:
        """Parse XML bytes and check the root element."""
        try:
            root = parse_xml(data, filename, self.elements)
        except ResourceLimitError as exc:
            raise LaunchLimitError(str(exc)) from None
        if root.tag != "launch":
            raise ROSLaunchException(
                f"{filename}:{root.line}: Invalid roslaunch XML syntax: no root <launch> tag "
                f"(found <{root.tag}>)"
            )
        return root

    def launch_tag(self, el: Element, scope: Scope) -> None:
        """The <launch> tag's own attributes."""
        with self.at(el, scope):
            self.check_attrs(el, _ATTRS["launch"])
            if "if" in el.attrs or "unless" in el.attrs:
                raise ROSLaunchException(
                    "if/unless on <launch> has no effect in roslaunch; wrap the content in "
                    "<group if=\"...\"> instead"
                )
            deprecated = el.attrs.get("deprecated")
            if deprecated:
                self.plan.warnings.append(f"[{scope.filename or '<string>'}] DEPRECATED: "
                                          f"{deprecated}")

    # -- entry -------------------------------------------------------------------------------

    def load_root(self, source: str | os.PathLike[str], args: dict[str, str]) -> LaunchPlan:
        """Load the top-level file with the command-line ``args``."""
        text = source if isinstance(source, str) and source.lstrip().startswith("<") else None
        filename = None if text is not None else os.fspath(source)
        try:
            ns = get_ros_namespace(self.environ, [f"__ns:={args['__ns']}"] if "__ns" in args
                                   else [])
        except DdesValueError as exc:
            raise ROSLaunchException(f"invalid root namespace: {exc}") from None
        subst = SubstitutionContext(self.rospack, self.environ, self.anon, filename, dict(args))
        scope = Scope(ns=ns, subst=subst, budget=self.budget)
        if text is not None:
            root = self.parse_root(text.encode("utf-8"), "<string>")
        else:
            assert filename is not None
            root = self.read_launch(filename)
            self.plan.files.append(filename)
        self.launch_tag(root, scope)
        self.recurse(root.children, scope)
        unused = sorted(a for a in args if a not in scope.arg_names and not a.startswith("__"))
        if unused:
            raise ROSLaunchException(
                f"unused args [{', '.join(unused)}] for [{filename or '<string>'}]: the file "
                "declares no such <arg>. Check the spelling, or declare it with "
                "<arg name=\"...\" default=\"...\"/>"
            )
        self.plan.args = {a: scope.subst.args[a] for a in scope.arg_names
                          if a in scope.subst.args}
        return self.plan

    def recurse(self, elements: list[Element], scope: Scope) -> None:
        """Process the tags of a <launch>, <group> or included file, in order.

        A <group> or <include> does not call this again: it returns an :class:`_Enter` and
        its elements go on the loader's own stack, so nesting costs memory, never Python
        stack (roslaunch recurses, and dies with RecursionError near 990 levels).
        """
        handlers: dict[str, Callable[[Element, Scope], _Enter | None]] = {
            "arg": self._arg, "group": self.group_tag, "node": self.node_tag,
            "test": self.test_tag, "param": self.param_tag, "rosparam": self.rosparam_tag,
            "remap": self.remap_tag, "include": self.include_tag, "env": self.env_tag,
            "machine": self.machine_tag,
        }
        stack = [_Level(elements, scope)]
        while stack:
            level = stack[-1]
            if level.index >= len(level.elements):
                stack.pop()
                if level.done is not None:
                    level.done()
                continue
            el = level.elements[level.index]
            level.index += 1
            scope = level.scope
            if el.tag == "master":
                self.plan.warnings.append("ignoring defunct <master /> tag")
                continue
            handler = handlers.get(el.tag)
            if handler is None:
                with self.at(el, scope):
                    raise ROSLaunchException(
                        f"unrecognized tag <{el.tag}>; launch files contain "
                        f"{', '.join(sorted(handlers))}"
                    )
                continue  # pragma: no cover - at() always raises here
            if not self.enabled(el, scope):
                continue
            enter = handler(el, scope)
            if enter is None:
                continue
            if len(stack) >= MAX_NESTING:
                inner = enter.scope
                raise LaunchLimitError(
                    f"{inner.filename or '<string>'}: <group>s and <include>s nest more than "
                    f"{MAX_NESTING} deep in all (ddes.launch.loader.MAX_NESTING, counting "
                    "across included files); flatten the groups" + chain_text(inner.chain))
            stack.append(_Level(enter.elements, enter.scope, enter.done))

    def _arg(self, el: Element, scope: Scope) -> None:
        self.arg_tag(el, scope)

    # -- simple tags ------------------------------------------------------------------------

    def arg_tag(self, el: Element, scope: Scope) -> str:
        """<arg name value|default doc>; returns the name."""
        with self.at(el, scope):
            self.check_attrs(el, _ATTRS["arg"])
            name = self.req(el, scope, "name")
            value, default = self.opt(el, scope, "value"), self.opt(el, scope, "default")
            self.opt(el, scope, "doc")
            if value is not None and default is not None:
                raise ROSLaunchException(
                    "<arg> tag must have one and only one of value/default; value= is a "
                    "constant, default= can be overridden"
                )
            scope.add_arg(name, value=value, default=default)
        return name

    def remap_tag(self, el: Element, scope: Scope, target: Scope | None = None) -> None:
        """<remap from to>: into ``target`` (a node's scope) or ``scope``."""
        with self.at(el, scope):
            self.check_attrs(el, _ATTRS["remap"])
            src, dst = self.req(el, scope, "from"), self.req(el, scope, "to")
            (target or scope).add_remap(src, dst)

    def env_tag(self, el: Element, scope: Scope) -> None:
        """<env name value>: for the nodes of the scope."""
        with self.at(el, scope):
            self.check_attrs(el, _ATTRS["env"])
            name, value = self.req(el, scope, "name"), self.req(el, scope, "value")
            if not name:
                raise ROSLaunchException("'name' attribute must be non-empty")
            scope.env.append((name, value))

    def machine_tag(self, el: Element, scope: Scope) -> None:
        """<machine>: checked, recorded by name, otherwise ignored."""
        with self.at(el, scope):
            legacy = [a for a in ("ros-root", "ros-package-path", "ros-ip", "ros-hostname")
                      if a in el.attrs]
            if legacy:
                raise ROSLaunchException(
                    "<machine>: ros-* attributes are not supported since ROS Fuerte. "
                    "Please use env-loader instead"
                )
            self.check_attrs(el, _ATTRS["machine"])
            name = self.req(el, scope, "name")
            self.req(el, scope, "address")
            if el.children:
                raise ROSLaunchException("<machine> takes no child tags")
            self._machines.append(name)
            self.plan.warnings.append(
                f"<machine name=\"{name}\"> ignored: ddes runs every node in one simulated "
                "process"
            )

    def group_tag(self, el: Element, scope: Scope) -> _Enter:
        """<group ns clear_params>: a child scope with a copy of the ~params."""
        with self.at(el, scope):
            self.check_attrs(el, _ATTRS["group"])
            child = self.ns_clear_params(el, scope)
            self.budget.charge(ENTRY_COST * len(child.private_params), "copying ~params")
            child.private_params = dict(child.private_params)
        return _Enter(el.children, child)

    def ns_clear_params(self, el: Element, scope: Scope, node_name: str | None = None) -> Scope:
        """The child scope of a tag with ``ns``/``clear_params`` (roslaunch rules)."""
        ns = None
        if "ns" in el.attrs:
            ns = self.opt(el, scope, "ns")
            if not ns:
                raise ROSLaunchException(f"<{el.tag}> tag has an empty 'ns' attribute")
        child = scope.child(ns)
        clear = self.opt(el, scope, "clear_params")
        if clear and parse_bool_attr(clear, False, "clear_params"):
            if el.tag == "node":
                if not node_name:
                    raise ROSLaunchException(
                        "<node> tag must have a 'name' attribute to use 'clear_params' attribute"
                    )
                self.plan.clear_params.append(child.ns + node_name + "/")
            elif not ns:
                raise ROSLaunchException(
                    "'ns' attribute must be set in order to use 'clear_params'"
                )
            else:
                self.plan.clear_params.append(child.ns)
        return child

    # -- params ------------------------------------------------------------------------------

    def param_tag(self, el: Element, scope: Scope, *, force_local: bool = False) -> None:
        """<param>: global/relative names go to the plan, ~names (or all, in a node) to nodes."""
        with self.at(el, scope):
            self.params.param_tag(self, el, scope, force_local=force_local)

    def rosparam_tag(self, el: Element, scope: Scope) -> None:
        """<rosparam command file param ns subst_value>."""
        with self.at(el, scope):
            self.params.rosparam_tag(self, el, scope)

    # -- nodes -------------------------------------------------------------------------------

    def node_tag(self, el: Element, scope: Scope) -> None:
        """<node>: a NodeSpec plus its private parameters."""
        self.node_or_test(el, scope, is_test=False)

    def test_tag(self, el: Element, scope: Scope) -> None:
        """<test>: checked like roslaunch (its params are set), the test itself ignored."""
        self.node_or_test(el, scope, is_test=True)

    def node_or_test(self, el: Element, scope: Scope, *, is_test: bool) -> None:
        with self.at(el, scope):
            self.check_attrs(el, _TEST_ATTRS if is_test else _NODE_ATTRS)
            if is_test:
                given = self.opt(el, scope, "name")  # resolved first, as roslaunch does
                test_name, time_limit, retry = self.test_attrs(el, scope)
                name = given or test_name
            else:
                name = self.req(el, scope, "name")
            if not name:
                raise ROSLaunchException("node name must be non-empty")
            if "/" in name:
                raise ROSLaunchException(
                    "node name cannot contain a namespace; use ns=\"...\" or a <group ns=...>"
                )
            if not is_legal_name(name):
                self.plan.warnings.append(
                    f"WARN: illegal <{el.tag}> name '{name}' (http://ros.org/wiki/Names); "
                    "this will likely cause problems with other ROS tools"
                )
            child = self.ns_clear_params(el, scope, node_name=name)
            param_scope = child.child(name)
            param_scope.private_params = {}
            pkg, node_type = self.req(el, scope, "pkg"), self.req(el, scope, "type")
            o = {a: self.opt(el, scope, a) for a in ("machine", "args", "output", "respawn",
                                                     "respawn_delay", "cwd", "launch-prefix",
                                                     "required")}
            required = parse_bool_attr(o["required"], False, "required")
            respawn = parse_bool_attr(o["respawn"], False, "respawn")
            respawn_delay = parse_float_attr(o["respawn_delay"], 0.0, "respawn_delay")
            remap_scope, env_scope = scope.child(""), scope.child("")
        own: dict[str, ParamValue] = {}
        self.params.sink = own
        for c in el.children:
            tag = c.tag.lower()
            where = {"remap": scope, "param": param_scope, "rosparam": param_scope,
                     "env": env_scope}.get(tag)
            if where is None:
                with self.at(c, scope):
                    raise ROSLaunchException(
                        f"unrecognized <{c.tag}> child tag in <{el.tag}>; a node takes "
                        "remap, param, rosparam and env"
                    )
                continue  # pragma: no cover - at() always raises here
            if not self.enabled(c, where):
                continue
            if tag == "remap":
                self.remap_tag(c, scope, remap_scope)
            elif tag == "param":
                self.param_tag(c, param_scope, force_local=True)
            elif tag == "rosparam":
                self.rosparam_tag(c, param_scope)
            else:
                self.env_tag(c, env_scope)
        with self.at(el, scope):
            inherited = list(scope.private_params.items())
            own_private = list(param_scope.private_params.items())
            self.budget.charge(ENTRY_COST * (len(inherited) + len(own_private)),
                               f"setting the ~params of node {name}")
            for key, value in inherited + own_private:
                self.params.add(param_scope.ns + (key[1:] if key.startswith("~") else key),
                                value)
            self.params.sink = None
            spec = self.node_spec(el, scope, o, pkg, node_type, name, child.ns,
                                  respawn, respawn_delay, required)
            if is_test:
                warning = (f"<test test-name=\"{el.attrs.get('test-name', '')}\"> ignored: "
                           "tests run under rostest, not roslaunch (its parameters were set)")
                self.plan.warnings.append(warning)
                test = TestSpec(**{f.name: getattr(spec, f.name) for f in fields(NodeSpec)},
                                test_name=test_name, time_limit=time_limit, retry=retry,
                                warning=warning)
                test.required = False  # roslaunch's Test drops required
                test.remappings = remap_scope.remap_args()
                test.env = list(env_scope.env)
                test.params = own
                self.plan.tests.append(test)
                return
            spec.remappings = remap_scope.remap_args()
            spec.env = list(env_scope.env)
            spec.params = own
            if spec.full_name in self._node_names:
                raise ROSLaunchException(
                    f"roslaunch file contains multiple nodes named [{spec.full_name}]. "
                    "Please check all <node> 'name' attributes to make sure they are unique. "
                    "Also check that $(anon id) use different ids"
                )
            self._node_names.add(spec.full_name)
            self.plan.nodes.append(spec)

    def test_attrs(self, el: Element, scope: Scope) -> tuple[str, float, int]:
        """<test>-only checks; returns test-name, time-limit and retry."""
        for a in ("respawn", "respawn_delay", "output"):
            if a in el.attrs:
                raise ROSLaunchException(f"<test> tags cannot have '{a}' attribute")
        test_name = self.req(el, scope, "test-name")
        limit, retry = self.opt(el, scope, "time-limit"), self.opt(el, scope, "retry")
        seconds, count = TEST_TIME_LIMIT_DEFAULT, 0
        if limit:
            try:
                seconds = float(limit)
            except ValueError:
                raise ROSLaunchException(f"'time-limit' must be a number: [{limit}]") from None
            if not seconds > 0.0:
                raise ROSLaunchException("'time-limit' must be a positive number")
        if retry:
            try:
                count = int(retry)
            except ValueError:
                raise ROSLaunchException(f"'retry' must be a number: [{retry}]") from None
        return test_name, seconds, count

    def node_spec(self, el: Element, scope: Scope, o: dict[str, str | None], pkg: str,
                  node_type: str, name: str, ns: str, respawn: bool, respawn_delay: float,
                  required: bool) -> NodeSpec:
        """Validate the node's attributes (roslaunch ``Node.__init__``) into a NodeSpec."""
        if respawn and required:
            raise ROSLaunchException("respawn and required cannot both be set to true")
        if not pkg.strip():
            raise ROSLaunchException("package must be non-empty")
        if not node_type.strip():
            raise ROSLaunchException("type must be non-empty")
        output, cwd = o["output"], o["cwd"]
        if cwd == "ros_home":
            cwd = "ROS_HOME"
        if output not in ("log", "screen", None):
            raise ROSLaunchException("output must be one of 'log', 'screen'")
        if cwd not in ("ROS_HOME", "node", None):
            raise ROSLaunchException("cwd must be one of 'ROS_HOME', 'node'")
        machine = o["machine"] or None
        if machine and machine not in self._machines:
            raise ROSLaunchException(
                f"unknown machine [{machine}]; declare it with <machine name=\"{machine}\" "
                "address=\"...\"/> first (ddes ignores machines anyway)"
            )
        prefix = o["launch-prefix"] or None
        if prefix:
            self.plan.warnings.append(
                f"launch-prefix=\"{prefix}\" of node {name} ignored: ddes runs no processes"
            )
        try:
            argv = shlex.split(o["args"] or "", posix=True)
        except ValueError as exc:
            raise ROSLaunchException(f"cannot split args=\"{o['args']}\": {exc}") from None
        return NodeSpec(
            pkg=pkg, type=node_type, name=name, namespace=_collapse(ns), args=argv,
            output=output, respawn=respawn, respawn_delay=respawn_delay, required=required,
            cwd=cwd, launch_prefix=prefix, machine=machine,
            source=f"{scope.filename or '<string>'}:{el.line}", include_chain=scope.chain,
        )

    # -- include -----------------------------------------------------------------------------

    def include_tag(self, el: Element, scope: Scope) -> _Enter:
        """<include file ns clear_params pass_all_args> with child <arg>/<env>."""
        with self.at(el, scope):
            self.check_attrs(el, _ATTRS["include"])
            inc = self.req(el, scope, "file")
            pass_all = parse_bool_attr(self.opt(el, scope, "pass_all_args"), False,
                                       "pass_all_args")
            child = self.ns_clear_params(el, scope)
            child.arg_names = {}
            child.include_args = {}
            if pass_all:
                for name, value in scope.subst.args.items():
                    child.add_arg(name, value=value)
                child.pass_all_args = True
        sites: dict[str, Element] = {}
        for c in el.children:
            if c.tag.lower() not in ("arg", "env"):
                with self.at(c, scope):
                    raise ROSLaunchException(
                        f"unrecognized <{c.tag}> tag in <include>; an include takes arg and env"
                    )
            if not self.enabled(c, child):
                continue
            if c.tag.lower() == "arg":
                sites[self.arg_tag(c, child)] = c
            else:
                self.env_tag(c, child)
        passed = child.include_args or {}
        missing = [a for a in child.arg_names if a not in passed]
        if missing:
            with self.at(sites.get(missing[0], el), scope):
                raise ROSLaunchException(
                    f"include args must have declared values: give <arg name=\"{missing[0]}\"> "
                    "a value= (or a default=) inside <include>"
                )
        with self.at(el, scope):
            args_passed = list(passed)
            child.arg_names = {}
            child.include_args = None
            child.subst = SubstitutionContext(self.rospack, self.environ, self.anon, inc,
                                              dict(passed), expansion=scope.subst.expansion)
            self.budget.charge(ENTRY_COST * (len(scope.chain) + 1), "including a file")
            child.chain = scope.chain + (f"{scope.filename or '<string>'}:{el.line}",)
            if len(child.chain) > MAX_INCLUDE_DEPTH:
                raise LaunchLimitError(
                    f"includes nested more than {MAX_INCLUDE_DEPTH} deep "
                    "(ddes.launch.loader.MAX_INCLUDE_DEPTH): does a file include itself? Guard "
                    "a recursive include with if=\"...\""
                )
        root = self.read_launch(inc, (el, scope), child.chain)
        self.plan.files.append(inc)
        self.launch_tag(root, child)

        def done() -> None:
            if pass_all:
                return
            unused = [a for a in args_passed if a not in child.arg_names]
            if unused:
                with self.at(sites.get(unused[0], el), scope):
                    raise ROSLaunchException(
                        f"unused args [{', '.join(unused)}] for include of [{inc}]; the "
                        "included file declares no such <arg> (check the spelling)"
                    )

        return _Enter(root.children, child, done)


def _located_kind(exc: BaseException) -> type[ROSLaunchException]:
    """The class of the located error for ``exc``: a refusal or a limit keeps its kind."""
    if isinstance(exc, UnsafeLaunchExpression):
        return UnsafeLaunchExpression
    if isinstance(exc, CostlyLaunchExpression):
        return CostlyLaunchExpression
    if isinstance(exc, ResourceLimitError):
        return LaunchLimitError
    return ROSLaunchException


def _collapse(ns: str) -> str:
    """roslaunch ``Node``: namespace global with a trailing slash and no ``//``."""
    return canonicalize_name(ns).rstrip("/") + "/" if ns != "/" else "/"

