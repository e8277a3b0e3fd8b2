"""The master: the world's registry of nodes, topics, services and parameters.

It answers the questions rosnode, rostopic, rosservice and rosparam ask
(``getSystemState``, ``getPublishedTopics``, ``getTopicTypes``,
``lookupNode``, ``lookupService``) and pairs publishers with subscribers.
Registrations are kept in insertion order, so every listing is
deterministic; the tools sort where ROS's tools sort.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from ddes.errors import ROSTopicException
from ddes.graph.params import ParamServer

if TYPE_CHECKING:
    from ddes.graph.node import Node
    from ddes.graph.topics import Publisher, Subscriber
    from ddes.graph.world import World
    from ddes.msg.message import MessageClass

__all__ = ["Master", "ServiceEntry", "TopicEntry"]


@dataclass
class TopicEntry:
    """A topic as the master knows it."""

    name: str
    type: str
    md5sum: str
    publishers: list[Publisher[MessageClass]] = field(default_factory=list)
    subscribers: list[Subscriber[MessageClass]] = field(default_factory=list)

    def publisher_nodes(self) -> list[str]:
        """Names of the publishing nodes (each once, in registration order)."""
        return list(dict.fromkeys(p.node.name for p in self.publishers))

    def subscriber_nodes(self) -> list[str]:
        """Names of the subscribing nodes (each once, in registration order)."""
        return list(dict.fromkeys(s.node.name for s in self.subscribers))


@dataclass
class ServiceEntry:
    """A service as the master knows it: its server object and node."""

    name: str
    type: str
    md5sum: str
    node: Node
    server: Any


class Master:
    """Registry and introspection for one world (there is one master per world)."""

    def __init__(self, world: World) -> None:
        self.world = world
        #: The parameter server.
        self.params = ParamServer()
        self.topics: dict[str, TopicEntry] = {}
        self.services: dict[str, ServiceEntry] = {}

    # -- topics ----------------------------------------------------------------------------
    def _entry(self, name: str, type_: str, md5: str, who: str) -> TopicEntry:
        entry = self.topics.get(name)
        if entry is None:
            entry = self.topics[name] = TopicEntry(name, type_, md5)
            return entry
        if not entry.publishers and not entry.subscribers:
            entry.type, entry.md5sum = type_, md5
            return entry
        if type_ != "*" and entry.type != "*" and (entry.type != type_ or entry.md5sum != md5):
            raise ROSTopicException(
                f"{who} wants topic {name} to have datatype/md5sum [{type_}/{md5}], but it "
                f"already has [{entry.type}/{entry.md5sum}]: use the same message type on both "
                "ends, or another topic name"
            )
        if entry.type == "*" and type_ != "*":
            entry.type, entry.md5sum = type_, md5
        return entry

    def register_publisher(self, pub: Publisher[MessageClass]) -> TopicEntry:
        """Add a publisher; raises ROSTopicException on a type conflict."""
        entry = self._entry(pub.resolved_name, pub.type, pub.md5sum, f"Publisher of [{pub.node.name}]")
        entry.publishers.append(pub)
        for sub in list(entry.subscribers):
            self.world.graph_connect(pub, sub)
        return entry

    def register_subscriber(self, sub: Subscriber[MessageClass]) -> TopicEntry:
        """Add a subscriber; raises ROSTopicException on a type conflict."""
        entry = self._entry(sub.resolved_name, sub.type, sub.md5sum, f"Client [{sub.node.name}]")
        entry.subscribers.append(sub)
        for pub in list(entry.publishers):
            self.world.graph_connect(pub, sub)
        return entry

    def unregister_publisher(self, pub: Publisher[MessageClass]) -> None:
        entry = self.topics.get(pub.resolved_name)
        if entry is not None and pub in entry.publishers:
            entry.publishers.remove(pub)

    def unregister_subscriber(self, sub: Subscriber[MessageClass]) -> None:
        entry = self.topics.get(sub.resolved_name)
        if entry is not None and sub in entry.subscribers:
            entry.subscribers.remove(sub)

    # -- services --------------------------------------------------------------------------
    def register_service(self, name: str, type_: str, md5: str, node: Node, server: Any) -> None:
        """Add a service (the caller checks for duplicates first)."""
        self.services[name] = ServiceEntry(name, type_, md5, node, server)

    def unregister_service(self, name: str, server: Any) -> None:
        entry = self.services.get(name)
        if entry is not None and entry.server is server:
            del self.services[name]

    def lookup_service(self, name: str) -> ServiceEntry | None:
        """The service registered under ``name``, or None."""
        return self.services.get(name)

    # -- introspection (the master's XML-RPC API, as data) ---------------------------------------
    def get_published_topics(self, subgraph: str = "") -> list[tuple[str, str]]:
        """``[(topic, type)]`` of topics with at least one publisher, under ``subgraph``."""
        prefix = subgraph.rstrip("/") + "/" if subgraph else ""
        return [(e.name, e.type) for e in self.topics.values()
                if e.publishers and e.name.startswith(prefix)]

    def get_topic_types(self) -> list[tuple[str, str]]:
        """``[(topic, type)]`` of every topic with a publisher or a subscriber."""
        return [(e.name, e.type) for e in self.topics.values() if e.publishers or e.subscribers]

    def get_system_state(self) -> tuple[list[tuple[str, list[str]]], ...]:
        """``(publishers, subscribers, services)``, each ``[(name, [node, ...])]``."""
        pubs = [(e.name, e.publisher_nodes()) for e in self.topics.values() if e.publishers]
        subs = [(e.name, e.subscriber_nodes()) for e in self.topics.values() if e.subscribers]
        srvs = [(s.name, [s.node.name]) for s in self.services.values()]
        return pubs, subs, srvs

    def lookup_node(self, name: str) -> Node | None:
        """The live node called ``name``, or None."""
        return self.world.lookup_node(name)

    def node_names(self) -> list[str]:
        """Names of all live nodes, sorted (as ``rosnode list`` prints them)."""
        return sorted(self.world.nodes)
