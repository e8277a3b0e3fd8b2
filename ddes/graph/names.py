"""ROS graph resource names, resolved exactly as ``rosgraph.names`` does.

A name is *global* (``/a/b``), *relative* (``a/b``, resolved in the node's
namespace) or *private* (``~a``, resolved under the node's own name).
:func:`resolve_name` has rosgraph's signature and results: its second
argument is the *node's fully-qualified name* (the caller id), not a
namespace.  Relative names resolve in ``namespace(node_name)``; private names
under ``node_name`` itself; the empty name resolves to the node's namespace.
Remappings are applied *after* resolution, as an exact match on the resolved
name (RC ``tools/rosgraph/src/rosgraph/names.py``).

Command-line arguments follow rospy: ``from:=to`` remaps, ``_param:=value``
sets a private parameter (the value parsed as YAML), ``__name:=``,
``__ns:=``, ``__master:=``, ``__ip:=``, ``__hostname:=``, ``__log:=`` are
special.  :class:`NameResolver` bundles a node's name, namespace and resolved
remappings, as ``rospy.names`` keeps them (without its module globals).

Deviations, on purpose: names with characters outside
``^[~/A-Za-z][\\w/]*$`` raise :class:`~ddes.errors.ROSNameException` (with
roscpp's wording) where rosgraph would silently resolve them; a malformed
``a:=b:=c`` argument raises :class:`~ddes.errors.ROSInitException` (rosgraph
prints an error and skips it, but ``rospy.init_node`` fails on it anyway);
:func:`anonymous_name` draws from a counter or a seeded generator instead of
the host name, pid and wall clock.
"""

from __future__ import annotations

import random
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import yaml

from ddes.errors import DdesTypeError, ResourceLimitError, ROSInitException, ROSNameException
from ddes.graph.yamlsafe import load_yaml

__all__ = [
    "ANYTYPE",
    "GLOBALNS",
    "LEGAL_NAME_PATTERN",
    "PRIV_NAME",
    "REMAP",
    "SEP",
    "SPECIAL_ARGS",
    "NameResolver",
    "NodeArgs",
    "anonymous_name",
    "canonicalize_name",
    "check_name",
    "get_ros_namespace",
    "is_global",
    "is_legal_base_name",
    "is_legal_name",
    "is_legal_remap",
    "is_private",
    "load_command_line_node_params",
    "load_mappings",
    "make_caller_id",
    "make_global_ns",
    "myargv",
    "namespace",
    "ns_join",
    "parse_node_args",
    "resolve_name",
]

SEP = "/"
GLOBALNS = "/"
PRIV_NAME = "~"
REMAP = ":="
ANYTYPE = "*"

#: The pattern rosgraph's ``is_legal_name`` checks (plus: no ``//``).
LEGAL_NAME_PATTERN = r"^[~/A-Za-z][\w/]*$"
_LEGAL_NAME = re.compile(r"[~/A-Za-z][\w/]*")
_LEGAL_BASE_NAME = re.compile(r"[A-Za-z]\w*")
_LEGAL_REMAP = re.compile(r"^([~/A-Za-z]|_|__)[\w/]*" + REMAP + ".*")
_NAME_CHAR = re.compile(r"[\w/]")

#: The special ``__x:=`` arguments rospy/roscpp understand.
SPECIAL_ARGS = ("__name", "__ns", "__master", "__ip", "__hostname", "__log")

_ANON_MAX = 2**63 - 1  # rosgraph draws randint(0, sys.maxsize) on 64-bit hosts


def _check_str(value: object, what: str) -> str:
    if not isinstance(value, str):
        raise DdesTypeError(f"{what} must be a str, got {type(value).__name__} {value!r}")
    return value


# -- predicates ----------------------------------------------------------------------------


def is_global(name: str) -> bool:
    """True if ``name`` starts with ``/`` (rosgraph.names.is_global)."""
    return bool(name) and name[0] == SEP


def is_private(name: str) -> bool:
    """True if ``name`` starts with ``~`` (rosgraph.names.is_private)."""
    return bool(name) and name[0] == PRIV_NAME


def is_legal_name(name: str | None) -> bool:
    """rosgraph's legality test: ``^[~/A-Za-z][\\w/]*$`` and no ``//``; ``""`` is legal."""
    if name is None or not isinstance(name, str):
        return False
    if name == "":
        return True
    return _LEGAL_NAME.fullmatch(name) is not None and "//" not in name


