"""``rosbag check``: whether a bag file is readable, indexed and playable here.

ROS's ``rosbag check BAG`` opens the bag (an unindexed bag is ``ERROR bag
unindexed: BAG.  Run rosbag reindex.``, exit 1), then asks the message
migrator whether every type in the bag matches the type of the same name on
this system: ``Bag file does not need any migrations.`` when it does.  ddes
does the same checks against the world's message registry: a type whose
md5sum differs from the local definition needs a migration (which ddes does
not model: ``rosbag fix`` is not provided), a type unknown locally is
playable from the definition stored in the bag.

``rosbag reindex`` is :func:`ddes.rosbag.ops.reindex_file`: it keeps every
complete chunk of an unindexed or truncated file (such as the
``NAME.bag.active`` a killed ``rosbag record`` leaves) and writes the index.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ddes.errors import DdesError
from ddes.rosbag.bag import Bag

if TYPE_CHECKING:
    from ddes.msg.registry import MessageRegistry

__all__ = ["CheckResult", "check_bag"]


@dataclass
class CheckResult:
    """What :func:`check_bag` found: the bag's version and the types needing a migration."""

    path: str
    version: str
    messages: int
    #: ``(type, md5 in the bag, md5 here)`` for each type that differs from this system's.
    migrations: list[tuple[str, str, str]] = field(default_factory=list)

    def lines(self) -> list[str]:
        """What ``rosbag check`` prints."""
        if not self.migrations:
            return ["Bag file does not need any migrations."]
        out = ["The following migrations need to occur:"]
        out += [f" * From: {t} [{old}]\n   To:   {t} [{new}]" for t, old, new in self.migrations]
        out.append("\nddes does not migrate messages (rosbag fix is not modelled): record the "
                   "bag again with the current message definitions")
        return out


def check_bag(path: str, registry: MessageRegistry | None = None) -> CheckResult:
    """Open ``path`` (errors: ROSBagUnindexedException, ROSBagFormatException...) and compare
    its types with ``registry`` (default: the bundled and package-path types)."""
    from ddes.msg import get_message_class

    bag = Bag(path)
    try:
        result = CheckResult(path, "2.0", bag.get_message_count())
        seen: set[str] = set()
        for conn in bag.get_connections():
            if conn.datatype in seen:
                continue
            seen.add(conn.datatype)
            try:
                local = get_message_class(conn.datatype, registry)
            except DdesError:
                continue  # unknown here: played from the definition stored in the bag
            md5 = getattr(local, "_md5sum", conn.md5sum)
            if conn.md5sum not in ("*", md5):
                result.migrations.append((conn.datatype, conn.md5sum, md5))
        return result
    finally:
        bag.close()
