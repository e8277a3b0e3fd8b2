"""docs/console.md names the TF programs rosrun starts: each one it names is a node type of a
bundled package, and its paragraph stays out of the console's command table."""

from __future__ import annotations

import re
from pathlib import Path

import ddes
from ddes.nodes import load_node_types

ROOT = Path(__file__).resolve().parents[2]


def test_the_tf_programs_named_in_console_md_are_node_types() -> None:
    text = (ROOT / "docs" / "console.md").read_text()
    paragraphs = [" ".join(p.split()) for p in text.split("\n\n")]
    para = next(p for p in paragraphs if "among them the TF programs" in p)
    named = re.findall(r"rosrun\s+(tf2?_?\w*)\s+(\S+?)[`\s]", para)
    assert sorted(set(named)) == [("tf", "static_transform_publisher"), ("tf", "tf_echo"),
                                  ("tf2_ros", "static_transform_publisher"),
                                  ("tf2_tools", "view_frames.py")]
    packages = Path(ddes.__file__).parent / "packages"
    for pkg, node_type in named:
        assert node_type in load_node_types(packages / pkg), (pkg, node_type)
    assert not para.startswith("|")