def is_legal_base_name(name: str | None) -> bool:
    """A base name has no namespace: ``^[A-Za-z]\\w*$`` (rosgraph)."""
    if name is None or not isinstance(name, str):
        return False
    return _LEGAL_BASE_NAME.fullmatch(name) is not None


def is_legal_remap(arg: str | None) -> bool:
    """True for a ``name:=value`` command-line argument (rosgraph.names.is_legal_remap)."""
    if arg is None or not isinstance(arg, str):
        return False
    m = _LEGAL_REMAP.match(arg)
    return m is not None and m.group(0) == arg


def check_name(name: str, what: str = "name") -> str:
    """Return ``name`` if its characters are legal, else raise ROSNameException.

    This is roscpp's ``names::validate``: the first character is a letter,
    ``/`` or ``~``, the others letters, digits, ``_`` or ``/``.  Double and
    trailing slashes are accepted (resolution canonicalizes them away).
    """
    _check_str(name, what)
    if name == "":
        return name
    if _LEGAL_NAME.match(name[0]) is None:
        raise ROSNameException(
            f"Character [{name[0]}] is not valid as the first character in Graph Resource "
            f"Name [{name}].  Valid characters are a-z, A-Z, / and in some cases ~. "
            f"(legal {what}s match {LEGAL_NAME_PATTERN})"
        )
    for i, c in enumerate(name[1:], start=1):
        if _NAME_CHAR.fullmatch(c) is None:
            raise ROSNameException(
                f"Character [{c}] at element [{i}] is not valid in Graph Resource Name "
                f"[{name}].  Valid characters are a-z, A-Z, 0-9, / and _. "
                f"(legal {what}s match {LEGAL_NAME_PATTERN})"
            )
    return name


# -- string operations ---------------------------------------------------------------------


def canonicalize_name(name: str) -> str:
    """Remove double and trailing slashes: ``//a//b/`` -> ``/a/b`` (rosgraph)."""
    _check_str(name, "name")
    if not name or name == SEP:
        return name
    parts = [x for x in name.split(SEP) if x]
    return SEP + SEP.join(parts) if name[0] == SEP else SEP.join(parts)


def namespace(name: str) -> str:
    """The namespace of ``name`` with a trailing slash: ``/wg/node1`` -> ``/wg/``.

    The empty name and top-level names give ``/`` (rosgraph.names.namespace).
    """
    _check_str(name, "name")
    if not name:
        return SEP
    if name[-1] == SEP:
        name = name[:-1]
    return name[: name.rfind(SEP) + 1] or SEP


def ns_join(ns: str, name: str) -> str:
    """Join a namespace and a name; global and private names are returned unchanged."""
    _check_str(ns, "namespace")
    _check_str(name, "name")
    if is_private(name) or is_global(name):
        return name
    if ns == PRIV_NAME:
        return PRIV_NAME + name
    if not ns:
        return name
    if ns[-1] == SEP:
        return ns + name
    return ns + SEP + name


def make_global_ns(name: str) -> str:
    """``foo`` -> ``/foo/``: a global namespace with a trailing slash (rosgraph)."""
    _check_str(name, "namespace")
    if is_private(name):
        raise ROSNameException(
            f"cannot turn [{name}] into a global name: a ~private name has no namespace of "
            f"its own; use a relative or global namespace"
        )
    if not is_global(name):
        name = SEP + name
    if name[-1] != SEP:
        name = name + SEP
    return name


def make_caller_id(name: str, ros_namespace: str = GLOBALNS) -> str:
    """The caller id of a node called ``name`` in ``ros_namespace`` (trailing slash, as rosgraph)."""
    return make_global_ns(ns_join(make_global_ns(ros_namespace), name))


def resolve_name(name: str, namespace_: str, remappings: Mapping[str, str] | None = None) -> str:
    """Resolve ``name`` to its global canonical form, then apply ``remappings``.

    ``namespace_`` is the fully-qualified name of the node the name belongs
    to (rosgraph's second argument): relative names resolve in
    ``namespace(namespace_)``, ``~private`` names under ``namespace_``
    itself, and ``""`` gives ``namespace(namespace_)``.  ``remappings``
    maps resolved names to resolved names and is matched exactly.
    """
    _check_str(namespace_, "node name")
    check_name(name)
    check_name(namespace_, "node name")
    if not name:
        return namespace(namespace_)
    name = canonicalize_name(name)
    if name[0] == SEP:
        resolved = name
    elif is_private(name):
        resolved = canonicalize_name(namespace_ + SEP + name[1:])
    else:
        resolved = namespace(namespace_) + name
    if remappings and resolved in remappings:
        return remappings[resolved]
    return resolved


