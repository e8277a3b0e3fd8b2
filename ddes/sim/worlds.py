"""Worlds of the 2D simulator: circles, segments and boxes, from YAML or a Gazebo SDF subset.

A world file is YAML with one key, ``obstacles``, a list of mappings::

    obstacles:
      - {type: circle, name: pillar, x: 20.0, y: 5.0, radius: 1.0}
      - {type: segment, name: wall, x1: -1, y1: 2, x2: 4, y2: 2}
      - {type: box, name: crate, x: 3, y: -1, yaw: 0.3, size_x: 1.0, size_y: 0.5}

(optional top-level keys: ``name``, ``description``).  ``WorldSpec.load(name)`` reads
``ddes_sim/worlds/<name>.yaml`` (or ``.world``) of the bundled package; a path reads that
file.  A ``.world``/``.sdf`` file is read as Gazebo SDF: every ``<model>`` whose collisions
are cylinders (or spheres) and boxes, placed by the model's (and the link's and collision's)
``<pose>``, overridden by a ``<state>`` block's model poses as Gazebo saves them; ground
planes and ``<include>`` (sun, ground_plane) are skipped.

A bad file raises :class:`WorldFileError` naming the file, the entry (index and name) and
the field.  Sizes are bounded (:data:`MAX_OBSTACLES`, :data:`MAX_COORD`, the file size of
:func:`ddes.graph.yamlsafe.read_bounded`) so a hostile file cannot stall the ray caster.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any
from xml.parsers import expat

import yaml

from ddes.errors import DdesValueError, ResourceLimitError
from ddes.graph.yamlsafe import load_yaml, read_bounded
from ddes.sim._trig import sincos

__all__ = ["MAX_COORD", "MAX_OBSTACLES", "BUNDLED_WORLDS", "Box", "Circle", "Obstacle",
           "Segment", "WorldFileError", "WorldSpec", "bundled_world_names"]

#: The most obstacles one world may hold.
MAX_OBSTACLES = 10_000
#: The largest coordinate or size (metres) a world may use.
MAX_COORD = 1.0e6
#: The folder of the bundled worlds (``$(rospack find ddes_sim)/worlds``).
BUNDLED_WORLDS = Path(__file__).resolve().parents[1] / "packages" / "ddes_sim" / "worlds"


class WorldFileError(DdesValueError):
    """A world file that cannot be read: names the file, the entry and the field."""

    def __init__(self, message: str, *, path: str = "", entry: str = "", field: str = ""):
        super().__init__(message)
        self.path = path
        self.entry = entry
        self.field = field


@dataclass(frozen=True)
class Circle:
    """A circle (a pillar, a cylinder) centred at ``(x, y)``."""

    x: float
    y: float
    radius: float
    name: str = ""

    def bounds(self) -> tuple[float, float, float]:
        """A circle holding the obstacle: centre x, y and radius."""
        return self.x, self.y, self.radius


@dataclass(frozen=True)
class Segment:
    """A line segment (a thin wall) from ``(x1, y1)`` to ``(x2, y2)``."""

    x1: float
    y1: float
    x2: float
    y2: float
    name: str = ""

    def bounds(self) -> tuple[float, float, float]:
        cx, cy = 0.5 * (self.x1 + self.x2), 0.5 * (self.y1 + self.y2)
        return cx, cy, 0.5 * math.sqrt((self.x2 - self.x1) ** 2 + (self.y2 - self.y1) ** 2)


@dataclass(frozen=True)
class Box:
    """A rectangle centred at ``(x, y)``, turned by ``yaw``, of ``size_x`` by ``size_y``."""

    x: float
    y: float
    yaw: float
    size_x: float
    size_y: float
    name: str = ""

    def corners(self) -> tuple[tuple[float, float], ...]:
        """The four corners, counter-clockwise from (+x, +y) in the box's frame."""
        s, c = sincos(self.yaw)
        hx, hy = 0.5 * self.size_x, 0.5 * self.size_y
        out = []
        for bx, by in ((hx, hy), (-hx, hy), (-hx, -hy), (hx, -hy)):
            out.append((self.x + c * bx - s * by, self.y + s * bx + c * by))
        return tuple(out)

    def edges(self) -> tuple[Segment, ...]:
        """The four sides as segments."""
        p = self.corners()
        return tuple(Segment(p[i][0], p[i][1], p[(i + 1) % 4][0], p[(i + 1) % 4][1], self.name)
                     for i in range(4))

    def bounds(self) -> tuple[float, float, float]:
        return self.x, self.y, 0.5 * math.sqrt(self.size_x ** 2 + self.size_y ** 2)


