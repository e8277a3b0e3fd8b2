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
from ddes.launch.substitution import SubstitutionContext
from ddes.launch.values import ParamValue

__all__ = ["Scope"]


@dataclass
class Scope:
    """One level of launch-file nesting (see the module docstring)."""

    ns: str
    subst: SubstitutionContext
    parent: Scope | None = None
    remaps: list[tuple[str, str]] = field(default_factory=list)
    private_params: list[tuple[str, ParamValue]] = field(default_factory=list)
    env: list[tuple[str, str]] = field(default_factory=list)
    arg_names: list[str] = field(default_factory=list)
    include_args: dict[str, str] | None = None
    pass_all_args: bool = False
    chain: tuple[str, ...] = ()

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
        return Scope(
            ns=make_global_ns(child_ns),
            subst=self.subst.child(),
            parent=self,
            private_params=self.private_params if self.private_params else [],
            env=list(self.env),
            arg_names=list(self.arg_names),
            include_args=self.include_args,
            chain=self.chain,
        )

    def add_private_param(self, key: str, value: ParamValue) -> None:
        """Declare a ``~param`` for later nodes; replaces one with the same key."""
        self.private_params[:] = [p for p in self.private_params if p[0] != key]
        self.private_params.append((key, value))

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
        self.remaps[:] = [r for r in self.remaps if r[0] != src]
        self.remaps.append((src, dst))

    def remap_args(self) -> list[tuple[str, str]]:
        """The remaps in effect: the parent's (minus those overridden here), then ours."""
        if self.parent is None:
            return list(self.remaps)
        mine = {r[0] for r in self.remaps}
        return [r for r in self.parent.remap_args() if r[0] not in mine] + list(self.remaps)

    def add_arg(self, name: str, *, value: str | None = None, default: str | None = None) -> None:
        """Declare arg ``name`` (roslaunch ``LoaderContext.add_arg``)."""
        if name in self.arg_names:
            if not self.pass_all_args:
                raise ROSLaunchException(
                    f"arg '{name}' has already been declared; declare each arg once per scope"
                )
        else:
            self.arg_names.append(name)
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