# -- command-line arguments -----------------------------------------------------------------


def _split_remap(arg: str) -> tuple[str, str]:
    parts = [x.strip() for x in arg.split(REMAP)]
    if len(parts) != 2:
        raise ROSInitException(
            f"invalid command-line parameters: {arg!r} contains {len(parts) - 1} ':=' "
            f"separators; write one 'from:=to' per argument"
        )
    return parts[0], parts[1]


def _is_param_assignment(src: str) -> bool:
    return len(src) > 1 and src[0] == "_" and src[1] != "_"


def load_mappings(argv: Sequence[str]) -> dict[str, str]:
    """Remappings from ``argv`` (rosgraph.names.load_mappings).

    Every legal ``from:=to`` with non-empty sides is kept, except private
    parameter assignments (``_param:=value``).  As in rosgraph, special
    arguments such as ``__name:=x`` *are* included (rospy reads them from
    this table); :func:`parse_node_args` separates them.
    """
    mappings: dict[str, str] = {}
    for arg in argv:
        if is_legal_remap(arg):
            src, dst = _split_remap(arg)
            if src and dst and not _is_param_assignment(src):
                mappings[src] = dst
    return mappings


def load_command_line_node_params(argv: Sequence[str]) -> dict[str, Any]:
    """Private parameters ``_name:=value`` from ``argv``, values parsed with YAML (rospy).

    Keys lose their underscore (``_rate:=10`` -> ``{"rate": 10}``); a node
    sets them as ``~rate``.  Unparsable YAML raises ROSInitException, as
    rospy's ``load_command_line_node_params`` does.
    """
    params: dict[str, Any] = {}
    for arg in argv:
        if is_legal_remap(arg):
            src, dst = _split_remap(arg)
            if src and dst and _is_param_assignment(src):
                try:
                    params[src[1:]] = load_yaml(dst)  # bounded (ddes.graph.yamlsafe)
                except ResourceLimitError as exc:
                    raise ResourceLimitError(f"command-line parameter {src}: {exc}") from None
                except yaml.YAMLError as exc:
                    raise ROSInitException(
                        f"invalid command-line parameters: {arg!r} is not valid YAML ({exc}); "
                        f"quote the value"
                    ) from exc
    return params


def myargv(argv: Sequence[str]) -> list[str]:
    """``argv`` without ROS remapping arguments (rospy.myargv)."""
    return [a for a in argv if not is_legal_remap(a)]


def get_ros_namespace(env: Mapping[str, str] | None = None, argv: Sequence[str] = ()) -> str:
    """The node namespace: ``__ns:=`` in ``argv``, else ``env["ROS_NAMESPACE"]``, else ``/``.

    ddes never reads ``os.environ`` behind your back: pass ``env`` explicitly.
    """
    for a in argv:
        if a.startswith("__ns:="):
            return make_global_ns(a[len("__ns:=") :])
    return make_global_ns((env or {}).get("ROS_NAMESPACE", GLOBALNS))


@dataclass(frozen=True)
class NodeArgs:
    """A node's command line split the way rospy reads it.

    ``remappings`` holds the ``from:=to`` pairs (unresolved, specials
    excluded), ``params`` the private parameters, ``special`` the ``__x:=``
    arguments by their full key (``"__name"``), ``args`` what remains
    (rospy.myargv).
    """

    remappings: dict[str, str] = field(default_factory=dict)
    params: dict[str, Any] = field(default_factory=dict)
    special: dict[str, str] = field(default_factory=dict)
    args: list[str] = field(default_factory=list)

    @property
    def name(self) -> str | None:
        """The ``__name:=`` override, or None."""
        return self.special.get("__name")

    @property
    def ns(self) -> str | None:
        """The ``__ns:=`` namespace made global (``/ns/``), or None."""
        ns = self.special.get("__ns")
        return None if ns is None else make_global_ns(ns)