Obstacle = Circle | Segment | Box

_FIELDS: dict[str, tuple[str, ...]] = {
    "circle": ("x", "y", "radius"),
    "segment": ("x1", "y1", "x2", "y2"),
    "box": ("x", "y", "yaw", "size_x", "size_y"),
}
_POSITIVE = {"radius", "size_x", "size_y"}


@dataclass(frozen=True)
class WorldSpec:
    """A 2D world: its obstacles (in file order), a name and the file it came from."""

    obstacles: tuple[Obstacle, ...] = ()
    name: str = ""
    source: str = ""

    def __iter__(self) -> Iterator[Obstacle]:
        return iter(self.obstacles)

    def __len__(self) -> int:
        return len(self.obstacles)

    def obstacle(self, name: str) -> Obstacle:
        """The obstacle called ``name``."""
        for ob in self.obstacles:
            if ob.name == name:
                return ob
        known = ", ".join(ob.name for ob in self.obstacles) or "none"
        raise DdesValueError(f"world {self.name!r} has no obstacle {name!r} (it has: {known})")

    def with_obstacles(self, *extra: Obstacle) -> WorldSpec:
        """A copy with ``extra`` obstacles appended (names must stay unique)."""
        spec = WorldSpec(self.obstacles + tuple(extra), self.name, self.source)
        _check_unique(spec.obstacles, self.source or "<python>")
        return spec

    # -- loading -------------------------------------------------------------------------------
    @classmethod
    def load(cls, name_or_path: str | os.PathLike[str]) -> WorldSpec:
        """A bundled world by name (``"single_pillar"``) or a ``.yaml``/``.world`` file by path."""
        text = os.fspath(name_or_path)
        if not text:
            raise WorldFileError("an empty world name; give a bundled name "
                                 f"({', '.join(bundled_world_names())}) or a file path")
        path = Path(text)
        if path.suffix or os.sep in text or "/" in text:
            return cls.from_file(path)
        for suffix in (".yaml", ".world"):
            candidate = BUNDLED_WORLDS / (text + suffix)
            if candidate.is_file():
                return cls.from_file(candidate)
        raise WorldFileError(
            f"no bundled world {text!r}; the bundled worlds are "
            f"{', '.join(bundled_world_names())}, or give the path of a .yaml or .world file",
            path=text)

    @classmethod
    def from_file(cls, path: str | os.PathLike[str]) -> WorldSpec:
        """Read a YAML world (``.yaml``/``.yml``) or a Gazebo SDF world (``.world``/``.sdf``)."""
        where = os.fspath(path)
        data = read_bounded(where, what="world file", error=WorldFileError)
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise WorldFileError(f"{where}: not UTF-8 text ({exc.reason} at byte {exc.start})",
                                 path=where) from None
        if Path(where).suffix in (".world", ".sdf"):
            return cls.from_sdf(text, source=where)
        return cls.from_yaml(text, source=where)

    @classmethod
    def from_yaml(cls, text: str, source: str = "<yaml>") -> WorldSpec:
        """Parse a YAML world (the ``obstacles:`` list)."""
        try:
            doc = load_yaml(text)
        except ResourceLimitError as exc:
            raise WorldFileError(f"{source}: {exc}", path=source) from None
        except yaml.YAMLError as exc:
            raise WorldFileError(f"{source}: not valid YAML: {exc}", path=source) from None
        if doc is None:
            doc = {}
        if not isinstance(doc, dict):
            raise WorldFileError(
                f"{source}: a world file is a mapping with an 'obstacles:' list, got "
                f"{type(doc).__name__}", path=source)
        unknown = sorted(str(k) for k in doc if k not in ("obstacles", "name", "description"))
        if unknown:
            raise WorldFileError(
                f"{source}: unknown top-level key {unknown[0]!r}; a world has 'obstacles' "
                "(and optionally 'name', 'description')", path=source, field=unknown[0])
        items = doc.get("obstacles") or []
        if not isinstance(items, list):
            raise WorldFileError(f"{source}: 'obstacles' must be a list of mappings, got "
                                 f"{type(items).__name__}", path=source, field="obstacles")
        if len(items) > MAX_OBSTACLES:
            raise WorldFileError(f"{source}: {len(items)} obstacles, more than the "
                                 f"{MAX_OBSTACLES} a world may hold", path=source,
                                 field="obstacles")
        obstacles = tuple(_obstacle(item, i, source) for i, item in enumerate(items))
        _check_unique(obstacles, source)
        name = doc.get("name", Path(source).stem)
        return cls(obstacles, str(name), source)

    @classmethod
    def from_sdf(cls, text: str, source: str = "<sdf>") -> WorldSpec:
        """Read the cylinders and boxes of a Gazebo SDF world (see the module text)."""
        root = _parse_xml(text, source)
        world = root if root.tag == "world" else root.find("world")
        if world is None:
            raise WorldFileError(f"{source}: no <world> element (an SDF world is "
                                 "<sdf><world>...</world></sdf>)", path=source, field="world")
        state_poses: dict[str, tuple[float, float, float]] = {}
        for state in world.findall("state"):
            for model in state.findall("model"):
                pose = model.find("pose")
                if pose is not None:
                    state_poses[model.attrs.get("name", "")] = _pose(
                        pose, source, f"<state> model {model.attrs.get('name', '')!r}")
        obstacles: list[Obstacle] = []
        for m_index, model in enumerate(world.findall("model")):
            mname = model.attrs.get("name", f"model_{m_index}")
            entry = f"model {mname!r}"
            pose_el = model.find("pose")
            mpose = state_poses.get(mname) or (
                _pose(pose_el, source, entry) if pose_el is not None else (0.0, 0.0, 0.0))
            shapes = []
            for link in model.findall("link"):
                lpose_el = link.find("pose")
                lpose = _pose(lpose_el, source, entry) if lpose_el is not None else (0., 0., 0.)
                for col in link.findall("collision"):
                    cpose_el = col.find("pose")
                    cpose = (_pose(cpose_el, source, entry) if cpose_el is not None
                             else (0.0, 0.0, 0.0))
                    geom = col.find("geometry")
                    if geom is None:
                        continue
                    shapes.append((_compose(mpose, _compose(lpose, cpose)), geom,
                                   col.attrs.get("name", "collision")))
            for n, (spose, geom, cname) in enumerate(shapes):
                oname = mname if len(shapes) == 1 else f"{mname}/{cname}_{n}"
                ob = _sdf_shape(geom, spose, oname, source, entry)
                if ob is not None:
                    obstacles.append(ob)
            if len(obstacles) > MAX_OBSTACLES:
                raise WorldFileError(f"{source}: more than {MAX_OBSTACLES} obstacles",
                                     path=source, field="model")
        result = tuple(obstacles)
        _check_unique(result, source)
        return cls(result, Path(source).stem, source)  # Gazebo names every world "default"

    def to_yaml(self) -> str:
        """The world as YAML text that :meth:`from_yaml` reads back exactly (float repr)."""
        lines = [f"name: {self.name}", "obstacles:"]
        for ob in self.obstacles:
            values: tuple[float, ...]
            if isinstance(ob, Circle):
                kind, values = "circle", (ob.x, ob.y, ob.radius)
            elif isinstance(ob, Segment):
                kind, values = "segment", (ob.x1, ob.y1, ob.x2, ob.y2)
            else:
                kind, values = "box", (ob.x, ob.y, ob.yaw, ob.size_x, ob.size_y)
            fields = ", ".join(f"{k}: {v!r}" for k, v in zip(_FIELDS[kind], values))
            lines.append(f"  - {{type: {kind}, name: {ob.name}, {fields}}}")
        return "\n".join(lines) + "\n"


