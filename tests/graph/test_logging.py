"""Node log lines reach Python's logging module and print by default in rospy's format."""

from __future__ import annotations

import logging

import pytest

import ddes
from ddes.graph.rosout import LOGGER, logger_name

from ..docsnippets import run_snippet


def _talk(world: ddes.World) -> None:
    node = world.create_node("talker", namespace="/robot")
    node.loginfo("hello %d", 1)
    node.logwarn("careful")
    node.logdebug("hidden at the default level")


def test_lines_print_by_default_as_rospy_prints_them(capsys: pytest.CaptureFixture[str]) -> None:
    _talk(ddes.World())
    out, err = capsys.readouterr()
    assert out == "[INFO] [0.000000]: hello 1\n"  # INFO on stdout, WARN and up on stderr
    assert err == "[WARN] [0.000000]: careful\n"


def test_caplog_sees_each_node_on_its_own_logger(caplog: pytest.LogCaptureFixture) -> None:
    with caplog.at_level(logging.DEBUG, logger=LOGGER):
        _talk(ddes.World())
    records = [(r.name, r.levelname, r.getMessage()) for r in caplog.records]
    assert records == [("ddes.node.robot.talker", "INFO", "hello 1"),
                       ("ddes.node.robot.talker", "WARNING", "careful")]
    assert caplog.records[0].ddes_line == "[INFO] [0.000000]: hello 1"  # type: ignore[attr-defined]
    assert caplog.records[0].ddes_node == "/robot/talker"  # type: ignore[attr-defined]
    assert logger_name("/robot/talker") == "ddes.node.robot.talker"


def test_a_console_prints_once_and_false_prints_nothing(capsys: pytest.CaptureFixture[str],
                                                         caplog: pytest.LogCaptureFixture) -> None:
    world = ddes.World()
    lines: list[str] = []
    world.log_output = lambda line, level: lines.append(line)
    _talk(world)
    assert lines == ["[INFO] [0.000000]: hello 1", "[WARN] [0.000000]: careful"]
    assert capsys.readouterr() == ("", "")  # not printed a second time
    caplog.clear()
    quiet = ddes.World()
    quiet.log_output = False
    with caplog.at_level(logging.INFO, logger=LOGGER):
        _talk(quiet)
    assert capsys.readouterr() == ("", "")
    assert [r.getMessage() for r in caplog.records] == ["hello 1", "careful"]  # still logged


def test_log_output_true_prints_and_rosout_still_works(capsys: pytest.CaptureFixture[str]) -> None:
    world = ddes.World()
    world.log_output = True  # "turn output on" must not crash
    seen: list[str] = []
    log = world.messages.get_message_class("rosgraph_msgs/Log")
    world.create_node("watch").subscribe("/rosout", log, lambda m: seen.append(m.msg))
    world.run_for(0.01)
    world.create_node("n").loginfo("on rosout too")
    world.run_for(0.01)
    assert "[INFO] [0.010000]: on rosout too\n" in capsys.readouterr().out
    assert "on rosout too" in seen


def test_python_levels_silence_lines(capsys: pytest.CaptureFixture[str]) -> None:
    parent = logging.getLogger(LOGGER)
    old = parent.level
    parent.setLevel(logging.ERROR)
    try:
        _talk(ddes.World())
    finally:
        parent.setLevel(old)
    assert capsys.readouterr() == ("", "")


def test_the_logging_snippet_of_docs_graph_md_runs(capsys: pytest.CaptureFixture[str]) -> None:
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[2] / "docs" / "graph.md").read_text(encoding="utf-8")
    section = text[text.index("## Logging"):text.index("## Waiting")]
    blocks = re.findall(r"```python\n(.*?)```", section, flags=re.S)
    assert blocks
    for i, block in enumerate(blocks):
        run_snippet(block, "docs/graph.md", f"'Logging' block {i}")
    assert "not shown" not in capsys.readouterr().out
