"""Lecture 4, actions: the actionlib tutorials' Fibonacci server and clients, on simulated time.

Run it with ``python examples/actions_fibonacci.py [--plot goals.png]``.  In one
deterministic world:

1. ``rosrun actionlib_tutorials fibonacci_server`` serves ``/fibonacci``
   (a SimpleActionServer; its execute callback sleeps 1 s per number);
2. ``rosrun actionlib_tutorials fibonacci_client`` asks for order 20;
3. at t = 3 s an impatient client sends order 5: the server holds one goal
   at a time, so the first goal is preempted (its client logs an empty
   ``Result:``, as the script would) and the new one is accepted 0.1 s after
   the execute callback returns (rospy's execute loop); at t = 4.5 s the
   impatient client cancels its own goal, which ends PREEMPTED;
4. the console tools show the five topics of the action, the server's
   transitions are listed from the trace, and ``--plot`` draws the goals.
"""

from __future__ import annotations

import argparse
from collections.abc import Generator
from typing import Any

import ddes
from ddes.actionlib import GoalStatus, SimpleActionClient, plot_goals
from ddes.console.tooling import run_command
from ddes.msg import get_message_class
from ddes.nodes import start_node


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plot", help="save the goal timeline to this PNG file")
    args = parser.parse_args(argv)

    world = ddes.World(seed=0)
    world.log_output = lambda line, level: print(line)
    start_node(world, "actionlib_tutorials", "fibonacci_server")
    start_node(world, "actionlib_tutorials", "fibonacci_client")

    fib = get_message_class("actionlib_tutorials/FibonacciAction")
    goal_cls = get_message_class("actionlib_tutorials/FibonacciGoal")
    impatient = world.create_node("impatient")
    client = SimpleActionClient(impatient, "fibonacci", fib)

    def run_impatient() -> Generator[Any, Any, None]:
        yield client.wait_for_server()
        yield impatient.sleep(3.0)
        client.send_goal(goal_cls(order=5),
                         feedback_cb=lambda fb: impatient.loginfo("feedback %s", list(fb.sequence)))
        yield impatient.sleep(1.5)
        impatient.loginfo("cancelling my goal")
        client.cancel_goal()
        yield client.wait_for_result()
        impatient.loginfo("my goal ended %s: %r", GoalStatus(client.get_state()).name,
                          client.get_goal_status_text())

    impatient.process(run_impatient())
    world.run(until=8.0)

    for line in ("rostopic list", "rostopic info /fibonacci/status"):
        print(f"$ {line}")
        print(run_command(world, line), end="")

    for event in world.trace.filter(kind="action.server.transition"):
        d = event.details
        print(f"{event.t / 1e9:9.3f}s  {d['id']:<30} {d['before']:>10} -> {d['after']:<10} "
              f"({d['event']})")
    if args.plot:
        plot_goals(world.trace, ns="/fibonacci").savefig(args.plot)
        print(f"timeline written to {args.plot}")
    print(f"trace digest: {world.digest()}")


if __name__ == "__main__":
    main()
