"""The rosbag command: world-bound (console, run_command) and one-shot ``ddes rosbag``."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from ddes import Time, World
from ddes.cli.main import main
from ddes.console.shell import Console
from ddes.console.tooling import ToolContext, run_command, run_command_result
from ddes.errors import ROSConsoleError
from ddes.rosbag import Bag

from .conftest import Int32, String, sample_bag


@pytest.fixture
def bag_file(tmp_path: Path) -> str:
    path = str(tmp_path / "in.bag")
    bag = Bag()
    for i in range(6):
        bag.write("/n", Int32(data=i), Time(i))
        bag.write("/s", String(data=f"s{i}"), Time(i, 5))
    bag.save(path)
    return path


def ctx() -> ToolContext:
    return ToolContext(World())


def test_info_matches_the_api_and_joins_files(utc: None, bag_file: str, tmp_path: Path) -> None:
    world = World()
    out = run_command(world, f"rosbag info {bag_file}")
    assert out == Bag(bag_file).info(freq=False) + "\n"
    assert run_command(world, f"rosbag info --freq {bag_file}") == \
        Bag(bag_file).info(freq=True) + "\n"
    two = run_command(world, f"rosbag info {bag_file} {bag_file}")
    assert two == out + "---\n" + out
    assert run_command(world, f"rosbag info -y -k messages {bag_file}") == "12\n"
    assert run_command(world, f"rosbag info -y {bag_file}") == \
        Bag(bag_file).yaml_info() + "\n"
    bad = run_command_result(ToolContext(world), f"rosbag info -y -k nope {bag_file}")
    assert (bad.code, bad.out, bad.err) == (0, "", 'Error getting key "nope"\n')


def test_info_errors(tmp_path: Path, bag_file: str) -> None:
    c = ctx()
    missing = str(tmp_path / "missing.bag")
    r = run_command_result(c, f"rosbag info {missing}")
    assert (r.code, r.err) == (1, f"ERROR reading {missing}: no such bag file\n")
    data = open(bag_file, "rb").read()
    unindexed = tmp_path / "u.bag"
    at = data.index(b"index_pos=") + 10
    unindexed.write_bytes(data[:at] + bytes(8) + data[at + 8:])
    r = run_command_result(c, f"rosbag info {unindexed}")
    assert (r.code, r.err) == (1, f"ERROR bag unindexed: {unindexed}.  Run rosbag reindex.\n")
    r = run_command_result(c, "rosbag info")
    assert r.code == 2 and "You must specify at least 1 bag file." in r.err
    r = run_command_result(c, f"rosbag info -k x {bag_file}")
    assert r.code == 2 and "only specify key when printing in YAML" in r.err


def test_one_shot_ddes_rosbag(utc: None, bag_file: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["rosbag", "info", bag_file]) == 0
    assert capsys.readouterr().out == Bag(bag_file).info(freq=False) + "\n"
    assert main(["rosbag", "record", "/x"]) == 1
    assert "needs a running world" in capsys.readouterr().err
    assert main(["rosbag"]) == 0
    assert "Available subcommands:" in capsys.readouterr().out
    assert main(["rosbag", "bogus"]) == 1
    assert "Unknown command: 'bogus'" in capsys.readouterr().err
    assert main(["rosbag", "-h"]) == 0
    assert main(["rosbag", "help", "info"]) == 0
    assert "rosbag info [options]" in capsys.readouterr().out


def test_filter(bag_file: str, tmp_path: Path) -> None:
    out = str(tmp_path / "out.bag")
    c = ctx()
    r = run_command_result(c, f"rosbag filter {bag_file} {out} \"topic == '/n' and m.data % 2 == 0\"")
    assert r.code == 0, r.err
    kept = Bag(out)
    assert [(m.topic, m.message.data) for m in kept.read_messages()] == [("/n", 0), ("/n", 2),
                                                                         ("/n", 4)]
    assert kept.get_connections()[0].header == Bag(bag_file).get_connections("/n")[0].header
    r = run_command_result(c, f"rosbag filter -p 't.secs' {bag_file} {out} 't.to_sec() < 1'")
    assert r.out.splitlines()[:3] == ["MATCH 0", "MATCH 0", "NO MATCH 1"]
    assert run_command_result(c, f"rosbag filter {bag_file} {bag_file} True").code == 3
    assert run_command_result(c, f"rosbag filter nope.bag {out} True").code == 2
    bad_out = str(tmp_path / "bad.bag")
    r = run_command_result(c, f"rosbag filter {bag_file} {bad_out} 'topic ==='")
    assert r.code == 1 and "not a valid Python expression" in r.err
    r = run_command_result(c, f"rosbag filter {bag_file} {bad_out} 'm.data + 1 > 2'")
    assert r.code == 1 and "failed on message 1" in r.err
    assert not os.path.exists(bad_out) and not os.path.exists(bad_out + ".active")
    r = run_command_result(c, f"rosbag filter {bag_file} {out}")
    assert r.code == 2 and "You must specify an expression." in r.err


def test_compress_decompress_with_backups(bag_file: str, tmp_path: Path) -> None:
    c = ctx()
    before = [(m.topic, m.message, m.timestamp) for m in Bag(bag_file).read_messages()]
    assert run_command_result(c, f"rosbag compress {bag_file}").code == 0
    backup = bag_file.replace(".bag", ".orig.bag")
    assert os.path.exists(backup)
    assert Bag(bag_file).get_compression_info().compression == "bz2"
    assert [(m.topic, m.message, m.timestamp) for m in Bag(bag_file).read_messages()] == before
    r = run_command_result(c, f"rosbag compress --lz4 {bag_file}")
    assert r.err == f"Skipping {bag_file}. Backup path {backup} already exists.\n"
    assert run_command_result(c, f"rosbag compress -q --lz4 {bag_file}").err == ""
    assert run_command_result(c, f"rosbag compress -f --lz4 {bag_file}").code == 0
    assert Bag(bag_file).get_compression_info().compression == "lz4"
    outdir = tmp_path / "dir"
    outdir.mkdir()
    assert run_command_result(c, f"rosbag decompress --output-dir {outdir} {bag_file}").code == 0
    plain = Bag(str(outdir / "in.bag"))
    assert plain.get_compression_info().compression == "none"
    assert [(m.topic, m.message, m.timestamp) for m in plain.read_messages()] == before
    r = run_command_result(c, f"rosbag decompress {tmp_path / 'none.bag'}")
    assert r.code == 1 and "ERROR reading" in r.err


def test_reindex_rebuilds_and_keeps_a_copy(bag_file: str) -> None:
    data = open(bag_file, "rb").read()
    at = data.index(b"index_pos=") + 10
    with open(bag_file, "wb") as f:
        f.write(data[:at] + bytes(8) + data[at + 8:])
    c = ctx()
    assert run_command_result(c, f"rosbag info {bag_file}").code == 1
    assert run_command_result(c, f"rosbag reindex {bag_file}").code == 0
    assert Bag(bag_file).get_message_count() == 12
    with open(bag_file.replace(".bag", ".orig.bag"), "rb") as f:
        assert f.read()[:at + 8].endswith(bytes(8))  # the backup is the untouched original


def test_record_and_play_in_a_console(tmp_path: Path) -> None:
    console = Console(seed=0, out=lambda _line: None)
    console.run("rosrun --quiet rospy_tutorials talker &")
    target = tmp_path / "rec"
    console.run(f"rosbag record -q -O {target} /chatter --duration 1")
    recorded = Bag(f"{target}.bag")
    assert recorded.get_message_count() == 10
    background = console.execute(f"rosbag record -O {tmp_path / 'bg'} /chatter &")
    assert background.code == 0
    assert background.out.splitlines() == ["[ INFO] [1.000000001]: Subscribing to /chatter",
                                           f"[2] rosbag record -O {tmp_path / 'bg'} /chatter"]
    console.run("sleep 0.5")
    assert os.path.exists(tmp_path / "bg.bag.active")
    console.run("kill %2")
    assert Bag(str(tmp_path / "bg.bag")).get_message_count() == 5
    with pytest.raises(ROSConsoleError, match="runs until Ctrl\\+C"):
        console.run("rosbag record /chatter")
    with pytest.raises(ROSConsoleError, match="end the line with &"):
        console.run(f"rosbag play -l {target}.bag")
    played = console.execute(f"rosbag play {target}.bag")
    assert played.code == 0
    assert played.out.splitlines()[-1] == "Done."
    assert "Hit space to toggle paused, or 's' to step." in played.out
    loop = console.execute(f"rosbag play -l -q {target}.bag &")
    assert loop.out.splitlines() == [f"[ INFO] [2.600000001]: Opening {target}.bag",
                                     f"[3] rosbag play -l -q {target}.bag"]
    console.run("sleep 2")
    assert "rosbag play -l -q" in console.run("jobs")
    console.run("kill %3")


def test_rostopic_echo_shows_the_fields_of_played_messages(bag_file: str) -> None:
    """The player's publishers carry raw bytes; rostopic takes the type's real class."""
    context = ctx()
    assert run_command_result(context, f"rosbag play -q {bag_file} &").code == 0
    echoed = run_command_result(context, "rostopic echo -n 2 /s")
    # -q keeps these lines, as in play.cpp (it drops only the empty first line and the status)
    assert (echoed.code, echoed.out) == (0, "Waiting 0.2 seconds after advertising topics... "
                                            "done.\n\nHit space to toggle paused, or 's' to "
                                            'step.\ndata: "s0"\n---\ndata: "s1"\n---\n')


def test_record_and_play_option_errors(tmp_path: Path) -> None:
    c = ctx()
    r = run_command_result(c, "rosbag record")
    assert r.code == 2 and "You must specify a topic name or else use the '-a' option." in r.err
    r = run_command_result(c, "rosbag record -o a -O b /x --duration 1")
    assert r.code == 2 and "Can't set both prefix and name." in r.err
    r = run_command_result(c, "rosbag record --split --duration 5 /x")
    assert r.code == 1 and "does not model --split" in r.err
    r = run_command_result(c, "rosbag record -a -l 3")
    assert r.code == 1 and "count is not valid" in r.err
    r = run_command_result(c, "rosbag play")
    assert r.code == 2 and "at least 1 bag file" in r.err
    empty = str(tmp_path / "e.bag")
    Bag().save(empty)
    r = run_command_result(c, f"rosbag play {empty}")
    assert r.code == 1 and r.err == "No messages to play on specified topics.  Exiting.\n"
    sample_bag().save(str(tmp_path / "s.bag"))
    r = run_command_result(c, f"rosbag play --pause-topics /x -- {tmp_path / 's.bag'}")
    assert r.code == 1 and "does not model --pause-topics" in r.err


def test_file_names_are_relative_to_the_console_directory(utc: None, tmp_path: Path,
                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    """roscd sets ctx.cwd: every rosbag subcommand opens and writes files from there."""
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    here = tmp_path / "here"
    here.mkdir()
    c = ToolContext(World(), cwd=str(here))
    assert run_command_result(c, "rostopic pub -r 10 /chatter std_msgs/String 'data: hi' &"
                              ).code == 0
    assert run_command_result(c, "rosbag record -O rel /chatter --duration 1").code == 0
    assert (here / "rel.bag").exists() and not (elsewhere / "rel.bag").exists()
    info = run_command_result(c, "rosbag info rel.bag")
    assert info.out.startswith("path:        rel.bag\n")  # the name as typed, as rosbag prints it
    assert run_command_result(c, "rosbag check rel.bag").code == 0
    assert run_command_result(c, "rosbag filter rel.bag f.bag 'True'").code == 0
    assert Bag(str(here / "f.bag")).get_message_count() == 10
    assert run_command_result(c, "rosbag compress f.bag").code == 0
    assert (here / "f.orig.bag").exists()
    assert run_command_result(c, "rosbag decompress --output-dir out f.bag").code == 1  # no dir
    (here / "out").mkdir()
    assert run_command_result(c, "rosbag decompress --output-dir out f.bag").code == 0
    assert Bag(str(here / "out" / "f.bag")).get_compression_info().compression == "none"
    assert run_command_result(c, "rosbag reindex f.bag").code == 0
    c.world.log_output = lambda line, level: c.out(line)
    played = run_command_result(c, "rosbag play -q rel.bag")
    assert played.out.splitlines()[0].endswith("]: Opening rel.bag")
    missing = run_command_result(c, "rosbag play nope.bag")
    assert (missing.code, missing.err) == (1, "ERROR reading nope.bag: no such bag file\n")
    assert run_command_result(c, "rosbag info nope.bag").err == \
        "ERROR reading nope.bag: no such bag file\n"


def test_record_prints_the_node_it_records_from(tmp_path: Path) -> None:
    c = ToolContext(World(), cwd=str(tmp_path))
    r = run_command_result(c, "rosbag record --node /talker -O n --duration 0.5")
    assert r.out.startswith("Recording from: /talker\n")  # record.cpp's std::cout line
    r = run_command_result(c, "rosbag record -x /rosout.* -O x --duration 0.5")
    assert r.code == 2 and "You must specify a topic name or else use the '-a' option." in r.err


def test_play_waits_for_subscribers_saying_so(bag_file: str) -> None:
    c = ctx()
    assert run_command_result(c, f"rosbag play --wait-for-subscribers {bag_file} &").code == 0
    assert run_command_result(c, "sleep 1").out == (
        "Waiting 0.2 seconds after advertising topics... done.\n\n"
        "Hit space to toggle paused, or 's' to step.\n"
        "Waiting for subscribers.\n")  # player.cpp's waitForSubscribers()
    assert run_command_result(c, "rostopic echo /s &").code == 0
    echoed = run_command_result(c, "rostopic echo -n 1 /n")  # now both topics have one
    assert echoed.out == "Finished waiting for subscribers.\ndata: 0\n---\n"
