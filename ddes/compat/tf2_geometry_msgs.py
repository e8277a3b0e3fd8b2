"""tf2_geometry_msgs (Noetic, ``tf2_geometry_msgs.py``) for a rospy script.

``import tf2_geometry_msgs`` in a script resolves here.  As on ROS, importing it registers
``PointStamped``, ``Vector3Stamped``, ``PoseStamped`` and ``WrenchStamped`` with tf2_ros's
``TransformRegistration``, so ``Buffer.transform`` takes them (:mod:`ddes.compat.tf2_ros`);
before the import ``Buffer.transform`` raises tf2_ros's ``TypeException``.

The functions are Noetic's: ``do_transform_point``, ``do_transform_vector3``,
``do_transform_pose``, ``do_transform_wrench`` (the transform as a KDL frame,
``Rotation::Quaternion`` not normalised; a vector and a wrench only rotated; a pose's orientation
KDL's ``GetQuaternion`` of the product; the result's header the transform's), ``to_msg_msg`` and
``from_msg_msg`` (identities).  The arithmetic is :mod:`ddes.tf2_ros.geometry`'s and
:mod:`ddes.tf2_ros.linmath`'s, the same bits on every CPU.

Deliberate deviations from Noetic:

* the registration is the world's (made at the first ``import tf2_geometry_msgs`` by one of
  the world's scripts), not the process's: two worlds in one process do not share it;
* ``do_transform_pose_stamped`` is a ddes alias of ``do_transform_pose`` (Noetic's is for
  PoseStamped and has no other name); Noetic has no ``do_transform_pose_with_covariance_stamped``
  in Python, nor has ddes;
* ``transform_to_kdl`` (it returns a ``PyKDL.Frame``; PyKDL is not available) and the
  ``ConvertRegistration`` entries are not provided;
* a result has the input's message class (the world's), its header a copy of the transform's
  (Noetic shares the transform's header object).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ddes.compat.tf2_ros import transform_registry
from ddes.tf2_ros.geometry import do_transform_point, do_transform_pose, do_transform_vector3
from ddes.tf2_ros.linmath import kdl_quat_to_matrix, mat_vec

if TYPE_CHECKING:
    from ddes.graph.world import World

__all__ = ["do_transform_point", "do_transform_pose", "do_transform_pose_stamped",
           "do_transform_vector3", "do_transform_wrench", "from_msg_msg", "to_msg_msg"]

#: ddes's alias of :func:`do_transform_pose` (which transforms a PoseStamped).
do_transform_pose_stamped = do_transform_pose


def to_msg_msg(msg: Any) -> Any:
    """tf2_geometry_msgs.to_msg_msg: the message itself."""
    return msg


def from_msg_msg(msg: Any) -> Any:
    """tf2_geometry_msgs.from_msg_msg: the message itself."""
    return msg


def do_transform_wrench(wrench: Any, transform: Any) -> Any:
    """tf2_geometry_msgs.do_transform_wrench: force and torque rotated (WrenchStamped)."""
    r = transform.transform.rotation
    m = kdl_quat_to_matrix(r.x, r.y, r.z, r.w)
    res = type(wrench)()
    f, tq = wrench.wrench.force, wrench.wrench.torque
    res.wrench.force.x, res.wrench.force.y, res.wrench.force.z = mat_vec(m, (f.x, f.y, f.z))
    res.wrench.torque.x, res.wrench.torque.y, res.wrench.torque.z = mat_vec(
        m, (tq.x, tq.y, tq.z))
    res.header.seq = transform.header.seq
    res.header.stamp = transform.header.stamp
    res.header.frame_id = transform.header.frame_id
    return res


_REGISTERED = (("geometry_msgs/PointStamped", do_transform_point),
               ("geometry_msgs/Vector3Stamped", do_transform_vector3),
               ("geometry_msgs/PoseStamped", do_transform_pose),
               ("geometry_msgs/WrenchStamped", do_transform_wrench))


def _script_imported(world: World) -> None:
    """A script of ``world`` imported tf2_geometry_msgs: register its types there, once (as the
    module body runs once on ROS; a callback a script added since stays)."""
    registry = transform_registry(world)
    if __name__ in registry.loaded:
        return
    registry.loaded.add(__name__)
    for name, fn in _REGISTERED:
        registry.transforms[world.messages.get_message_class(name)] = fn
