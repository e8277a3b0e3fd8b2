"""Checks the course's exercises share: the student's log lines, graph facts, a driver node."""

from __future__ import annotations

import ast
import re
from typing import TYPE_CHECKING, Any

from ddes.grading.course import notes

if TYPE_CHECKING:
    from ddes.grading.exercise import Facts
    from ddes.graph.world import World

__all__ = ["NUMBER", "add_driver", "launch_problem", "student_logs", "student_subscriptions",
           "class_names", "calls_in"]

NUMBER = re.compile(r"[-+]?(?:inf|\d+(?:\.\d*)?(?:[eE][-+]?\d+)?)")


def launch_problem(facts: Facts) -> str:
    """Why the student's launch file did not start anything ('' when it did)."""
    n = notes(facts.world)
    if n.error:
        return n.error
    if not n.student_nodes:
        extra = f" ({'; '.join(n.problems)})" if n.problems else ""
        return f"{n.launch} starts no node of the submission's packages{extra}"
    return ""


def student_logs(facts: Facts) -> list[tuple[int, str, str]]:
    """``(t_ns, node, text)`` of every /rosout line of a student node, oldest first."""
    out = []
    for t, who, msg in facts.messages("/rosout"):
        if who in facts.student_nodes:
            out.append((t, who, str(msg.msg)))
    return out


def student_subscriptions(facts: Facts) -> list[tuple[str, str, int | None]]:
    """``(node, topic, queue_size)`` of the student's subscriptions, from the grader's master."""
    out = []
    for topic, entry in sorted(facts.world.master.topics.items()):
        for sub in entry.subscribers:
            if sub.node.name in facts.student_nodes:
                out.append((sub.node.name, topic, sub.queue_size))
    return out


def add_driver(world: World, moves: list[tuple[float, float, float]], *, rate: float = 10.0) -> None:
    """A grader node publishing ``/cmd_vel``: ``moves`` are ``(until_s, v, w)`` segments."""
    import ddes
    from ddes.msg import get_message_class

    Twist = get_message_class("geometry_msgs/Twist")
    node = world.create_node("/grader_driver", disable_rosout=True)
    pub = ddes.Publisher(node, "/cmd_vel", Twist, queue_size=1)

    def tick(_event: Any) -> None:
        now = world.now / 1e9
        for until, v, w in moves:
            if now < until:
                msg = Twist()
                msg.linear.x, msg.angular.z = v, w
                pub.publish(msg)
                return

    ddes.Timer(node, 1.0 / rate, tick)


def class_names(tree: ast.Module) -> list[str]:
    return [n.name for n in tree.body if isinstance(n, ast.ClassDef)]


def calls_in(node: ast.AST) -> list[ast.Call]:
    return [n for n in ast.walk(node) if isinstance(n, ast.Call)]


def call_name(call: ast.Call) -> str:
    f = call.func
    if isinstance(f, ast.Name):
        return f.id
    if isinstance(f, ast.Attribute):
        return f.attr
    return ""