def bundled_world_names() -> list[str]:
    """The names of the bundled worlds, sorted."""
    if not BUNDLED_WORLDS.is_dir():
        return []
    return sorted({p.stem for p in BUNDLED_WORLDS.iterdir() if p.suffix in (".yaml", ".world")})


# -- YAML entries ------------------------------------------------------------------------------


def _obstacle(item: Any, index: int, source: str) -> Obstacle:
    entry = f"obstacles[{index}]"
    if not isinstance(item, dict):
        raise WorldFileError(f"{source}: {entry} must be a mapping with a 'type' "
                             f"(circle, segment or box), got {item!r:.80}", path=source,
                             entry=entry)
    name = item.get("name", f"{item.get('type', 'obstacle')}_{index}")
    if not isinstance(name, str) or not name or len(name) > 200:
        raise WorldFileError(f"{source}: {entry}: field 'name' must be a non-empty string of at "
                             f"most 200 characters, got {name!r:.80}", path=source, entry=entry,
                             field="name")
    entry = f"{entry} ({name!r})"
    kind = item.get("type")
    if kind not in _FIELDS:
        raise WorldFileError(f"{source}: {entry}: field 'type' must be circle, segment or box, "
                             f"got {kind!r:.80}", path=source, entry=entry, field="type")
    fields = _FIELDS[kind]
    allowed = {"type", "name", *fields}
    for key in item:
        if key not in allowed:
            raise WorldFileError(
                f"{source}: {entry}: unknown field {key!r} for a {kind} (its fields: "
                f"{', '.join(fields)}, name)", path=source, entry=entry, field=str(key))
    values = []
    for key in fields:
        if key not in item:
            if kind == "box" and key == "yaw":
                values.append(0.0)
                continue
            raise WorldFileError(f"{source}: {entry}: missing field {key!r} (a {kind} needs "
                                 f"{', '.join(fields)})", path=source, entry=entry, field=key)
        values.append(_number(item[key], source, entry, key))
    if kind == "circle":
        return Circle(values[0], values[1], values[2], name)
    if kind == "segment":
        if values[0] == values[2] and values[1] == values[3]:
            raise WorldFileError(f"{source}: {entry}: field 'x2'/'y2': a segment needs two "
                                 "different end points", path=source, entry=entry, field="x2")
        return Segment(values[0], values[1], values[2], values[3], name)
    if abs(values[2]) > 100.0:
        raise WorldFileError(f"{source}: {entry}: field 'yaw' must be an angle in radians of at "
                             f"most 100 in size, got {values[2]!r}", path=source, entry=entry,
                             field="yaw")
    return Box(values[0], values[1], values[2], values[3], values[4], name)


