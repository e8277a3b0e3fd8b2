"""``sensor_msgs.point_cloud2`` of ROS Noetic: read and build ``sensor_msgs/PointCloud2``.

In a rospy script, ``from sensor_msgs import point_cloud2`` and ``import
sensor_msgs.point_cloud2 as pc2`` resolve here (:data:`ddes.compat.scripts.PACKAGE_MODULES`).
Follows Noetic's ``sensor_msgs/point_cloud2.py``:

* :func:`read_points` is a generator of one tuple per point (``struct.unpack_from`` of the
  fields asked for, in offset order), row by row, or at the ``(u, v)`` pixels of ``uvs``;
  ``skip_nans`` drops every point with a NaN value;
* :func:`read_points_list` the same as a list of namedtuples ``Point``;
* :func:`create_cloud` packs the points little-endian with the fields' layout into an
  unorganised cloud (``height=1``, ``is_dense=False``), :func:`create_cloud_xyz32` with three
  float32 fields ``x, y, z``: the cloud's ``data`` is byte for byte what Noetic builds;
* :data:`_DATATYPES` (PointField datatype -> struct code and size) and
  :func:`_get_struct_fmt` (the struct format of a field list, ``x`` pad bytes for gaps).

The message classes are those of the running world (:func:`_classes`): the classes of the
world whose script calls, else ddes's bundled ones; ``read_points`` accepts any ddes
``sensor_msgs/PointCloud2``.

Deliberate deviations:

* a field of unknown datatype is skipped with ``Skipping unknown PointField datatype [N]`` on
  the script's standard error, as the Noetic code means to (Noetic itself raises ``NameError``
  there: its module uses ``sys`` without importing it);
* ``points`` of :func:`create_cloud` may be any iterable (Noetic needs ``len()``), and a
  cloud's ``data`` given as a list of ints is read as bytes;
* ``uvs`` defaults to an empty tuple instead of a shared empty list (the same behaviour).
"""

from __future__ import annotations

import math
import struct
import sys
from collections import namedtuple
from collections.abc import Container, Iterable, Iterator, Sequence
from typing import TYPE_CHECKING, Any

from ddes.graph.blocking import current_task
from ddes.msg import Message, default_registry

if TYPE_CHECKING:
    from ddes.msg import MessageRegistry

__all__ = ["create_cloud", "create_cloud_xyz32", "read_points", "read_points_list"]

# sensor_msgs/PointField's datatype constants.
_INT8, _UINT8, _INT16, _UINT16, _INT32, _UINT32, _FLOAT32, _FLOAT64 = range(1, 9)

#: PointField datatype -> (struct format character, size in bytes), as Noetic's table.
_DATATYPES: dict[int, tuple[str, int]] = {
    _INT8: ("b", 1),
    _UINT8: ("B", 1),
    _INT16: ("h", 2),
    _UINT16: ("H", 2),
    _INT32: ("i", 4),
    _UINT32: ("I", 4),
    _FLOAT32: ("f", 4),
    _FLOAT64: ("d", 8),
}

_NOT_A_CLOUD = "cloud is not a sensor_msgs.msg.PointCloud2"


def _registry() -> MessageRegistry:
    """The message types of the world whose code runs now (ddes's bundled ones outside any)."""
    task = current_task()
    return task.world.messages if task is not None else default_registry()


def _classes() -> tuple[Any, Any]:
    """The running world's ``sensor_msgs/PointCloud2`` and ``sensor_msgs/PointField``."""
    registry = _registry()
    return (registry.get_message_class("sensor_msgs/PointCloud2"),
            registry.get_message_class("sensor_msgs/PointField"))


def _warn(text: str) -> None:
    """``text`` on the standard error of the running script (the real one outside scripts)."""
    task = current_task()
    printer = getattr(task.context, "print_line", None) if task is not None else None
    if printer is not None:
        printer(text, True)
    else:
        print(text, file=sys.stderr)


