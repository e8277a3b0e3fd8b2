"""Lecture 4, actions: the lecture's FollowPath action, with feedback, a cancel and a latency.

Run it with ``python examples/actions_follow_path.py [--plot goals.png]``.

``FollowPath.action`` is on the lecture's slide (goal ``nav_msgs/Path path``;
the slide writes ``navigation_msgs/Path``); ddes bundles it in the package
``lecture4_actions`` with a server and a client node.  This script:

1. starts ``follow_path_server`` (0.5 m/s, feedback at 10 Hz) and a
   ``follow_path_client`` that sends a 2 m square and lets it finish;
2. starts a second client that cancels its 4 m square after 3 s;
3. puts 200 ms of latency on ``/follow_path/feedback`` to show that
   feedback lags while status and result do not;
4. prints the goals' final states, the message counts per topic and, with
   ``--plot``, draws the timeline.
"""

from __future__ import annotations

import argparse

import ddes
from ddes.actionlib import goal_timelines, plot_goals
from ddes.nodes import start_node


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plot", help="save the goal timeline to this PNG file")
    args = parser.parse_args(argv)

    world = ddes.World(seed=0)
    world.log_output = lambda line, level: print(line)
    world.set_link("/follow_path/feedback", latency=0.2)
    start_node(world, "lecture4_actions", "follow_path_server")
    start_node(world, "lecture4_actions", "follow_path_client")
    world.run(until=20.0)
    start_node(world, "lecture4_actions", "follow_path_client", name="impatient_client",
               argv=["_side:=4.0", "_cancel_after:=3.0"])
    world.run(until=30.0)

    for tl in goal_timelines(world.trace, ns="/follow_path"):
        print(f"{tl.goal_id:<36} {tl.status:<10} {len(tl.feedback):3d} feedback messages")
    published = world.trace.filter(kind="topic.publish")
    for topic in ("goal", "cancel", "status", "feedback", "result"):
        name = f"/follow_path/{topic}"
        count = sum(1 for e in published if e.details["topic"] == name)
        print(f"{name:<22} {count:4d} messages published")
    if args.plot:
        plot_goals(world.trace, ns="/follow_path").savefig(args.plot)
        print(f"timeline written to {args.plot}")
    print(f"trace digest: {world.digest()}")


if __name__ == "__main__":
    main()
