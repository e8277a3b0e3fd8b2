"""Fixtures of the console and tool tests: a console on a fresh world with a roscore."""

from __future__ import annotations

import pytest

from ddes.console.shell import Console


@pytest.fixture
def console() -> Console:
    """A console (seed 0, ``/rosout`` running) whose output is only captured, never printed."""
    return Console(seed=0, out=lambda _line: None)


@pytest.fixture
def chat(console: Console) -> Console:
    """The console after ``rosrun --quiet rospy_tutorials talker &`` and ``listener --quiet``."""
    console.run("rosrun --quiet rospy_tutorials talker &")
    console.run("rosrun --quiet rospy_tutorials listener &")
    return console
