"""A message registry and a package path per World: worlds never see each other's types."""

from __future__ import annotations

from pathlib import Path

import pytest

import ddes
from ddes.errors import MsgNotFound
from ddes.msg import default_registry


def _package(root: Path, fields: str) -> Path:
    (root / "hw1" / "msg").mkdir(parents=True)
    (root / "hw1" / "msg" / "Reading.msg").write_text(fields)
    (root / "hw1" / "package.xml").write_text("<package><name>hw1</name></package>\n")
    return root


def test_two_worlds_with_different_package_paths_never_interfere(tmp_path: Path) -> None:
    a = ddes.World(package_path=[_package(tmp_path / "a", "float64 value\n")])
    b = ddes.World(package_path=[_package(tmp_path / "b", "int32 value\nstring unit\n")])
    plain = ddes.World()
    ra = a.messages.get_message_class("hw1/Reading")
    rb = b.messages.get_message_class("hw1/Reading")
    assert ra._md5sum != rb._md5sum and rb().unit == ""
    with pytest.raises(MsgNotFound):
        plain.messages.get_message_class("hw1/Reading")
    assert plain.messages is default_registry()
    string = ddes.get_message_class("std_msgs/String")
    assert a.messages.get_message_class("std_msgs/String") is string
    assert "hw1" in a.rospack and "hw1" not in plain.rospack


def test_a_world_never_reads_the_environment(tmp_path: Path, monkeypatch: pytest.MonkeyPatch
                                             ) -> None:
    monkeypatch.setenv("DDES_PACKAGE_PATH", str(_package(tmp_path, "float64 value\n")))
    world = ddes.World()
    with pytest.raises(MsgNotFound):
        world.messages.get_message_class("hw1/Reading")
    assert "hw1" not in world.rospack


def test_a_single_folder_is_a_package_path(tmp_path: Path) -> None:
    world = ddes.World(package_path=str(_package(tmp_path, "float64 value\n")))
    assert world.messages.get_message_class("hw1/Reading")().value == 0.0


def test_the_console_finds_packages_on_the_world_s_path(tmp_path: Path) -> None:
    world = ddes.World(package_path=[_package(tmp_path, "float64 value\n")])
    console = ddes.Console(world)
    assert console.world is world and console.ctx.rospack is world.rospack
    assert isinstance(ddes.Console().world, ddes.World)
