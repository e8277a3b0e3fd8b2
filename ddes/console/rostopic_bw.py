"""``rostopic bw``: the bandwidth a topic uses, on simulated time.

As ros_comm ``rostopic`` (``ROSTopicBandwidth``, ``_rostopic_bw``): an
anonymous ``/rostopic_N`` node subscribes to the topic with ``AnyMsg``,
prints ``subscribed to [/t]``, and counts the serialized bytes of every
message (``len(msg._buff)``, the wire bytes without the 4-byte length
prefix) with its arrival time, over the last ``WINDOW`` messages (``-w``,
default 100).  Once a second it prints, when at least two messages are in
the window::

    average: 1.23KB/s
    \tmean: 0.01KB min: 0.01KB max: 0.01KB window: 100

``average`` is the window's bytes over the time from its first message to
the report; ``mean``/``min``/``max`` are message sizes; every value takes the
unit of the average (``B`` under 1000 bytes/s, ``KB`` under 10^6, else ``MB``;
powers of 1000, two decimals).

rostopic measures on the wall clock (``time.time()`` and a wall-clock
sleep); ddes's wall clock is the kernel clock (as for ``hz --wall-time``),
so reports fall on whole simulated seconds after the command and the
figures are exact and repeatable.  As for ``hz``, a report counts the
messages arriving in its own instant (rostopic's sleep starts after the
subscribe call) and ``--duration S`` includes instant S.  A report whose
window spans no time (every message arrived at the report's instant) is
skipped: rostopic would divide by zero there, which its wall clock never
lets happen.  As ``hz``, it needs ``-n REPORTS`` (reports printed),
``--duration S`` or ``&``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ddes.console.rostopic_live import (
    _check_known,
    _require_bound,
    _wait_for_type,
    end_of_instant,
)
from ddes.console.toolkit import (
    Task,
    ToolParser,
    add_run_options,
    command_label,
    open_ended,
    parse_count,
    parse_duration,
    run_task,
    script_resolve_name,
    take_background,
)
from ddes.time.units import duration_to_ns, ns_to_sec

if TYPE_CHECKING:
    from simpy.events import ProcessGenerator

    from ddes.console.rostopic import MsgEval
    from ddes.console.tooling import ToolContext
    from ddes.msg.anymsg import AnyMsg

__all__ = ["TopicBandwidth", "bw", "format_bw"]

#: rostopic's window when ``-w`` is not given (or is 0).
DEFAULT_WINDOW = 100


class TopicBandwidth:
    """rostopic's ``ROSTopicBandwidth``: message sizes and arrival times over a window.

    Times are seconds, as rostopic's ``time.time()`` (ddes: the kernel clock,
    ``ns_to_sec(world.now)``), and the arithmetic is rostopic's.
    ``window_size`` 0 or None means :data:`DEFAULT_WINDOW`; a negative one
    keeps no message (as rostopic, which then never prints).
    """

    def __init__(self, window_size: int | None = DEFAULT_WINDOW) -> None:
        self.window_size = window_size or DEFAULT_WINDOW
        self.times: list[float] = []
        self.sizes: list[int] = []

    def callback(self, now: float, size: int) -> None:
        """Record a message of ``size`` serialized bytes received at ``now`` (seconds)."""
        self.times.append(now)
        self.sizes.append(size)
        if len(self.times) > self.window_size:
            self.times.pop(0)
            self.sizes.pop(0)

    def get_bw(self, now: float) -> tuple[float, float, int, int, int] | None:
        """``(bytes/s, mean, min, max, window)`` at ``now``; None when rostopic prints nothing."""
        if len(self.times) < 2 or now - self.times[0] <= 0:
            return None
        n = len(self.times)
        total = sum(self.sizes)
        return total / (now - self.times[0]), total / n, min(self.sizes), max(self.sizes), n


def format_bw(stats: tuple[float, float, int, int, int]) -> str:
    """The two lines ``rostopic bw`` prints for one report."""
    bytes_per_s, mean, min_s, max_s, n = stats
    values = (bytes_per_s, mean, min_s, max_s)
    if bytes_per_s < 1000:
        bw_t, mean_t, min_t, max_t = (f"{v:.2f}B" for v in values)
    elif bytes_per_s < 1000000:
        bw_t, mean_t, min_t, max_t = (f"{v / 1000:.2f}KB" for v in values)
    else:
        bw_t, mean_t, min_t, max_t = (f"{v / 1000000:.2f}MB" for v in values)
    return f"average: {bw_t}/s\n\tmean: {mean_t} min: {min_t} max: {max_t} window: {n}"


def bw(ctx: ToolContext, argv: list[str]) -> int:
    """``rostopic bw [-w WINDOW] /topic`` (see the module docstring)."""
    argv, background = take_background(argv)
    parser = ToolParser(ctx, "usage: %prog bw /topic", "rostopic")
    parser.add_option("-w", "--window", dest="window_size", default=None, metavar="WINDOW",
                      help="window size, in # of messages, for calculating rate")
    add_run_options(parser, count="ddes: number of reports printed (at most one per simulated "
                                  "second)")
    options, args = parser.parse_args(argv)
    if not args:
        parser.error("topic must be specified")
    if len(args) > 1:
        parser.error("you may only specify one input topic")
    window: int | None = None
    if options.window_size is not None:
        try:
            window = int(options.window_size)
        except ValueError:
            parser.error("window size must be an integer")
    reports = parse_count(options.count)
    duration = parse_duration(options.duration)
    bounded = background or open_ended(ctx)
    _require_bound("rostopic bw", bounded, duration, reports is not None)
    world = ctx.world
    topic = script_resolve_name("rostopic", args[0])
    _check_known(world, topic, bounded, duration)
    task = Task(world, command_label("rostopic", ["bw", *argv]))
    node = task.own(world.create_node("rostopic", anonymous=True))
    stats = TopicBandwidth(window)

    def callback(msg: AnyMsg) -> None:
        if not task.done:
            stats.callback(ns_to_sec(world.now), len(msg._buff))

    def start(_type_name: str, real: str, _eval: MsgEval | None) -> None:
        from ddes.msg.anymsg import AnyMsg

        if not node.is_shutdown():
            node.subscribe(real, AnyMsg, callback)
            ctx.print(f"subscribed to [{real}]")

    _wait_for_type(ctx, task, topic, start)
    printed = [0]

    def reporter() -> ProcessGenerator:
        while not task.done:
            yield world.timeout(1)
            yield end_of_instant(world)  # the messages arriving as the second ends count
            if task.done:
                return
            report = stats.get_bw(ns_to_sec(world.now))
            if report is None:
                continue
            ctx.print(format_bw(report))
            printed[0] += 1
            if reports is not None and printed[0] >= reports:
                task.finish(0)

    world.env.process(reporter())
    if duration is None:
        return run_task(ctx, task, background=background, duration=None,
                        waiting_for=None if reports is None else f"{reports} reports")

    def finisher(duration_ns: int) -> ProcessGenerator:
        # --duration S ends once instant S has run (as hz): a report due at S is printed
        yield world.env.timeout(duration_ns)
        yield end_of_instant(world)
        yield end_of_instant(world)  # after the reporter, woken by the same end of instant
        task.finish(0)

    world.env.process(finisher(duration_to_ns(duration, "--duration")))
    return run_task(ctx, task, background=background, duration=duration + 0.001,
                    waiting_for=f"--duration {duration:g}")
