"""The launch plan: what a launch file asks for, fully resolved, as plain data.

The loader (:func:`ddes.launch.load_launch`) reads XML and produces a
:class:`LaunchPlan`; whoever runs the plan on a world does, in this order
(roslaunch's ``ROSLaunchRunner._setup`` then ``_launch_nodes``):

1. :attr:`LaunchPlan.rosparam_commands` in order: ``delete`` (a missing
   parameter is not an error, as the ``rosparam delete`` roslaunch spawns
   only prints) and ``dump`` (write the parameters under ``param`` to
   ``file`` as YAML).  roslaunch runs them *before* the parameters below
   are set.
2. Delete every namespace in :attr:`LaunchPlan.clear_params` that exists.
3. Set every entry of :attr:`LaunchPlan.params`, in order.  Dictionaries
   from ``<rosparam>`` are already unrolled into leaf parameters (roslaunch
   merges them into the tree, it does not replace subtrees); a
   ``<param type="yaml">`` dict stays one value.
4. Start :attr:`LaunchPlan.nodes` in order.

:attr:`NodeSpec.params` and :attr:`LaunchPlan.rosparam_loads` are records
for display and introspection: their values are already in
:attr:`LaunchPlan.params` and must not be set a second time.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ddes.errors import DdesKeyError
from ddes.launch.values import ParamValue

__all__ = ["TEST_TIME_LIMIT_DEFAULT", "LaunchPlan", "NodeSpec", "RosparamCommand", "TestSpec"]

#: rostest's default ``time-limit`` of a ``<test>`` (seconds; simulated ones in ddes).
TEST_TIME_LIMIT_DEFAULT = 60.0


@dataclass
class NodeSpec:
    """One ``<node>``: what to run, under which name, with which remappings.

    ``namespace`` is global with a trailing slash (``/`` or ``/robot/``), as
    roslaunch's ``Node.namespace``; :attr:`full_name` joins it with
    ``name``.  ``args`` is the ``args`` attribute split as a POSIX shell
    does (``shlex``).  ``remappings`` are the ``<remap>`` pairs in scope,
    unresolved, in roslaunch's order (each node receives them as
    ``from:=to`` arguments and resolves them in its own namespace).
    ``env`` holds the ``<env>`` settings in scope.  ``launch_prefix`` and
    ``machine`` are recorded but ignored: ddes runs every node in one
    simulated process.  ``source`` is ``file:line`` of the tag and
    ``include_chain`` the ``file:line`` of each ``<include>`` that led to
    it, outermost first.
    """

    pkg: str
    type: str
    name: str
    namespace: str = "/"
    args: list[str] = field(default_factory=list)
    remappings: list[tuple[str, str]] = field(default_factory=list)
    params: dict[str, ParamValue] = field(default_factory=dict)
    output: str | None = None
    respawn: bool = False
    respawn_delay: float = 0.0
    required: bool = False
    env: list[tuple[str, str]] = field(default_factory=list)
    cwd: str | None = None
    launch_prefix: str | None = None
    machine: str | None = None
    source: str = ""
    include_chain: tuple[str, ...] = ()

    @property
    def full_name(self) -> str:
        """The node's fully-qualified name, e.g. ``/robot/talker``."""
        return self.namespace + self.name

    def summary_name(self) -> str:
        """``name (pkg/type)``, as roslaunch's summary prints a node."""
        return f"{self.name} ({self.pkg}/{self.type})"


@dataclass
class TestSpec(NodeSpec):
    """One ``<test>`` (roslaunch's ``Test``): a node plus ``test_name``, ``time_limit``
    (seconds, rostest's default 60) and ``retry``.  rostest runs each against a fresh
    launch of :attr:`LaunchPlan.nodes`; plain roslaunch ignores it.  ``required`` is
    read and dropped, as roslaunch's ``Test`` drops it.  ``warning`` is the text the
    loader added to :attr:`LaunchPlan.warnings` for it (roslaunch's view: ignored).
    """

    __test__ = False  # not a pytest test class

    test_name: str = ""
    time_limit: float = TEST_TIME_LIMIT_DEFAULT
    retry: int = 0
    warning: str = ""


@dataclass(frozen=True)
class RosparamCommand:
    """A ``<rosparam command="delete|dump">``: ``param`` is resolved; ``file`` only for dump."""

    command: str
    param: str
    file: str | None = None
    source: str = ""


@dataclass
class LaunchPlan:
    """Everything a launch file asks for (see the module docstring for the order)."""

    params: dict[str, ParamValue] = field(default_factory=dict)
    clear_params: list[str] = field(default_factory=list)
    rosparam_commands: list[RosparamCommand] = field(default_factory=list)
    rosparam_loads: list[tuple[str, ParamValue]] = field(default_factory=list)
    nodes: list[NodeSpec] = field(default_factory=list)
    #: The ``<test>`` elements, in order (run by rostest, ignored by roslaunch).
    tests: list[TestSpec] = field(default_factory=list)
    args: dict[str, str] = field(default_factory=dict)
    files: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)

    @property
    def deletions(self) -> list[str]:
        """The parameters ``<rosparam command="delete">`` removes, in order."""
        return [c.param for c in self.rosparam_commands if c.command == "delete"]

    def node(self, full_name: str) -> NodeSpec:
        """The node called ``full_name`` (``/ns/name``); KeyError-like error if absent."""
        for n in self.nodes:
            if n.full_name == full_name:
                return n
        known = ", ".join(n.full_name for n in self.nodes) or "none"
        raise DdesKeyError(f"no node named {full_name!r} in the launch plan (nodes: {known})")

    def to_text(self) -> str:
        """roslaunch's SUMMARY print-out (sorted, values cut to 20 characters)."""
        out = ["SUMMARY", "========"]
        if self.clear_params:
            out += ["", "CLEAR PARAMETERS"] + sorted(f" * {p}" for p in self.clear_params)
        if self.params:
            out += ["", "PARAMETERS"] + sorted(
                f" * {k}: {_summary_value(v)}" for k, v in self.params.items()
            )
        out += ["", "NODES"]
        by_ns: dict[str, list[NodeSpec]] = {}
        for n in self.nodes:
            by_ns.setdefault(n.namespace, []).append(n)
        for ns in sorted(by_ns):
            out.append(f"  {ns}")
            out += sorted(f"    {n.summary_name()}" for n in by_ns[ns])
        return "\n".join(out) + "\n"


def _summary_value(value: ParamValue) -> str:
    """roslaunch's ``strip_string``: at most 20 characters, ``<...>`` for unprintables."""
    text = value.decode("latin-1") if isinstance(value, bytes) else str(value)
    if len(text) > 20:
        text = text[:17] + "..."
    for i, ch in enumerate(text):
        if not 32 <= ord(ch) <= 126:
            text = text.rstrip()
            if i >= len(text):
                break
            return "<...>"
    return text
