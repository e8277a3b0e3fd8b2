"""World files: every bundled world loads; the SDF reader; bad files give typed errors."""

from __future__ import annotations

from pathlib import Path

import pytest

from ddes.errors import DdesValueError
from ddes.sim import Box, Circle, Segment, WorldFileError, WorldSpec, bundled_world_names
from ddes.sim.worlds import BUNDLED_WORLDS, MAX_OBSTACLES, generate_obstacle_field


def test_every_bundled_world_loads() -> None:
    names = bundled_world_names()
    assert names == ["corridor", "empty", "obstacle_field", "pillars_field", "robocup_field",
                     "single_pillar"]
    for name in names:
        spec = WorldSpec.load(name)
        assert spec.name == name and (len(spec) > 0) == (name != "empty")
    assert WorldSpec.load("single_pillar").obstacles == (Circle(20.0, 5.0, 1.0, "pillar"),)


def test_the_sdf_single_pillar_is_the_yaml_one() -> None:
    sdf = WorldSpec.load(BUNDLED_WORLDS / "single_pillar.world")
    assert sdf.obstacles == WorldSpec.load("single_pillar").obstacles


def test_obstacle_field_is_the_generator_output() -> None:
    committed = WorldSpec.load("obstacle_field")
    generated = generate_obstacle_field()
    assert committed.obstacles == generated.obstacles
    assert (BUNDLED_WORLDS / "obstacle_field.yaml").read_text().endswith(generated.to_yaml())
    assert WorldSpec.from_yaml(generated.to_yaml()).obstacles == generated.obstacles


SDF_GAZEBO_SAVED = """<?xml version="1.0" ?>
<sdf version="1.6">
  <world name="default">
    <include><uri>model://ground_plane</uri></include>
    <model name="ground"><static>1</static><link name="l"><collision name="c">
      <geometry><plane><normal>0 0 1</normal><size>100 100</size></plane></geometry>
    </collision></link></model>
    <model name="pillar">
      <pose frame="">1 1 0.5 0 -0 0</pose>
      <link name="link"><collision name="collision">
        <geometry><cylinder><radius>0.5</radius><length>1</length></cylinder></geometry>
      </collision></link>
    </model>
    <model name="crate">
      <pose>0 0 0 0 0 1.5707963267948966</pose>
      <link name="link"><pose>2 0 0 0 0 0</pose><collision name="collision">
        <geometry><box><size>1 0.5 1</size></box></geometry>
      </collision></link>
    </model>
    <state world_name="default">
      <model name="pillar"><pose frame="">3 4 0.5 0 0 0</pose></model>
    </state>
  </world>
</sdf>
"""


def test_sdf_poses_compose_and_state_overrides() -> None:
    spec = WorldSpec.from_sdf(SDF_GAZEBO_SAVED, "saved.world")
    pillar, crate = spec.obstacles
    assert pillar == Circle(3.0, 4.0, 0.5, "pillar")  # the <state> pose wins
    assert isinstance(crate, Box) and crate.size_x == 1.0 and crate.size_y == 0.5
    assert crate.x == pytest.approx(0.0, abs=1e-15) and crate.y == pytest.approx(2.0)
    assert crate.yaw == pytest.approx(1.5707963267948966)


