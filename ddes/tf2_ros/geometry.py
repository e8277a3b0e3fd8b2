"""tf2_geometry_msgs's ``do_transform_*`` for the three stamped types ``Buffer.transform`` takes.

As ``tf2_geometry_msgs.py`` (Noetic): the transform becomes a KDL frame (``Rotation::Quaternion``,
not normalised), the result's header is the transform's (``frame_id`` the target frame, ``stamp``
the transform's), a vector is only rotated, and a pose's orientation is KDL's ``GetQuaternion``
of the product.  The result has the input's class (so a world's own message registry is kept).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ddes.errors import DdesTypeError
from ddes.tf2_ros.linmath import kdl_frame_mul, kdl_matrix_to_quat, kdl_quat_to_matrix, mat_vec

__all__ = ["TRANSFORMABLE", "TypeException", "do_transform", "do_transform_point",
           "do_transform_pose", "do_transform_vector3", "transform_function"]


class TypeException(DdesTypeError):
    """tf2_ros.TypeException: a type ``Buffer.transform`` cannot handle (its text)."""


def _frame(transform: Any) -> tuple[Any, tuple[float, float, float]]:
    r = transform.transform.rotation
    t = transform.transform.translation
    return kdl_quat_to_matrix(r.x, r.y, r.z, r.w), (t.x, t.y, t.z)


def _header(res: Any, transform: Any) -> Any:
    res.header.seq = transform.header.seq
    res.header.stamp = transform.header.stamp
    res.header.frame_id = transform.header.frame_id
    return res


def do_transform_point(point: Any, transform: Any) -> Any:
    """tf2_geometry_msgs.do_transform_point: ``transform * point`` (PointStamped)."""
    m, t = _frame(transform)
    p = mat_vec(m, (point.point.x, point.point.y, point.point.z))
    res = type(point)()
    res.point.x, res.point.y, res.point.z = p[0] + t[0], p[1] + t[1], p[2] + t[2]
    return _header(res, transform)


def do_transform_vector3(vector3: Any, transform: Any) -> Any:
    """tf2_geometry_msgs.do_transform_vector3: the rotation only (Vector3Stamped)."""
    m, _t = _frame(transform)
    v = mat_vec(m, (vector3.vector.x, vector3.vector.y, vector3.vector.z))
    res = type(vector3)()
    res.vector.x, res.vector.y, res.vector.z = v
    return _header(res, transform)


def do_transform_pose(pose: Any, transform: Any) -> Any:
    """tf2_geometry_msgs.do_transform_pose: ``transform * pose`` as KDL frames (PoseStamped)."""
    m, t = _frame(transform)
    o, p = pose.pose.orientation, pose.pose.position
    fm, fp = kdl_frame_mul(m, t, kdl_quat_to_matrix(o.x, o.y, o.z, o.w), (p.x, p.y, p.z))
    res = type(pose)()
    res.pose.position.x, res.pose.position.y, res.pose.position.z = fp
    q = kdl_matrix_to_quat(fm)
    (res.pose.orientation.x, res.pose.orientation.y, res.pose.orientation.z,
     res.pose.orientation.w) = q
    return _header(res, transform)


#: Message type -> its ``do_transform`` (tf2_ros's TransformRegistration, these three types).
TRANSFORMABLE: dict[str, Callable[[Any, Any], Any]] = {
    "geometry_msgs/PointStamped": do_transform_point,
    "geometry_msgs/PoseStamped": do_transform_pose,
    "geometry_msgs/Vector3Stamped": do_transform_vector3,
}


def transform_function(object_stamped: Any) -> Callable[[Any, Any], Any]:
    """The ``do_transform_*`` of ``object_stamped``'s type, or tf2_ros's TypeException."""
    fn = TRANSFORMABLE.get(getattr(object_stamped, "_type", ""))
    if fn is None:
        raise TypeException(
            f"Type {type(object_stamped)} if not loaded or supported (ddes's Buffer.transform "
            f"takes {', '.join(sorted(TRANSFORMABLE))})")
    return fn


def do_transform(object_stamped: Any, transform: Any) -> Any:
    """``object_stamped`` transformed by ``transform`` (the function of its type)."""
    return transform_function(object_stamped)(object_stamped, transform)