def parse_node_args(argv: Sequence[str]) -> NodeArgs:
    """Split ``argv`` into remappings, private parameters, special arguments and the rest."""
    for a in argv:
        _check_str(a, "command-line argument")
    mappings = load_mappings(argv)
    special = {k: v for k, v in mappings.items() if k.startswith("__")}
    remaps = {k: v for k, v in mappings.items() if not k.startswith("__")}
    return NodeArgs(remaps, load_command_line_node_params(argv), special, myargv(argv))


def anonymous_name(id: str, source: int | random.Random) -> str:
    """A ROS-legal anonymous name ``<id>_<n>``, deterministic.

    ``source`` is a counter value (e.g. ``world.next_id("anon")``) or a
    seeded :class:`random.Random` (e.g. ``world.rng``).  rosgraph appends the
    host name, pid and a random number; ddes keeps runs reproducible.
    """
    _check_str(id, "anonymous name prefix")
    if isinstance(source, random.Random):
        n = source.randint(0, _ANON_MAX)
    elif isinstance(source, int) and not isinstance(source, bool):
        n = source
    else:
        raise DdesTypeError(
            f"anonymous_name needs a counter (int) or a random.Random, got {source!r}"
        )
    name = f"{id}_{n}"
    return name.replace(".", "_").replace("-", "_").replace(":", "_")


# -- per-node resolution -------------------------------------------------------------------


class NameResolver:
    """Resolve a node's topic, service and parameter names, with its remappings.

    Parameters
    ----------
    node_name:
        The node's name: a base name (``"talker"``) placed in ``namespace``,
        or a relative/global name (``"/robot/talker"``).
    namespace:
        The node's namespace (``ROS_NAMESPACE`` / ``__ns``), ``"/"`` by default.
    remappings:
        ``from:=to`` pairs as given on the command line (unresolved).  Both
        sides are resolved against the node name, as ``rospy.names.
        initialize_mappings`` does; ``__special`` keys are ignored.
    """

    def __init__(
        self,
        node_name: str,
        namespace: str = GLOBALNS,
        remappings: Mapping[str, str] | None = None,
    ) -> None:
        _check_str(node_name, "node name")
        if not node_name or is_private(node_name):
            raise ROSNameException(
                f"node name {node_name!r} must be a non-empty base, relative or global name "
                f"(legal names match {LEGAL_NAME_PATTERN}, without a leading ~)"
            )
        ns = make_global_ns(check_name(namespace, "namespace"))
        #: The node's fully-qualified name (its caller id), e.g. ``/robot/talker``.
        self.name = resolve_name(node_name, ns + "unnamed")
        self._unresolved = dict(remappings or {})
        self._resolved: dict[str, str] = {}
        for src, dst in self._unresolved.items():
            if src.startswith("__"):
                continue
            self._resolved[resolve_name(src, self.name)] = resolve_name(dst, self.name)

    @classmethod
    def from_argv(
        cls, node_name: str, argv: Sequence[str], namespace: str = GLOBALNS
    ) -> NameResolver:
        """Build from a command line, honouring ``__name:=`` and ``__ns:=`` as rospy does."""
        args = parse_node_args(argv)
        return cls(args.name or node_name, args.ns or namespace, args.remappings)

    @property
    def namespace(self) -> str:
        """The node's namespace with a trailing slash (``/robot/``)."""
        return namespace(self.name)

    @property
    def remappings(self) -> dict[str, str]:
        """The resolved remappings (a copy)."""
        return dict(self._resolved)

    def resolve(self, name: str) -> str:
        """Resolve a topic, service or parameter name, then apply the remappings."""
        return resolve_name(name, self.name, self._resolved)

    def resolve_without_remapping(self, name: str) -> str:
        """Resolve ``name`` ignoring the remappings."""
        return resolve_name(name, self.name)

    def search_key(self, key: str) -> str:
        """The key rospy sends to ``searchParam``: remapped on its *unresolved* form.

        rospy's ``search_param`` looks ``key`` up in the raw command-line
        remappings (ros_comm #1810), then the master searches from this
        node's name upwards (:meth:`ddes.graph.params.ParamServer.search_param`).
        """
        _check_str(key, "parameter key")
        return self._unresolved.get(key, key)

    def __repr__(self) -> str:
        return f"NameResolver({self.name!r}, remappings={self._resolved!r})"
