"""A Ctrl+C pressed while an interactive command starts (before its paced run) is not lost."""

from __future__ import annotations

import math
import signal

from ddes.console.shell import Console


def test_ctrl_c_during_the_commands_start_stops_the_paced_run() -> None:
    console = Console(seed=0, out=lambda _line: None, rtf=math.inf)
    # Ctrl+C arrives while the world settles what the command started, inside a kernel callback
    console.world.post_ns(0, None, lambda _ev: signal.raise_signal(signal.SIGINT))
    out: list[str] = []
    err: list[str] = []
    before = signal.getsignal(signal.SIGINT)  # (pytest-xdist's workers ignore SIGINT)
    code = console.command("rostopic echo /nobody", out.append, err.append)
    assert code == 130  # stopped as Ctrl+C stops it in ROS; without the flag it ran for ever
    assert err[-1] == ("^C: stopped the foreground command 'rostopic echo /nobody' (its nodes "
                       "were shut down; background jobs keep running: 'jobs' lists them)")
    assert console.ctx.interrupted is None
    assert signal.getsignal(signal.SIGINT) is before
