"""The console's recordings are dated (issue 42, item 3.5).

rosbag names a recording by the machine's clock; ddes has none, so a plain world's kernel time 0
is 1970-01-01 00:00:00 UTC.  The console's kernel time 0 is
:data:`~ddes.console.shell.CONSOLE_RECORD_DATE` (2024-01-01 00:00:00 UTC) in the names of its
recordings; ``DDES_BAG_DATE`` and ``set_record_date`` still win (docs/bags.md).  The messages'
record times stay the recorder's ROS time, the console's simulated time from 0, as the header
stamps inside them (docs/console.md, "Deviations").
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from ddes.console.shell import CONSOLE_RECORD_DATE, Console
from ddes.graph.world import World
from ddes.rosbag import Bag, Recorder
from ddes.rosbag.recorder import fallback_record_date, set_fallback_record_date, set_record_date


@pytest.fixture
def here(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("DDES_BAG_DATE", raising=False)
    return tmp_path


def test_a_default_name_carries_the_consoles_date(console: Console, here: Path) -> None:
    assert CONSOLE_RECORD_DATE == "2024-01-01-00-00-00"
    console.run("rosrun --quiet rospy_tutorials talker &")
    console.run("sleep 5")
    out = console.run("rosbag record -a --duration 1")
    assert "Recording to '2024-01-01-00-00-05.bag'." in out  # not 1970-01-01-00-00-05.bag
    out = console.run("rosrun rosbag record -o pre --duration 1 /chatter")  # the node type too
    assert "Recording to 'pre_2024-01-01-00-00-06.bag'." in out
    assert sorted(os.listdir(here)) == ["2024-01-01-00-00-05.bag", "pre_2024-01-01-00-00-06.bag"]
    stamps = [m.timestamp.to_sec() for m in Bag("pre_2024-01-01-00-00-06.bag").read_messages()]
    assert stamps[0] == pytest.approx(6.1)  # record times: the console's simulated time


def test_ddes_bag_date_and_the_worlds_own_date_still_win(here: Path,
                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("DDES_BAG_DATE", "2020-05-05-10-00-00")
    console = Console(out=lambda _line: None)
    assert "'2020-05-05-10-00-00.bag'" in console.run("rosbag record -a --duration 1")
    world = World()
    set_record_date(world, "1999-12-31-23-59-59")
    console = Console(world, out=lambda _line: None)
    assert "'1999-12-31-23-59-59.bag'" in console.run("rosbag record -a --duration 1")


def test_python_recorders_on_the_consoles_world_and_plain_worlds(here: Path) -> None:
    console = Console(out=lambda _line: None)
    assert fallback_record_date(console.world) == CONSOLE_RECORD_DATE
    rec = Recorder(console.world, ["/rosout"], output_prefix="py")
    assert rec.path == "py_2024-01-01-00-00-00.bag"
    rec.stop()
    plain = World()  # a world outside the console: 1970, as before
    assert Recorder(plain, ["/x"], in_memory=True, output_prefix="w").path is None
    rec = Recorder(plain, ["/x"], output_prefix="w")
    assert rec.path == "w_1970-01-01-00-00-00.bag"
    rec.stop()
    set_fallback_record_date(plain, "2030-01-01")
    rec = Recorder(plain, ["/x"], output_prefix="v")
    assert rec.path == "v_2030-01-01-00-00-00.bag"
    rec.stop()
