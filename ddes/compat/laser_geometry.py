"""``laser_geometry`` of ROS Noetic (its Python half): project a LaserScan into a PointCloud2.

In a rospy script, ``from laser_geometry import LaserProjection`` resolves here.  Follows
Noetic's ``laser_geometry/laser_geometry.py``:

* ``LaserProjection().projectLaser(scan_in, range_cutoff=-1.0,
  channel_options=LaserProjection.ChannelOption.DEFAULT)`` returns a ``sensor_msgs/PointCloud2``
  in the scan's frame (its header), built by :func:`ddes.compat.point_cloud2.create_cloud`:
  float32 fields ``x``, ``y``, ``z`` (``z`` 0), then, as the options ask, ``intensity``
  (float32, only when the scan has intensities), ``index`` (int32), ``distances`` (float32),
  ``stamps`` (float32, ``i * time_increment``) and ``vp_x``, ``vp_y``, ``vp_z`` (float32, 0),
  packed in that order at offsets 12, 16, ...;
* a reading becomes a point when ``range_min <= r < cutoff``, the cutoff being ``range_max``, or
  ``min(range_cutoff, range_max)`` when ``range_cutoff >= 0``; point ``i`` is
  ``(r cos a_i, r sin a_i, 0)`` with ``a_i = angle_min + i * angle_increment`` in double
  precision;
* the table of cosines and sines is kept between calls and made again when the number of
  readings, ``angle_min`` or ``angle_max`` changes (as Noetic; a change of ``angle_increment``
  alone keeps the old table there too), with the debug line ``No precomputed map given.
  Computing one.``;
* :class:`ChannelOption` (``NONE``, ``INTENSITY``, ``INDEX``, ``DISTANCE``, ``TIMESTAMP``,
  ``VIEWPOINT``, ``DEFAULT``), nested in :class:`LaserProjection` as in Noetic, and the class
  constants ``LASER_SCAN_INVALID``, ``LASER_SCAN_MIN_RANGE``, ``LASER_SCAN_MAX_RANGE``.

Deliberate deviations:

* the sines and cosines are :func:`ddes.transformations.sin` / :func:`~ddes.transformations.cos`
  (deterministic, fdlibm's algorithm, within an ulp), not numpy's, whose results differ by an
  ulp between CPUs and libms: a point's double-precision coordinates can differ from Noetic's
  numpy result by an ulp (before rounding to float32, so the packed floats agree nearly always);
* no numpy: the table is plain lists (``projectLaser`` returns the same message);
* ``ChannelOption`` is also a module attribute (``laser_geometry.ChannelOption``, which Noetic's
  package does not export); the submodule ``laser_geometry.laser_geometry`` is not provided.
"""

from __future__ import annotations

from typing import Any

from ddes.compat import point_cloud2 as _pc2
from ddes.compat import rospy as _rospy
from ddes.transformations import cos, sin

__all__ = ["ChannelOption", "LaserProjection"]


class _ChannelOption:
    """The channels :meth:`LaserProjection.projectLaser` can add (OR them together)."""

    NONE = 0x00  #: no channel
    INTENSITY = 0x01  #: "intensity"
    INDEX = 0x02  #: "index"
    DISTANCE = 0x04  #: "distances"
    TIMESTAMP = 0x08  #: "stamps"
    VIEWPOINT = 0x10  #: "vp_x", "vp_y", "vp_z"
    DEFAULT = INTENSITY | INDEX


class LaserProjection:
    """Projects ``sensor_msgs/LaserScan`` messages into ``sensor_msgs/PointCloud2`` ones,
    keeping the unit vectors between calls while the scan's geometry stays the same.

    Readings outside ``[range_min, range_max)`` are dropped (as assumed invalid), so a point's
    position in the cloud is not its reading's index: ask for the ``index`` channel
    (``ChannelOption.INDEX``, on by default) to map points back to readings.
    """

    LASER_SCAN_INVALID = -1.0
    LASER_SCAN_MIN_RANGE = -2.0
    LASER_SCAN_MAX_RANGE = -3.0

    ChannelOption = _ChannelOption

    def __init__(self) -> None:
        self.__angle_min = 0.0
        self.__angle_max = 0.0
        self.__cos_sin_map: tuple[list[float], list[float]] = ([], [])

    def projectLaser(self, scan_in: Any, range_cutoff: float = -1.0,
                     channel_options: int = _ChannelOption.DEFAULT) -> Any:
        """The point cloud of ``scan_in`` (see the module docstring).

        ``range_cutoff``, when not negative, is a range limit tighter than the scan's
        ``range_max``; ``channel_options`` an OR of :class:`ChannelOption` values.
        """
        ranges = list(scan_in.ranges)
        count = len(ranges)
        cosines, sines = self.__unit_vectors(scan_in, count)
        _, field_class = _pc2._classes()

        layout: list[tuple[str, int]] = [("x", _pc2._FLOAT32), ("y", _pc2._FLOAT32),
                                         ("z", _pc2._FLOAT32)]
        intensities = scan_in.intensities
        with_intensity = bool(channel_options & _ChannelOption.INTENSITY) and len(intensities) > 0
        with_index = bool(channel_options & _ChannelOption.INDEX)
        with_distance = bool(channel_options & _ChannelOption.DISTANCE)
        with_stamp = bool(channel_options & _ChannelOption.TIMESTAMP)
        with_viewpoint = bool(channel_options & _ChannelOption.VIEWPOINT)
        if with_intensity:
            layout.append(("intensity", _pc2._FLOAT32))
        if with_index:
            layout.append(("index", _pc2._INT32))
        if with_distance:
            layout.append(("distances", _pc2._FLOAT32))
        if with_stamp:
            layout.append(("stamps", _pc2._FLOAT32))
        if with_viewpoint:
            layout.extend((name, _pc2._FLOAT32) for name in ("vp_x", "vp_y", "vp_z"))
        fields = [field_class(name=name, offset=4 * i, datatype=datatype, count=1)
                  for i, (name, datatype) in enumerate(layout)]

        cutoff = scan_in.range_max if range_cutoff < 0 else min(range_cutoff, scan_in.range_max)
        range_min = scan_in.range_min
        points: list[list[Any]] = []
        for i, r in enumerate(ranges):
            if not (r < cutoff and r >= range_min):
                continue
            point: list[Any] = [r * cosines[i], r * sines[i], 0]
            if with_intensity:
                point.append(intensities[i])
            if with_index:
                point.append(i)
            if with_distance:
                point.append(r)
            if with_stamp:
                point.append(i * scan_in.time_increment)
            if with_viewpoint:
                point.extend((0, 0, 0))
            points.append(point)
        return _pc2.create_cloud(scan_in.header, fields, points)

    def __unit_vectors(self, scan_in: Any, count: int) -> tuple[list[float], list[float]]:
        """The cosines and sines of the scan's angles, made again when its geometry changed."""
        cosines, _ = self.__cos_sin_map
        if (len(cosines) != count or self.__angle_min != scan_in.angle_min
                or self.__angle_max != scan_in.angle_max):
            _rospy.logdebug("No precomputed map given. Computing one.")
            self.__angle_min = scan_in.angle_min
            self.__angle_max = scan_in.angle_max
            start, step = scan_in.angle_min, scan_in.angle_increment
            angles = [start + float(i) * step for i in range(count)]
            self.__cos_sin_map = ([cos(a) for a in angles], [sin(a) for a in angles])
        return self.__cos_sin_map


#: :attr:`LaserProjection.ChannelOption` (a ddes convenience: Noetic has it in the class only).
ChannelOption = _ChannelOption
