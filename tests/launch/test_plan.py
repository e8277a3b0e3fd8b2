"""The plan's data classes and its roslaunch-style SUMMARY."""

from __future__ import annotations

import pytest

from ddes.errors import DdesKeyError
from ddes.launch import LaunchPlan, NodeSpec, RosparamCommand


def test_summary_layout() -> None:
    plan = LaunchPlan(
        params={"/b": True, "/a/long": "x" * 30, "/bin": b"\x00\x01", "/n": 3,
                "/text": "two\nlines"},
        clear_params=["/g/"],
        nodes=[NodeSpec("pkg", "t.py", "zed"), NodeSpec("pkg", "t.py", "alpha"),
               NodeSpec("other", "bin", "n", namespace="/g/")],
    )
    assert plan.to_text() == (
        "SUMMARY\n"
        "========\n"
        "\n"
        "CLEAR PARAMETERS\n"
        " * /g/\n"
        "\n"
        "PARAMETERS\n"
        " * /a/long: xxxxxxxxxxxxxxxxx...\n"
        " * /b: True\n"
        " * /bin: <...>\n"
        " * /n: 3\n"
        " * /text: <...>\n"
        "\n"
        "NODES\n"
        "  /\n"
        "    alpha (pkg/t.py)\n"
        "    zed (pkg/t.py)\n"
        "  /g/\n"
        "    n (other/bin)\n"
    )


def test_empty_summary() -> None:
    assert LaunchPlan().to_text() == "SUMMARY\n========\n\nNODES\n"


def test_trailing_whitespace_before_unprintable_is_not_hidden() -> None:
    # roslaunch strips trailing whitespace and keeps the value when nothing else is hidden
    assert "* /t: abc" in LaunchPlan(params={"/t": "abc\n"}).to_text()


def test_node_lookup_and_deletions() -> None:
    plan = LaunchPlan(nodes=[NodeSpec("p", "t", "n", namespace="/r/")],
                      rosparam_commands=[RosparamCommand("delete", "/a"),
                                         RosparamCommand("dump", "/", "f.yaml"),
                                         RosparamCommand("delete", "/b")])
    assert plan.node("/r/n").name == "n"
    assert plan.deletions == ["/a", "/b"]
    with pytest.raises(DdesKeyError, match=r"no node named '/n'.*nodes: /r/n"):
        plan.node("/n")
