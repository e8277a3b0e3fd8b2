"""A PointCloud2 flattened to a LaserScan, as ``pointcloud_to_laserscan`` (noetic) does it.

On the SMB the laser is a VLP-16 publishing ``/rslidar_points`` and the ``pointcloud_to_laserscan``
node makes ``/scan`` of it.  :func:`cloud_to_ranges` is that node's ``cloudCb``: the ranges start
at +inf (``use_inf``) or ``range_max + inf_epsilon``; each point with finite x, y, z and
``min_height <= z <= max_height`` has its planar range ``sqrt(x*x + y*y)`` (upstream's ``hypot``)
and bearing ``atan2(y, x)``; points outside ``[range_min, range_max]`` or
``[angle_min, angle_max]`` are skipped, the rest go to bin
``int((angle - angle_min) / angle_increment)`` (truncated, as the C++ ``int`` conversion does),
keeping the nearest.  There are ``ceil((angle_max - angle_min) / angle_increment)`` bins; a point
at exactly ``angle_max`` would fall one past the last bin (upstream writes out of bounds) and is
skipped here.

Only IEEE basic operations, ``math.sqrt`` and :func:`ddes.sim._trig.atan2`: the same cloud gives
the same scan on every machine.
"""

from __future__ import annotations

import math
import struct
from typing import TYPE_CHECKING

from ddes.errors import DdesValueError
from ddes.sim._trig import atan2

if TYPE_CHECKING:
    from ddes.msg.message import Message

__all__ = ["cloud_to_ranges", "cloud_xyz"]

_INF = float("inf")
_FORMATS = {7: "f", 8: "d"}  # PointField FLOAT32, FLOAT64


def cloud_xyz(cloud: Message) -> list[tuple[float, float, float]]:
    """The x, y, z of every point of a sensor_msgs/PointCloud2 (FLOAT32 or FLOAT64 fields)."""
    found = {}
    for f in cloud.fields:
        if f.name in ("x", "y", "z"):
            if f.datatype not in _FORMATS:
                raise DdesValueError(f"PointCloud2 field {f.name!r} has datatype {f.datatype}; "
                                     "pointcloud_to_laserscan reads FLOAT32 (7) or FLOAT64 (8)")
            found[f.name] = (f.offset, _FORMATS[f.datatype])
    missing = [n for n in ("x", "y", "z") if n not in found]
    if missing:
        raise DdesValueError(f"PointCloud2 has no field {missing[0]!r} (fields: "
                             f"{[f.name for f in cloud.fields]}); it needs x, y and z")
    step = int(cloud.point_step)
    n = int(cloud.width) * int(cloud.height)
    data = bytes(cloud.data)
    if n and (step <= 0 or len(data) < n * step):
        raise DdesValueError(f"PointCloud2 of {n} points with point_step {step} needs "
                             f"{n * step} bytes of data, has {len(data)}")
    end = ">" if cloud.is_bigendian else "<"
    (ox, fx), (oy, fy), (oz, fz) = found["x"], found["y"], found["z"]
    if (fx, fy, fz) == ("f", "f", "f") and (ox, oy, oz) == (0, 4, 8):
        fmt = struct.Struct(f"{end}3f{step - 12}x") if step >= 12 else None
        if fmt is not None:
            return list(fmt.iter_unpack(data[:n * step]))
    ux, uy, uz = (struct.Struct(end + fx), struct.Struct(end + fy), struct.Struct(end + fz))
    return [(ux.unpack_from(data, i * step + ox)[0], uy.unpack_from(data, i * step + oy)[0],
             uz.unpack_from(data, i * step + oz)[0]) for i in range(n)]


def cloud_to_ranges(points: list[tuple[float, float, float]], angle_min: float,
                    angle_max: float, angle_increment: float, range_min: float,
                    range_max: float, min_height: float, max_height: float,
                    use_inf: bool = True, inf_epsilon: float = 1.0) -> list[float]:
    """The ranges of the scan ``pointcloud_to_laserscan`` makes of ``points`` (module text)."""
    size = math.ceil((angle_max - angle_min) / angle_increment)
    ranges = [_INF if use_inf else range_max + inf_epsilon] * max(size, 0)
    sqrt = math.sqrt
    for x, y, z in points:
        if x != x or y != y or z != z:  # NaN
            continue
        if z > max_height or z < min_height:
            continue
        r = sqrt(x * x + y * y)
        if r < range_min or r > range_max:
            continue
        a = atan2(y, x)
        if a < angle_min or a > angle_max:
            continue
        i = int((a - angle_min) / angle_increment)
        if i < size and r < ranges[i]:
            ranges[i] = r
    return ranges
