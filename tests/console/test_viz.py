"""rviz, rqt_plot and rqt_graph in the console write PNGs in its directory and print the path;
ddes rqt_plot --bag does it from the shell."""

from __future__ import annotations

from pathlib import Path

import pytest

import ddes
from ddes.cli.main import main
from ddes.errors import ROSConsoleError


def test_console_pictures(tmp_path: Path) -> None:
    c = ddes.Console(seed=0)
    c.run(f"cd {tmp_path}")
    c.run("rosrun ddes_sim simulator _world:=single_pillar _noise:=false &")
    c.run('rostopic pub -r 10 /cmd_vel geometry_msgs/Twist "{linear: {x: 0.5}}" &')
    c.run("rosbag record -O run.bag /odom --duration 2 &")
    c.run("sleep 3")
    for line, name in (("rviz --markers /visualization_marker", "rviz.png"),
                       ("rqt_plot /odom/twist/twist/linear/x", "rqt_plot.png"),
                       ("rqt_plot --bag run.bag -o bag.png /odom/pose/pose/position/x:y", "bag.png"),
                       ("rqt_graph", "rqt_graph.png")):
        out = c.run(line)
        assert out == f"wrote {tmp_path / name}\n"
        data = (tmp_path / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000
    assert {"rviz", "rqt_plot", "rqt_graph"} <= set(c.commands())
    usage = c.run("rqt_plot", check=False)
    assert "rqt_plot: error: the following arguments are required: FIELD" in usage


def test_rviz_without_a_simulator() -> None:
    with pytest.raises(ROSConsoleError, match="no simulator is running"):
        ddes.Console(seed=0).run("rviz")


def test_ddes_rqt_plot_on_a_bag(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    c = ddes.Console(seed=0)
    c.run(f"cd {tmp_path}")
    c.run("rosrun ddes_sim simulator _world:=empty _noise:=false &")
    c.run("rosbag record -O run.bag /odom --duration 1 &")
    c.run("sleep 2")
    out = tmp_path / "v.png"
    assert main(["rqt_plot", "--bag", str(tmp_path / "run.bag"), "-o", str(out),
                 "/odom/twist/twist/linear/x"]) == 0
    assert out.read_bytes()[:4] == b"\x89PNG"
    assert capsys.readouterr().out == f"wrote {out}\n"
    assert main(["rqt_plot", "/odom/twist/twist/linear/x"]) == 2
    assert "give --bag FILE" in capsys.readouterr().err
    assert main(["rqt_plot", "--bag", str(tmp_path / "run.bag"), "/nope/x"]) == 1
    assert "no topic is a prefix of '/nope/x'" in capsys.readouterr().err