def _get_struct_fmt(is_bigendian: bool, fields: Iterable[Any],
                    field_names: Iterable[str] | None = None) -> str:
    """The :mod:`struct` format of one point: the fields (those named in ``field_names``, or
    all) in offset order, ``x`` pad bytes for the gaps before them, ``>`` or ``<`` first."""
    names = field_names if field_names is None or isinstance(field_names, Container) \
        else list(field_names)
    parts = [">" if is_bigendian else "<"]
    position = 0
    for field in sorted(fields, key=lambda f: f.offset):
        if names is not None and field.name not in names:
            continue
        if field.offset > position:
            parts.append("x" * (field.offset - position))
            position = field.offset
        known = _DATATYPES.get(field.datatype)
        if known is None:
            _warn(f"Skipping unknown PointField datatype [{field.datatype}]")
            continue
        code, size = known
        parts.append(code * field.count)
        position += size * field.count
    return "".join(parts)


def _check_cloud(cloud: Any) -> None:
    assert isinstance(cloud, Message) and cloud._type == "sensor_msgs/PointCloud2", _NOT_A_CLOUD


def _has_nan(values: tuple[Any, ...]) -> bool:
    return any(math.isnan(v) for v in values)


def read_points(cloud: Any, field_names: Iterable[str] | None = None, skip_nans: bool = False,
                uvs: Iterable[Sequence[int]] = ()) -> Iterator[tuple[Any, ...]]:
    """Yield the points of ``cloud`` as tuples of the values of ``field_names`` (all fields
    when None), in field-offset order; only those at the ``(u, v)`` pairs of ``uvs`` when it is
    given; without the points holding a NaN when ``skip_nans``."""
    _check_cloud(cloud)
    unpack_from = struct.Struct(_get_struct_fmt(cloud.is_bigendian, cloud.fields,
                                                field_names)).unpack_from
    data = cloud.data
    if isinstance(data, (list, tuple)):
        data = bytes(data)
    point_step, row_step = cloud.point_step, cloud.row_step
    if uvs:
        offsets: Iterable[int] = (row_step * v + point_step * u for u, v in uvs)
    else:
        offsets = (row_step * v + point_step * u
                   for v in range(cloud.height) for u in range(cloud.width))
    for offset in offsets:
        point = unpack_from(data, offset)
        if skip_nans and _has_nan(point):
            continue
        yield point


def read_points_list(cloud: Any, field_names: Iterable[str] | None = None,
                     skip_nans: bool = False,
                     uvs: Iterable[Sequence[int]] = ()) -> list[Any]:
    """:func:`read_points` as a list of namedtuples ``Point`` (one attribute per field name)."""
    _check_cloud(cloud)
    names = [f.name for f in cloud.fields] if field_names is None else list(field_names)
    point_class = namedtuple("Point", names)  # type: ignore[misc]  # names known at run time
    return [point_class._make(p) for p in read_points(cloud, names, skip_nans, uvs)]


def create_cloud(header: Any, fields: Sequence[Any], points: Iterable[Iterable[Any]]) -> Any:
    """A ``sensor_msgs/PointCloud2`` of ``points`` (one sequence of field values each, in the
    order of ``fields``) packed little-endian: ``height`` 1, ``width`` the number of points,
    ``is_dense`` False; ``header`` and ``fields`` are used as given."""
    point_class, _ = _classes()
    packer = struct.Struct(_get_struct_fmt(False, fields))
    rows = points if isinstance(points, Sequence) else list(points)
    step = packer.size
    buffer = bytearray(step * len(rows))
    offset = 0
    for p in rows:
        packer.pack_into(buffer, offset, *p)
        offset += step
    return point_class(header=header, height=1, width=len(rows), is_dense=False,
                       is_bigendian=False, fields=fields, point_step=step,
                       row_step=step * len(rows), data=bytes(buffer))


def create_cloud_xyz32(header: Any, points: Iterable[Iterable[Any]]) -> Any:
    """:func:`create_cloud` with three float32 fields ``x``, ``y``, ``z`` (offsets 0, 4, 8)."""
    _, field_class = _classes()
    fields = [field_class(name, offset, _FLOAT32, 1)
              for name, offset in (("x", 0), ("y", 4), ("z", 8))]
    return create_cloud(header, fields, points)


def __getattr__(name: str) -> Any:
    """``pc2.PointCloud2`` and ``pc2.PointField`` (Noetic's module imports them): the running
    world's classes."""
    if name == "PointCloud2":
        return _classes()[0]
    if name == "PointField":
        return _classes()[1]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