def _number(value: Any, source: str, entry: str, key: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise WorldFileError(f"{source}: {entry}: field {key!r} must be a number (metres), got "
                             f"{value!r:.80}", path=source, entry=entry, field=key)
    x = float(value)
    if not math.isfinite(x) or abs(x) > MAX_COORD:
        raise WorldFileError(f"{source}: {entry}: field {key!r} must be a finite number of at "
                             f"most {MAX_COORD:g} in size, got {value!r}", path=source,
                             entry=entry, field=key)
    if key in _POSITIVE and x <= 0.0:
        raise WorldFileError(f"{source}: {entry}: field {key!r} must be positive, got {value!r}",
                             path=source, entry=entry, field=key)
    return x


def _check_unique(obstacles: tuple[Obstacle, ...], source: str) -> None:
    seen: dict[str, int] = {}
    for i, ob in enumerate(obstacles):
        if ob.name in seen:
            raise WorldFileError(
                f"{source}: obstacles[{i}] ({ob.name!r}): field 'name' repeats obstacles"
                f"[{seen[ob.name]}]'s name; give each obstacle its own name", path=source,
                entry=f"obstacles[{i}]", field="name")
        seen[ob.name] = i


# -- SDF -------------------------------------------------------------------------------------


@dataclass
class _El:
    tag: str
    attrs: Mapping[str, str]
    line: int
    children: list[_El]
    text: str = ""

    def find(self, tag: str) -> _El | None:
        for c in self.children:
            if c.tag == tag:
                return c
        return None

    def findall(self, tag: str) -> list[_El]:
        return [c for c in self.children if c.tag == tag]


_MAX_DEPTH = 64


def _parse_xml(text: str, source: str) -> _El:
    parser = expat.ParserCreate()
    stack: list[_El] = []
    roots: list[_El] = []

    def doctype(name: str, *_: object) -> None:
        raise WorldFileError(f"{source}:{parser.CurrentLineNumber}: <!DOCTYPE {name}> is not "
                             "allowed in a world file (no DTDs or entities); remove it",
                             path=source, field="DOCTYPE")

    def start(tag: str, attrs: dict[str, str]) -> None:
        el = _El(tag, dict(attrs), parser.CurrentLineNumber, [])
        if stack:
            stack[-1].children.append(el)
        else:
            roots.append(el)
        stack.append(el)
        if len(stack) > _MAX_DEPTH:
            raise WorldFileError(f"{source}:{el.line}: elements nested more than {_MAX_DEPTH} "
                                 "deep", path=source, field=tag)

    def end(tag: str) -> None:
        stack.pop()

    def chars(data: str) -> None:
        if stack:
            stack[-1].text += data

    parser.StartDoctypeDeclHandler = doctype
    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.CharacterDataHandler = chars
    try:
        parser.Parse(text, True)
    except expat.ExpatError as exc:
        raise WorldFileError(f"{source}:{exc.lineno}: not well-formed XML: "
                             f"{expat.ErrorString(exc.code)} (column {exc.offset})",
                             path=source) from None
    if not roots:
        raise WorldFileError(f"{source}: empty XML", path=source)
    return roots[0]


def _floats(el: _El, n: int, source: str, entry: str) -> list[float]:
    parts = el.text.split()
    try:
        values = [float(p) for p in parts]
    except ValueError:
        values = []
    if len(values) != n or not all(math.isfinite(v) and abs(v) <= MAX_COORD for v in values):
        raise WorldFileError(f"{source}:{el.line}: {entry}: field <{el.tag}> must hold {n} finite "
                             f"numbers, got {el.text.strip()!r:.80}", path=source, entry=entry,
                             field=el.tag)
    return values


def _pose(el: _El, source: str, entry: str) -> tuple[float, float, float]:
    x, y, _z, roll, pitch, yaw = _floats(el, 6, source, entry)
    if roll != 0.0 or pitch != 0.0:
        raise WorldFileError(f"{source}:{el.line}: {entry}: field <pose> tilts the shape (roll "
                             f"{roll!r}, pitch {pitch!r}); the 2D simulator takes upright "
                             "shapes only", path=source, entry=entry, field="pose")
    return x, y, yaw


def _compose(a: tuple[float, float, float],
             b: tuple[float, float, float]) -> tuple[float, float, float]:
    s, c = sincos(a[2])
    return a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], a[2] + b[2]


