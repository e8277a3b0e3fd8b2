"""The loader's scope: namespace, remaps, ~params, env and args of one nesting level.

This is roslaunch's ``LoaderContext`` (``roslaunch/loader.py``), with the
same inheritance rules:

* A child scope (``<group>``, ``<node>``, ``<include>``) gets its own
  namespace and a *copy* of the args and anon names: an ``<arg>`` declared
  in a ``<group>`` is invisible after it.
* Remaps are looked up through the parent chain; a remap in an inner scope
  replaces an outer one with the same ``from``.
* ``~private`` params declared at launch/group level apply to every node
  declared later in the scope.  A ``<group>`` copies the list.  An
  ``<include>`` *shares* the list with its parent when the parent's list is
  non-empty (roslaunch's ``params or []``), so a ``~param`` declared in an
  included file then also reaches nodes declared after the ``<include>``.
  ddes reproduces this quirk so that the same files give the same
  parameters.
* An ``<include>`` collects its child ``<arg>`` tags into
  :attr:`Scope.include_args`; the included file then sees only those args
  (plus all of the parent's with ``pass_all_args``) and fresh anon names.

Every scope of one load shares a :class:`LoadBudget`: making a scope costs
its namespace's characters and the entries it copies, looking its remaps up
costs the scopes and remaps it reads, a parameter name its characters.
Deep nesting makes these grow with the depth (a namespace 3000 levels deep
is copied into each of its 3000 scopes), so the budget, not a depth limit,
is what bounds a hostile file's work and memory.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ddes.errors import ROSLaunchException
from ddes.graph.names import (
    PRIV_NAME,
    canonicalize_name,
    is_legal_name,
    make_global_ns,
    ns_join,
)
from ddes.launch.substitution import LaunchLimitError, SubstitutionContext
from ddes.launch.values import ParamValue

__all__ = ["ENTRY_COST", "MAX_LOAD_WORK", "SCOPE_COST", "LoadBudget", "Scope"]

#: The work one load may do building scopes, remap lists and parameter names, in units of
#: about a byte: a character counts 1, a copied list or dict entry :data:`ENTRY_COST`, a
#: scope :data:`SCOPE_COST` (64 Mi units: a few seconds and a few hundred MB at most).
MAX_LOAD_WORK = 64 << 20
#: The cost of one entry copied into a nested scope (an arg, an env pair, a ~param ...).
ENTRY_COST = 16
#: The cost of making one scope (its objects), besides what it copies.
SCOPE_COST = 256


@dataclass
class LoadBudget:
    """The work the scopes of one load have done (see the module docstring)."""

    work: int = 0
    limit: int = MAX_LOAD_WORK

    def charge(self, units: int, what: str) -> None:
        """Count ``units`` of work for ``what``; past the limit, :class:`LaunchLimitError`."""
        self.work += units
        if self.work > self.limit:
            raise LaunchLimitError(
                f"this launch does more work than ddes allows ({self.limit} units, "
                f"ddes.launch.scope.MAX_LOAD_WORK) while {what}: nesting thousands of "
                "<group ns=...>s makes every namespace, remap list and parameter name inside "
                "them longer; flatten the groups, use shorter namespaces, or split the launch "
                "into several")


@dataclass
class Scope:
    """One level of launch-file nesting (see the module docstring)."""

    ns: str
    subst: SubstitutionContext
    parent: Scope | None = None
    #: ``from -> to``, in order (dicts here: replacing an entry costs O(1), not a scan).
    remaps: dict[str, str] = field(default_factory=dict)
    #: ``~name -> value`` for the nodes declared later, in order.
    private_params: dict[str, ParamValue] = field(default_factory=dict)
    env: list[tuple[str, str]] = field(default_factory=list)
    #: The args declared in this scope, in order (a dict: membership in O(1), as a set).
    arg_names: dict[str, None] = field(default_factory=dict)
    include_args: dict[str, str] | None = None
    pass_all_args: bool = False
    chain: tuple[str, ...] = ()
    budget: LoadBudget = field(default_factory=LoadBudget)
    #: :meth:`remap_args` of this scope, until :meth:`add_remap` changes it.
    _remap_cache: list[tuple[str, str]] | None = field(default=None, repr=False, compare=False)

    @property
    def filename(self) -> str | None:
        """The launch file whose tags are being read (None for XML text)."""
        return self.subst.filename

    def child(self, ns: str | None) -> Scope:
        """A nested scope in ``ns`` (relative, ``/global``, ``~``, or None for the same ns)."""
        if ns:
            if ns[0] == "/":
                child_ns = ns
            elif ns == PRIV_NAME:
                child_ns = PRIV_NAME
            else:
                child_ns = ns_join(self.ns, ns)
        else:
            child_ns = self.ns
        child_ns = make_global_ns(child_ns)
        copied = (len(self.subst.args) + len(self.subst.anon) + len(self.env)
                  + len(self.arg_names))
        self.budget.charge(SCOPE_COST + len(child_ns) + ENTRY_COST * copied,
                           f"entering namespace {child_ns[:80]}")
        return Scope(
            ns=child_ns,
            subst=self.subst.child(),
            parent=self,
            private_params=self.private_params if self.private_params else {},
            env=list(self.env),
            arg_names=dict(self.arg_names),
            include_args=self.include_args,
            chain=self.chain,
            budget=self.budget,
        )

    def add_private_param(self, key: str, value: ParamValue) -> None:
        """Declare a ``~param`` for later nodes; replaces one with the same key."""
        self.private_params.pop(key, None)
        self.private_params[key] = value

    def add_remap(self, src: str, dst: str) -> None:
        """Add ``src:=dst`` (canonicalized, checked); replaces one with the same ``src``."""
        src, dst = canonicalize_name(src), canonicalize_name(dst)
        if not src or not dst:
            raise ROSLaunchException("remap from/to attributes cannot be empty")
        for label, name in (("from", src), ("to", dst)):
            if not is_legal_name(name):
                raise ROSLaunchException(
                    f"remap {label} [{name}] is not a valid ROS name; names start with a "
                    "letter, / or ~ and contain letters, digits, _ and /"
                )
        self.remaps.pop(src, None)
        self.remaps[src] = dst
        self._remap_cache = None

    def remap_args(self) -> list[tuple[str, str]]:
        """The remaps in effect: the parent's (minus those overridden here), then ours.

        Computed from the nearest ancestor that knows its list, down, without recursion; each
        scope keeps its list (the tags of a scope are read while its parents' are not, so an
        ancestor's remaps cannot change under a living child).
        """
        chain: list[Scope] = []
        scope: Scope | None = self
        while scope is not None and scope._remap_cache is None:
            chain.append(scope)
            scope = scope.parent
        inherited = scope._remap_cache if scope is not None else []
        assert inherited is not None
        self.budget.charge(len(chain) * (SCOPE_COST // 8) + ENTRY_COST * len(inherited),
                           "collecting the remaps of a node")
        for s in reversed(chain):
            mine = s.remaps
            inherited = [r for r in inherited if r[0] not in mine] + list(mine.items())
            self.budget.charge(ENTRY_COST * len(inherited), "collecting the remaps of a node")
            s._remap_cache = inherited
        return list(inherited)

    def add_arg(self, name: str, *, value: str | None = None, default: str | None = None) -> None:
        """Declare arg ``name`` (roslaunch ``LoaderContext.add_arg``)."""
        if name in self.arg_names:
            if not self.pass_all_args:
                raise ROSLaunchException(
                    f"arg '{name}' has already been declared; declare each arg once per scope"
                )
        else:
            self.arg_names[name] = None
        target = self.subst.args if self.include_args is None else self.include_args
        if value is not None:
            if name in target and not self.pass_all_args:
                raise ROSLaunchException(
                    f"cannot override arg '{name}', which has already been set. An <arg> with "
                    "value= is a constant: use default= to let callers override it"
                )
            target[name] = value
        elif default is not None and name not in target:
            target[name] = default
