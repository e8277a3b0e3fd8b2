"""Fixtures of the console and tool tests: a console on a fresh world with a roscore."""

from __future__ import annotations

import pytest

from ddes.console.shell import Console


@pytest.fixture
def console(ddes_seed: int) -> Console:
    """A console (``/rosout`` running) whose output is only captured, never printed.

    It overrides the ``console`` of ddes's pytest plugin, whose between-command output goes to
    standard output; its seed is the plugin's (``--ddes-seed``, 0 by default), so a failing
    test prints its replay command.
    """
    return Console(seed=ddes_seed, out=lambda _line: None)


@pytest.fixture
def chat(console: Console) -> Console:
    """The console after ``rosrun --quiet rospy_tutorials talker &`` and ``listener --quiet``."""
    console.run("rosrun --quiet rospy_tutorials talker &")
    console.run("rosrun --quiet rospy_tutorials listener &")
    return console