def _sdf_shape(geom: _El, pose: tuple[float, float, float], name: str, source: str,
               entry: str) -> Obstacle | None:
    for child in geom.children:
        if child.tag in ("cylinder", "sphere"):
            r_el = child.find("radius")
            if r_el is None:
                raise WorldFileError(f"{source}:{child.line}: {entry}: <{child.tag}> without "
                                     "field <radius>", path=source, entry=entry, field="radius")
            (r,) = _floats(r_el, 1, source, entry)
            if r <= 0.0:
                raise WorldFileError(f"{source}:{r_el.line}: {entry}: field <radius> must be "
                                     f"positive, got {r!r}", path=source, entry=entry,
                                     field="radius")
            return Circle(pose[0], pose[1], r, name)
        if child.tag == "box":
            s_el = child.find("size")
            if s_el is None:
                raise WorldFileError(f"{source}:{child.line}: {entry}: <box> without field "
                                     "<size>", path=source, entry=entry, field="size")
            sx, sy, _sz = _floats(s_el, 3, source, entry)
            if sx <= 0.0 or sy <= 0.0:
                raise WorldFileError(f"{source}:{s_el.line}: {entry}: field <size> must be "
                                     f"positive, got {s_el.text.strip()!r}", path=source,
                                     entry=entry, field="size")
            return Box(pose[0], pose[1], pose[2], sx, sy, name)
        if child.tag == "plane":
            return None  # the ground
        raise WorldFileError(f"{source}:{child.line}: {entry}: field <geometry> holds "
                             f"<{child.tag}>; the 2D simulator reads cylinders, spheres, boxes "
                             "and planes (the ground) only", path=source, entry=entry,
                             field=child.tag)
    return None


def generate_obstacle_field(seed: int = 2026, count: int = 40) -> WorldSpec:
    """The bundled ``obstacle_field`` world: ``count`` pillars and crates drawn from ``seed``.

    Centres lie in x 2..30 m, y -10..10 m (so the robot's footprint at the origin is free),
    each value rounded to millimetres (``round`` is exact on every machine).  The committed
    ``worlds/obstacle_field.yaml`` is ``generate_obstacle_field().to_yaml()``
    (tests/sim/test_worlds.py checks it).
    """
    import random

    rng = random.Random(seed)
    out: list[Obstacle] = []
    while len(out) < count:
        x = round(rng.uniform(2.0, 30.0), 3)
        y = round(rng.uniform(-10.0, 10.0), 3)
        if rng.random() < 0.6:
            out.append(Circle(x, y, round(rng.uniform(0.15, 0.8), 3), f"pillar_{len(out)}"))
        else:
            out.append(Box(x, y, round(rng.uniform(-1.5, 1.5), 3), round(rng.uniform(0.3, 1.5), 3),
                           round(rng.uniform(0.3, 1.5), 3), f"crate_{len(out)}"))
    return WorldSpec(tuple(out), "obstacle_field", "")
