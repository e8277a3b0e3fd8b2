"""The catalogue of trace kinds: every ``kind`` ddes records, with its detail keys.

:data:`TRACE_KINDS` maps each kind (``"topic.publish"``, ``"timer.fire"`` ...)
to a :class:`TraceKind`: the detail keys every event of that kind carries
(``fields``), the keys only some carry (``optional``), the layer of ddes that
records it and one line on what it means.  Pure data: this module imports
nothing from ddes, so any layer (and any grader) may read it.

Conventions of the details: times, stamps and latencies are integer
nanoseconds (a ``Time``/``Duration`` value is written as its nanoseconds in
the canonical form); ``source`` is the node that recorded the event (its
resolved name, e.g. ``/talker``) unless the kind's line says otherwise.

``tests/kernel/test_kinds.py`` checks that every kind the source records is
here with the right keys, and that ``docs/trace.md`` holds :func:`markdown_table`.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from types import MappingProxyType

__all__ = [
    "KIND_PREFIXES",
    "TRACE_KINDS",
    "TraceKind",
    "close_matches",
    "describe",
    "is_known",
    "markdown_table",
]


@dataclass(frozen=True)
class TraceKind:
    """One kind of trace event.

    ``fields`` are the detail keys every event of the kind has; ``optional``
    the keys some events add (e.g. ``node.exit``'s ``error``).  ``layer`` is
    the ddes layer that records it (``graph``, ``services``, ``actionlib``,
    ``rosbag``, ``nodes``).
    """

    kind: str
    fields: tuple[str, ...]
    layer: str
    doc: str
    optional: tuple[str, ...] = ()

    @property
    def all_fields(self) -> tuple[str, ...]:
        """``fields`` then ``optional``: every key an event of this kind may carry."""
        return self.fields + self.optional

    def check(self, details: Iterable[str]) -> list[str]:
        """What is wrong with an event's detail keys (``[]`` when they fit)."""
        keys = set(details)
        problems = [f"missing {k!r}" for k in self.fields if k not in keys]
        allowed = set(self.all_fields)
        problems += [f"unexpected {k!r}" for k in sorted(keys - allowed)]
        return problems


def _k(kind: str, fields: str, layer: str, doc: str, optional: str = "") -> TraceKind:
    return TraceKind(kind, tuple(fields.split()), layer, doc, tuple(optional.split()))


_ALL: tuple[TraceKind, ...] = (
    # -- nodes and logging (graph) -----------------------------------------------------
    _k("node.start", "use_sim_time", "graph",
       "A node was created (rospy.init_node); use_sim_time is whether it follows /clock."),
    _k("node.shutdown", "reason", "graph",
       "A node shut down (signal_shutdown, end of its main, or the world's end) and why."),
    _k("node.exit", "code", "nodes",
       "A node's main function returned (exit code) or raised (code 1 and the error).",
       optional="error"),
    _k("callback.exception", "callback error", "graph",
       "A user callback (subscriber, timer, service, action) raised: its qualified name and "
       "'Type: message'."),
    _k("log", "level msg file line", "graph",
       "A log line (loginfo/logwarn/...): level name, text, and the caller's file and line."),
    _k("warning", "topic text", "graph",
       "ddes warns about a ROS usage pitfall (e.g. a Publisher without queue_size)."),
    # -- timers and topics (graph) -----------------------------------------------------
    _k("timer.fire", "expected real", "graph",
       "A Timer callback ran; source is the timer's node. expected and real are the "
       "scheduled and actual times (ns)."),
    _k("topic.advertise", "topic type latch", "graph",
       "A publisher was created on a topic (resolved name, message type, latching)."),
    _k("topic.unadvertise", "topic", "graph", "A publisher was unregistered."),
    _k("topic.subscribe", "topic type", "graph", "A subscriber was created on a topic."),
    _k("topic.unsubscribe", "topic", "graph", "A subscriber was unregistered."),
    _k("topic.connect", "topic publisher connection", "graph",
       "A publisher-to-subscriber connection came up; source is the subscriber's node, "
       "publisher the publishing node, connection its id."),
    _k("topic.disconnect", "topic publisher connection", "graph",
       "A connection went down (either end unregistered or shut down)."),
    _k("topic.publish", "topic seq connections data", "graph",
       "A message was published (serialized once): its seq, how many connections it "
       "was sent on, and its serialized bytes (the digest covers their sha256)."),
    _k("topic.deliver", "topic publisher seq", "graph",
       "A subscriber's callback ran for a message; source is the subscriber's node, "
       "publisher the publishing node."),
    _k("topic.drop", "topic publisher seq reason", "graph",
       "A message did not reach a callback: reason 'loss' (the link lost it) or "
       "'queue_full' (the oldest queued message was dropped)."),
    _k("reconfigure.update", "ns config", "dynamic_reconfigure",
       "A dynamic_reconfigure server applied a new configuration (dict of parameters)."),
    # -- services ----------------------------------------------------------------------
    _k("service.advertise", "service type style uri", "services",
       "A service server was registered (rospy or roscpp style, invented rosrpc:// uri)."),
    _k("service.unadvertise", "service reason", "services",
       "A service server was shut down and why."),
    _k("service.call", "service call persistent request", "services",
       "A client sent a request: call id, persistent connection or not, a snapshot of the "
       "request message."),
    _k("service.request", "service call client", "services",
       "A server received a request; source is the server's node, client the caller's."),
    _k("service.response", "service call latency response", "services",
       "A client received the response: round-trip latency (ns) and the response message."),
    _k("service.error", "service call latency reason error", "services",
       "A call failed: reason one of unavailable, connect, server, transport, closed, "
       "timeout, interrupted; error the exception text."),
    _k("service.exception", "service call error", "services",
       "A service handler raised ('Type: message')."),
    _k("service.discard", "service call client reason", "services",
       "A response was thrown away: the client gave up, or the server shut down."),
    # -- actionlib: clients ------------------------------------------------------------
    _k("action.client.send", "ns id stamp", "actionlib",
       "An action client sent a goal (goal id and its stamp)."),
    _k("action.client.cancel", "ns id stamp", "actionlib",
       "An action client sent a cancel request (id '' and stamp 0 cancel everything)."),
    _k("action.client.transition", "ns id before after status", "actionlib",
       "A client goal handle's comm state changed (before/after state names, latest status)."),
    _k("action.client.lost", "ns id state", "actionlib",
       "A client's goal vanished from the server's status list while it was in state."),
    _k("action.client.result", "ns id status", "actionlib",
       "An action client received a result (terminal status name)."),
    _k("action.client.feedback", "ns id", "actionlib",
       "An action client received feedback for one of its goals."),
    _k("action.client.invalid", "ns id state status error", "actionlib",
       "A status the client's state machine cannot accept in its state (logged as ROS does)."),
    _k("action.simple.transition", "ns id before after", "actionlib",
       "A SimpleActionClient's simple state changed (PENDING/ACTIVE/DONE)."),
    # -- actionlib: servers ------------------------------------------------------------
    _k("action.server.start", "ns type status_frequency status_list_timeout", "actionlib",
       "An action server started (action type, status rate in Hz, status_list_timeout)."),
    _k("action.server.stop", "ns", "actionlib", "An action server stopped."),
    _k("action.server.status_list_del", "ns id status", "actionlib",
       "A script deleted a goal from actionlib's ActionServer.status_list (the goal is gone "
       "from the status; its client sees it LOST), as actionlib's tests do."),
    _k("action.server.goal", "ns id stamp arrival", "actionlib",
       "A goal message arrived: arrival new, canceled_by_stamp, duplicate or "
       "duplicate_recalled."),
    _k("action.server.transition", "ns id event before after text", "actionlib",
       "A server goal's status changed by event (setAccepted, setSucceeded, ...), with the "
       "status text."),
    _k("action.server.illegal", "ns id event state error", "actionlib",
       "An illegal transition was requested on a server goal (ignored and logged, as ROS)."),
    _k("action.server.feedback", "ns id status", "actionlib",
       "An action server published feedback for a goal (its status then)."),
    _k("action.server.cancel", "ns id stamp matched requested placeholder", "actionlib",
       "A cancel request arrived: the goal ids it matched, those now cancel-requested, and "
       "whether a placeholder goal was made for an unknown id."),
    _k("action.simple.preempt_request", "ns id reason", "actionlib",
       "A SimpleActionServer flagged a preempt (a newer goal or a cancel); id may be None."),
    _k("action.simple.execute", "ns id phase", "actionlib",
       "A SimpleActionServer's execute callback started or ended (phase start/end)."),
    _k("action.misuse", "ns level text", "actionlib",
       "actionlib misuse that ROS logs (level WARN or ERROR) instead of raising.",
       optional="method"),
    # -- rosbag ------------------------------------------------------------------------
    _k("rosbag.record", "path topics", "rosbag",
       "rosbag record started writing a bag (path, the topics asked for)."),
    _k("rosbag.stop", "reason messages", "rosbag",
       "rosbag record stopped (reason, messages written)."),
    _k("rosbag.play", "bags rate clock", "rosbag",
       "rosbag play started (number of bags, rate factor, whether it publishes /clock)."),
    _k("rosbag.loop", "loops published", "rosbag",
       "rosbag play --loop went round again (loops so far, messages published)."),
    _k("rosbag.done", "reason published", "rosbag",
       "rosbag play finished (reason, messages published)."),
    # -- sim: the 2D robot -------------------------------------------------------------
    _k("sim.pose", "stamp x y yaw v w", "sim",
       "The simulated robot's true state at 10 Hz: stamp (simulated ns), x, y, yaw, v, w as "
       "float.hex strings, so the physics is inside the digest."),
    _k("sim.collision", "obstacle speed normal_x normal_y stamp", "sim",
       "The robot's footprint touched an obstacle (recorded when the contact begins): speed "
       "and the contact normal as float.hex, stamp in simulated ns."),
    _k("sim.bump", "lateral vertical steps", "sim",
       "A wheel rolled over a bump (Simulator.bump): the IMU's lateral and vertical jolt peaks "
       "(m/s^2, float.hex) over this many 10 ms steps; no crash."),
    _k("sim.pause", "paused", "sim",
       "The simulator's physics paused (true) or went on (false)."),
    _k("sim.reset", "x y yaw", "sim",
       "The simulator put the robot back at its start pose (float.hex)."),
    _k("sim.place", "x y yaw", "sim",
       "The simulator placed the robot at a new pose (float.hex)."),
)

#: Every kind ddes records, by name (read-only).
TRACE_KINDS: Mapping[str, TraceKind] = MappingProxyType({k.kind: k for k in _ALL})

#: Every proper prefix of a catalogued kind, ending in ``"."`` (``"topic."``,
#: ``"action."``, ``"action.server."`` ...).
KIND_PREFIXES: frozenset[str] = frozenset(
    kind[: i + 1] for kind in TRACE_KINDS for i, ch in enumerate(kind) if ch == "."
)


def is_known(kind: str) -> bool:
    """Whether ``kind`` is a catalogued kind, or a prefix of one ending in ``"."``."""
    return kind in TRACE_KINDS or kind in KIND_PREFIXES


def close_matches(kind: str, n: int = 3) -> list[str]:
    """Catalogued kinds and prefixes that look like ``kind`` (for error messages)."""
    return difflib.get_close_matches(kind, sorted({*TRACE_KINDS, *KIND_PREFIXES}), n=n, cutoff=0.6)


def describe(kind: str) -> str:
    """A human-readable description of a kind or of every kind under a prefix.

    Raises ``KeyError`` (naming close matches) for a kind that is neither.
    """
    if kind in TRACE_KINDS:
        k = TRACE_KINDS[kind]
        opt = f" [optional: {', '.join(k.optional)}]" if k.optional else ""
        return f"{k.kind} ({k.layer}): {', '.join(k.fields) or '-'}{opt}\n    {k.doc}"
    if kind in KIND_PREFIXES:
        return "\n".join(describe(name) for name in sorted(TRACE_KINDS) if name.startswith(kind))
    near = close_matches(kind)
    hint = f"; did you mean {' or '.join(map(repr, near))}?" if near else ""
    raise KeyError(f"unknown trace kind {kind!r}{hint}")


def markdown_table() -> str:
    """The catalogue as a Markdown table (the one in ``docs/trace.md``)."""
    rows = [
        "| kind | fields | optional | layer | meaning |",
        "|---|---|---|---|---|",
    ]
    for name in sorted(TRACE_KINDS):
        k = TRACE_KINDS[name]
        fields = ", ".join(f"`{f}`" for f in k.fields) or "-"
        optional = ", ".join(f"`{f}`" for f in k.optional) or "-"
        rows.append(f"| `{k.kind}` | {fields} | {optional} | {k.layer} | {k.doc} |")
    return "\n".join(rows) + "\n"