def write(tmp_path: Path, text: str, name: str = "w.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


BAD_YAML = [
    ("obstacles: 3\n", None, "obstacles", "must be a list"),
    ("[1, 2]\n", None, "", "a world file is a mapping"),
    ("obstacle: []\n", None, "obstacle", "unknown top-level key"),
    ("obstacles:\n  - 5\n", "obstacles[0]", "", "must be a mapping"),
    ("obstacles:\n  - {type: cone, name: a, x: 1}\n", "obstacles[0] ('a')", "type",
     "must be circle, segment or box"),
    ("obstacles:\n  - {type: circle, name: p, x: 1, y: 2}\n", "obstacles[0] ('p')", "radius",
     "missing field 'radius'"),
    ("obstacles:\n  - {type: circle, name: p, x: 1, y: 2, radius: -1}\n", "obstacles[0] ('p')",
     "radius", "must be positive"),
    ("obstacles:\n  - {type: circle, name: p, x: true, y: 2, radius: 1}\n", "obstacles[0] ('p')",
     "x", "must be a number"),
    ("obstacles:\n  - {type: circle, name: p, x: .nan, y: 2, radius: 1}\n",
     "obstacles[0] ('p')", "x", "finite number"),
    ("obstacles:\n  - {type: circle, name: p, x: 1.0e+9, y: 2, radius: 1}\n",
     "obstacles[0] ('p')", "x", "finite number"),
    ("obstacles:\n  - {type: circle, name: p, x: 1, y: 2, radius: 1, colour: red}\n",
     "obstacles[0] ('p')", "colour", "unknown field"),
    ("obstacles:\n  - {type: segment, name: s, x1: 1, y1: 1, x2: 1, y2: 1}\n",
     "obstacles[0] ('s')", "x2", "two different end points"),
    ("obstacles:\n  - {type: box, name: b, x: 0, y: 0, size_x: 0, size_y: 1}\n",
     "obstacles[0] ('b')", "size_x", "must be positive"),
    ("obstacles:\n  - {type: circle, name: p, x: 1, y: 2, radius: 1}\n"
     "  - {type: circle, name: p, x: 5, y: 2, radius: 1}\n", "obstacles[1]", "name",
     "repeats obstacles[0]"),
    ("obstacles:\n  - {type: circle, name: 7, x: 1, y: 2, radius: 1}\n", "obstacles[0]", "name",
     "non-empty string"),
    ("obstacles: [\n", None, "", "not valid YAML"),
]


@pytest.mark.parametrize("text, entry, field, words", BAD_YAML)
def test_bad_yaml_worlds_name_file_entry_and_field(tmp_path: Path, text: str, entry: str | None,
                                                   field: str, words: str) -> None:
    path = write(tmp_path, text)
    with pytest.raises(WorldFileError) as info:
        WorldSpec.load(path)
    err = info.value
    message = str(err)
    assert isinstance(err, DdesValueError) and isinstance(err, ValueError)
    assert str(path) in message and err.path == str(path) and words in message
    if entry is not None:
        assert entry in message and err.entry.startswith(entry.split(" ")[0])
    if field:
        assert repr(field) in message or f"<{field}>" in message
        assert err.field == field


def test_too_many_obstacles(tmp_path: Path) -> None:
    text = "obstacles:\n" + "".join(
        f"  - {{type: circle, x: {i}, y: 0, radius: 0.1}}\n" for i in range(MAX_OBSTACLES + 1))
    with pytest.raises(WorldFileError, match="more than the 10000"):
        WorldSpec.load(write(tmp_path, text))


def test_yaml_alias_bomb_is_refused(tmp_path: Path) -> None:
    bomb = "a: &a [1,1,1,1,1,1,1,1,1]\n" + "".join(
        f"{c}: &{c} [{', '.join(['*' + p] * 9)}]\n"
        for p, c in zip("abcdefgh", "bcdefghi")) + "obstacles: []\n"
    with pytest.raises(WorldFileError, match="w.yaml"):
        WorldSpec.load(write(tmp_path, bomb))


BAD_SDF = [
    ('<?xml version="1.0"?><!DOCTYPE x [<!ENTITY a "b">]><sdf><world/></sdf>', "DOCTYPE",
     "not allowed"),
    ("<sdf><world><model name='m'><pose>1 2 0 0.1 0 0</pose><link><collision><geometry>"
     "<box><size>1 1 1</size></box></geometry></collision></link></model></world></sdf>",
     "pose", "tilts"),
    ("<sdf><world><model name='m'><link><collision><geometry><mesh><uri>x</uri></mesh>"
     "</geometry></collision></link></model></world></sdf>", "mesh", "cylinders"),
    ("<sdf><world><model name='m'><link><collision><geometry><cylinder><radius>-1</radius>"
     "</cylinder></geometry></collision></link></model></world></sdf>", "radius", "positive"),
    ("<sdf><world><model name='m'><link><collision><geometry><box><size>1 1</size></box>"
     "</geometry></collision></link></model></world></sdf>", "size", "3 finite numbers"),
    ("<sdf><model name='m'/></sdf>", "world", "no <world>"),
    ("<sdf><world>", "", "not well-formed"),
]


@pytest.mark.parametrize("text, field, words", BAD_SDF)
def test_bad_sdf_worlds(tmp_path: Path, text: str, field: str, words: str) -> None:
    path = write(tmp_path, text, "bad.world")
    with pytest.raises(WorldFileError) as info:
        WorldSpec.load(path)
    assert str(path) in str(info.value) and words in str(info.value)
    assert info.value.field == field
    if field not in ("", "world", "DOCTYPE"):
        assert "model 'm'" in str(info.value)


def test_missing_and_unknown_names(tmp_path: Path) -> None:
    with pytest.raises(WorldFileError, match="no bundled world 'nope'.*single_pillar"):
        WorldSpec.load("nope")
    with pytest.raises(WorldFileError, match="not found"):
        WorldSpec.load(tmp_path / "missing.yaml")
    (tmp_path / "dir.yaml").mkdir()
    with pytest.raises(WorldFileError, match="is a directory"):
        WorldSpec.load(tmp_path / "dir.yaml")


def test_python_built_worlds() -> None:
    spec = WorldSpec((Circle(1, 2, 0.5, "a"),), "mine").with_obstacles(Segment(0, 0, 1, 0, "s"))
    assert [ob.name for ob in spec] == ["a", "s"] and spec.obstacle("s").name == "s"
    with pytest.raises(WorldFileError, match="repeats"):
        spec.with_obstacles(Circle(5, 5, 1, "a"))
    with pytest.raises(DdesValueError, match="no obstacle 'x'"):
        spec.obstacle("x")
