"""``rostest`` of ROS Noetic for a test node run by ddes: ``rostest.rosrun(PKG, NAME, Case)``.

A test script's ``import rostest`` is this module (``ddes.compat.scripts``). The script is the
``<test>`` node of a rostest file (``ddes rostest``, docs/rostest.md), or any script run as a
node. Its unittest cases run inside the node on simulated time (see
:mod:`ddes.compat.rosunit`, which does the running and the reporting):

* :func:`rosrun` (and its alias :func:`run`): run the cases, print rosunit's ``SUMMARY:``,
  shut the node down (``rospy.signal_shutdown('test complete')``) and ``sys.exit(1)`` on a
  failure, as rostest's ``rosrun`` does;
* :func:`unitrun`: rosunit's ``unitrun`` (deprecated in rostest, kept);
* :func:`is_subscriber` / :func:`is_publisher`: whether the master (the world's) lists the node
  as a subscriber / publisher of the topic.

``get_master`` (an XML-RPC proxy of the master) is not provided: ddes has no XML-RPC; use
``rospy`` or the two functions above.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from ddes.compat import rosunit
from ddes.compat.rosunit import XML_OUTPUT_FLAG, print_unittest_summary, run_node_tests

__all__ = ["XML_OUTPUT_FLAG", "is_publisher", "is_subscriber", "rosrun", "run", "unitrun"]


def _system_state() -> tuple[list[tuple[str, list[str]]], ...]:
    from ddes.errors import ROSException
    from ddes.graph.blocking import current_task

    task = current_task()
    if task is None:
        raise ROSException("rostest: no ROS master here (call it from a test node run by ddes)")
    return task.world.master.get_system_state()  # type: ignore[no-any-return]


def is_subscriber(topic: str, subscriber_id: str) -> bool:
    """True if the master lists ``subscriber_id`` as a subscriber of ``topic``."""
    _pubs, subs, _srvs = _system_state()
    return any(subscriber_id in nodes for name, nodes in subs if name == topic)


def is_publisher(topic: str, publisher_id: str) -> bool:
    """True if the master lists ``publisher_id`` as a publisher of ``topic``."""
    pubs, _subs, _srvs = _system_state()
    return any(publisher_id in nodes for name, nodes in pubs if name == topic)


def rosrun(package: str, test_name: str, test: Any, sysargs: Sequence[str] | None = None) -> None:
    """Run a rostest/unittest integration test in this node (rostest's ``rosrun``)."""
    from ddes.graph.blocking import current_node

    result = run_node_tests(package, test_name, test, sysargs)
    print_unittest_summary(result)
    node = current_node()
    if node is not None and not node.is_shutdown():
        node.signal_shutdown("test complete")
    if not result.wasSuccessful():
        raise SystemExit(1)


run = rosrun


def unitrun(package: str, test_name: str, test: Any, sysargs: Sequence[str] | None = None,
            coverage_packages: Sequence[str] | None = None) -> None:
    """rosunit's ``unitrun`` (rostest keeps it, deprecated)."""
    rosunit.unitrun(package, test_name, test, sysargs, coverage_packages)
