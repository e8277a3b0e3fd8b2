"""What ``rosbag record`` and ``rosbag play`` print, against what Noetic's print (issue 14, item 2).

The ``REAL_*`` texts are the standard output of the real tools (ros-noetic rosbag 1.15.15 from
Debian, colour codes removed), recorded with a roscore, a 10 Hz talker on ``/chatter`` and

    rosbag record /chatter -O x.bag      (Ctrl+C after 3 s)
    rosbag record -a                     (Ctrl+C after 3 s)
    rosbag play x.bag / rosbag play -q l2.bag / rosbag play -i l2.bag

``rosbag play`` rewrites its status line with ``\\r``; :func:`screen` renders the text as the
terminal shows it.  ddes prints that final line once per pass (docs/bags.md).  Times differ
(wall clock against simulated time) and are masked; everything else must be equal.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from ddes.console.shell import Console

REAL_RECORD = ("[ INFO] [1795439547.374279634]: Subscribing to /chatter\n"
               "[ INFO] [1795439547.377891146]: Recording to 'x.bag'.\n")
REAL_RECORD_ALL = ("[ INFO] [1795439550.732839167]: Subscribing to /rosout_agg\n"
                   "[ INFO] [1795439550.733444152]: Recording to '2026-11-23-13-12-30.bag'.\n"
                   "[ INFO] [1795439550.734663328]: Subscribing to /rosout\n"
                   "[ INFO] [1795439550.736486687]: Subscribing to /chatter\n")
_STATUS = " [RUNNING]  Bag Time: {}   Duration: {} / {}               "
REAL_PLAY = ("[ INFO] [1795439566.513349982]: Opening x.bag\n"
             "\n"
             "Waiting 0.2 seconds after advertising topics... done.\n"
             "\n"
             "Hit space to toggle paused, or 's' to step.\n"
             + "".join("\r" + _STATUS.format(t, d, "2.399946") + "\r" for t, d in (
                 ("1795439547.678913", "0.000000"), ("1795439547.678973", "0.000060"),
                 ("1795439547.778923", "0.100010"), ("1795439549.779210", "2.100298"),
                 ("1795439549.880487", "2.201575")))
             + "\nDone.\n")
REAL_PLAY_QUIET = ("[ INFO] [1795439828.417095797]: Opening l2.bag\n"
                   "Waiting 0.2 seconds after advertising topics... done.\n"
                   "\n"
                   "Hit space to toggle paused, or 's' to step.\n"
                   "\n"
                   "Done.\n")
REAL_PLAY_IMMEDIATE = ("[ INFO] [1795439829.500617243]: Opening l2.bag\n"
                       "\n"
                       "Waiting 0.2 seconds after advertising topics... done.\n"
                       "\n"
                       "Hit space to toggle paused, or 's' to step.\n"
                       + "".join("\r" + _STATUS.format(t, d, "0.200142") + "\r" for t, d in (
                           ("1795439783.278961", "0.000000"), ("1795439783.379161", "0.100200"),
                           ("1795439783.479102", "0.200142")))
                       + "\nDone.\n")


def screen(text: str) -> list[str]:
    """``text`` as a terminal shows it: ``\\r`` returns to the start of the line, blanks at the
    ends of lines are invisible."""
    lines = []
    for raw in text.split("\n")[:-1]:
        shown: list[str] = []
        for part in raw.split("\r"):
            shown[:len(part)] = part
        lines.append("".join(shown).rstrip())
    return lines


def masked(lines: list[str]) -> list[str]:
    """Times masked: log stamps, bag times and durations, dates in file names; the bag played."""
    out = []
    for line in lines:
        line = re.sub(r"^\[ (\w+)\] \[\d+\.\d{9}\]", r"[ \1] [T]", line)
        line = re.sub(r"Bag Time: +[\d.]+   Duration: [\d.]+ / [\d.]+",
                      "Bag Time: B   Duration: D / L", line)
        line = re.sub(r"Opening \S+$", "Opening BAG", line)
        out.append(re.sub(r"\d{4}-\d\d-\d\d-\d\d-\d\d-\d\d\.bag", "DATE.bag", line))
    return out


@pytest.fixture
def console(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Console:
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("DDES_BAG_DATE", "2024-03-01-12-00-00")
    con = Console(seed=0, out=lambda _line: None)
    con.run('rostopic pub -r 10 /chatter std_msgs/String "data: hello" &')
    return con


def test_record_prints_what_the_cpp_recorder_prints(console: Console) -> None:
    out = console.run("rosbag record /chatter -O x.bag --duration 2.5")
    assert out == ("[ INFO] [0.000000000]: Subscribing to /chatter\n"
                   "[ INFO] [0.000000000]: Recording to 'x.bag'.\n")
    assert masked(out.splitlines()) == masked(screen(REAL_RECORD))
    out = console.run("rosbag record -a --duration 1")
    assert out == ("[ INFO] [2.500000001]: Recording to '2024-03-01-12-00-02.bag'.\n"
                   "[ INFO] [2.500000001]: Subscribing to /rosout_agg\n"
                   "[ INFO] [2.500000001]: Subscribing to /rosout\n"
                   "[ INFO] [2.500000001]: Subscribing to /chatter\n")
    # the same lines; real record prints its first Subscribing line from another thread
    assert sorted(masked(out.splitlines())) == sorted(masked(screen(REAL_RECORD_ALL)))


def test_play_prints_what_the_cpp_player_prints(console: Console) -> None:
    console.run("rosbag record /chatter -O x.bag --duration 2.5")
    out = console.run("rosbag play x.bag")
    assert out == ("[ INFO] [2.500000001]: Opening x.bag\n"
                   "\n"
                   "Waiting 0.2 seconds after advertising topics... done.\n"
                   "\n"
                   "Hit space to toggle paused, or 's' to step.\n"
                   " [RUNNING]  Bag Time:      2.400000   Duration: 2.300000 / 2.400000\n"
                   "Done.\n")
    assert masked(out.splitlines()) == masked(screen(REAL_PLAY))
    quiet = console.run("rosbag play -q x.bag")
    assert masked(quiet.splitlines()) == masked(screen(REAL_PLAY_QUIET)) != []
    immediate = console.run("rosbag play -i x.bag")
    assert immediate.splitlines()[-2] == \
        " [RUNNING]  Bag Time:      2.500000   Duration: 2.400000 / 2.400000"
    assert masked(immediate.splitlines()) == masked(screen(REAL_PLAY_IMMEDIATE))


def test_the_status_line_follows_the_rate_and_the_end(console: Console) -> None:
    console.run("rosbag record /chatter -O x.bag --duration 1")
    # at half speed play.cpp rewrites the line every 0.05 bag seconds: the last before 1.0
    out = console.run("rosbag play -r 0.5 x.bag")
    assert out.splitlines()[-2] == \
        " [RUNNING]  Bag Time:      0.950000   Duration: 0.850000 / 0.900000"
    # a loop shows the line at the end of every pass; a stopped player shows where it was
    console.run("rosbag play -l x.bag &")
    out = console.run("sleep 2.25")
    assert out.splitlines() == [
        "Waiting 0.2 seconds after advertising topics... done.", "",
        "Hit space to toggle paused, or 's' to step.",
        " [RUNNING]  Bag Time:      0.900000   Duration: 0.800000 / 0.900000",
        " [RUNNING]  Bag Time:      0.900000   Duration: 0.800000 / 0.900000"]
    out = console.run("kill %2")
    assert out.splitlines()[0] == \
        " [RUNNING]  Bag Time:      0.300000   Duration: 0.200000 / 0.900000"
    assert "Done." not in out


def test_pausing_shows_paused(console: Console) -> None:
    console.run("rosbag record /chatter -O x.bag --duration 1")
    console.run("rosbag play --pause x.bag &")
    console.run("sleep 1")
    out = console.run("kill %2")
    assert out.splitlines()[0] == \
        " [PAUSED ]  Bag Time:      0.100000   Duration: 0.000000 / 0.900000"
