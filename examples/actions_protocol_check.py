"""Check an action server against the actionlib protocol with random schedules (for graders).

Run it with ``python examples/actions_protocol_check.py``.

:mod:`ddes.testing.actions` drives any server through random goals, cancels,
preemptions and latencies, checking the protocol after every step.  Here it
checks two Fibonacci servers:

* the tutorial's server (``actionlib_tutorials``): no violation;
* a "student" server that forgets the ``return`` after ``set_preempted()``:
  the machine finds a schedule where the goal is preempted, shrinks it to
  the smallest one, and prints it with the world seed to replay it.

In pytest, ``TestStudent = ActionProtocolMachine.for_server(make_server)`` is
all it takes.
"""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

from hypothesis import strategies as st

from ddes.actionlib import SimpleActionServer
from ddes.msg import get_message_class
from ddes.nodes import load_node_types
from ddes.rospack import RosPack
from ddes.testing.actions import ProtocolViolation, run_protocol_machine

Fibonacci = get_message_class("actionlib_tutorials/FibonacciAction")
Feedback = get_message_class("actionlib_tutorials/FibonacciFeedback")
Result = get_message_class("actionlib_tutorials/FibonacciResult")
#: Small orders keep each goal short (the tutorial computes one number per second).
GOALS = st.integers(0, 4).map(lambda n: {"order": n})


def tutorial_server(world: Any, node: Any) -> Any:
    """The tutorial's fibonacci_server, started on the machine's node."""
    types = load_node_types(RosPack().get_path("actionlib_tutorials"))
    return types["fibonacci_server"].main(node)


def student_server(world: Any, node: Any) -> SimpleActionServer:
    """A student's server with a classic bug."""

    def execute(goal: Any) -> Generator[Any, Any, None]:
        seq = [0, 1]
        for i in range(1, goal.order):
            if server.is_preempt_requested():
                server.set_preempted()          # BUG: no return
            seq.append(seq[i] + seq[i - 1])
            server.publish_feedback(Feedback(sequence=seq))
            yield node.sleep(1.0)
        server.set_succeeded(Result(sequence=seq))

    server = SimpleActionServer(node, "fibonacci", Fibonacci, execute, auto_start=False)
    server.start()
    return server


def main() -> None:
    run_protocol_machine(tutorial_server, action=Fibonacci, ns="/action_server", goals=GOALS,
                         max_examples=30, derandomize=True, database=None)
    print("tutorial server: no violation in 30 random schedules")
    try:
        run_protocol_machine(student_server, goals=GOALS, max_examples=100, derandomize=True,
                             database=None, print_blob=False)
    except ProtocolViolation as exc:
        print("student server:")
        print(exc)


if __name__ == "__main__":
    main()
