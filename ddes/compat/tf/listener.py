"""tf's ``listener.py`` (Noetic): Transformer, TransformerROS and TransformListener over tf2.

As in Noetic, tf1's Python classes are proxies of tf2: ``Transformer`` holds a
``tf2_ros.Buffer(cache_time, debug=False)`` (:class:`ddes.compat.tf2_ros.Buffer`, so a wait
blocks the calling script's node on simulated time) and strips a leading ``/`` from frame names;
``TransformListener()`` adds a ``tf2_ros.TransformListener`` on the script's node.

* ``lookupTransform(target, source, time)`` returns ``([x, y, z], [x, y, z, w])`` (two lists,
  as Noetic); ``waitForTransform(target, source, time, timeout, polling_sleep_duration=None)``
  blocks until ``can_transform`` or the timeout has passed on simulated time, then raises
  ``tf.Exception`` (tf2's TransformException) with tf2's text, as Noetic; a ``Transformer``
  without a listener refuses to wait with Noetic's text;
* ``asMatrix``, ``fromTranslationRotation`` (4x4 ``numpy.ndarray``; nested lists without
  numpy), ``transformPoint``/``transformVector3``/``transformQuaternion``/``transformPose``/
  ``transformPointCloud`` compute through :mod:`ddes.transformations` (deterministic
  arithmetic), as Noetic's compute through tf.transformations and numpy.

Deliberate deviations: a transformed message has the input's class and Python floats (Noetic
builds ``geometry_msgs.msg`` classes and stores numpy floats); ``transformPointCloud`` keeps the
points' ``Point32`` class (Noetic puts ``geometry_msgs/Point`` objects into the cloud);
``lookupTwist``/``lookupTwistFull`` are not provided (they need ``rotation_from_matrix``, an
eigen-decomposition).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import yaml

from ddes import transformations as _t
from ddes.compat import tf2_ros
from ddes.compat.tf.transformations import _array

__all__ = ["Transformer", "TransformListener", "TransformerROS", "strip_leading_slash",
           "xyz_to_mat44", "xyzw_to_mat44"]


def strip_leading_slash(s: str) -> str:
    """``s`` without one leading ``/`` (tf2 refuses frame names starting with one)."""
    return s[1:] if s.startswith("/") else s


def xyz_to_mat44(pos: Any) -> Any:
    """The translation matrix of a geometry_msgs Point/Vector3."""
    return _array(_t.translation_matrix((pos.x, pos.y, pos.z)))


def xyzw_to_mat44(ori: Any) -> Any:
    """The rotation matrix of a geometry_msgs Quaternion."""
    return _array(_t.quaternion_matrix((ori.x, ori.y, ori.z, ori.w)))


_NO_THREAD = ("cannot wait for transform without a dedicated thread that listens to incoming "
              "TF messages")


class Transformer:
    """tf.Transformer(interpolate=True, cache_time=None): a tf2 buffer with tf1's names."""

    def __init__(self, interpolate: bool = True, cache_time: Any = None) -> None:
        self._buffer = tf2_ros.Buffer(cache_time, debug=False)
        self._using_dedicated_thread = False

    def allFramesAsDot(self, current_time: Any = None) -> str:  # noqa: N802 - tf's names
        """The tree as graphviz dot text."""
        if current_time:
            return self._buffer._allFramesAsDot(current_time)
        return self._buffer._allFramesAsDot()

    def allFramesAsString(self) -> str:  # noqa: N802
        """tf2's ``all_frames_as_string``."""
        return self._buffer.all_frames_as_string()

    def setTransform(self, transform: Any,  # noqa: N802
                     authority: str = "default_authority") -> None:
        """Insert a geometry_msgs/TransformStamped."""
        self._buffer.set_transform(transform, authority)

    def canTransform(self, target_frame: str, source_frame: str, time: Any) -> bool:  # noqa: N802
        """True when the transform can be computed now."""
        return bool(self._buffer.can_transform(strip_leading_slash(target_frame),
                                               strip_leading_slash(source_frame), time))

    def canTransformFull(self, target_frame: str, target_time: Any,  # noqa: N802
                         source_frame: str, source_time: Any, fixed_frame: str) -> bool:
        """``canTransform`` of the advanced API."""
        return bool(self._buffer.can_transform_full(
            strip_leading_slash(target_frame), target_time, strip_leading_slash(source_frame),
            source_time, strip_leading_slash(fixed_frame)))

    def waitForTransform(self, target_frame: str, source_frame: str, time: Any,  # noqa: N802
                         timeout: Any, polling_sleep_duration: Any = None) -> None:
        """Block until the transform can be computed; tf.Exception after ``timeout``."""
        if not self._using_dedicated_thread:
            raise tf2_ros.TransformException(_NO_THREAD)
        ok, error = self._buffer.can_transform(
            strip_leading_slash(target_frame), strip_leading_slash(source_frame), time, timeout,
            return_debug_tuple=True)
        if not ok:
            raise tf2_ros.TransformException(
                error or f'no such transformation: "{source_frame}" -> "{target_frame}"')

    def waitForTransformFull(self, target_frame: str, target_time: Any,  # noqa: N802
                             source_frame: str, source_time: Any, fixed_frame: str,
                             timeout: Any, polling_sleep_duration: Any = None) -> None:
        """``waitForTransform`` of the advanced API."""
        if not self._using_dedicated_thread:
            raise tf2_ros.TransformException(_NO_THREAD)
        ok, error = self._buffer.can_transform_full(
            strip_leading_slash(target_frame), target_time, strip_leading_slash(source_frame),
            source_time, strip_leading_slash(fixed_frame), timeout, return_debug_tuple=True)
        if not ok:
            raise tf2_ros.TransformException(
                error or f'no such transformation: "{source_frame}" -> "{target_frame}"')

    def chain(self, target_frame: str, target_time: Any, source_frame: str, source_time: Any,
              fixed_frame: str) -> Any:
        """The frames between two frames (tf2's ``_chain``)."""
        return self._buffer._chain(target_frame, target_time, source_frame, source_time,
                                   fixed_frame)

    def clear(self) -> None:
        """Forget every transform."""
        self._buffer.clear()

    def frameExists(self, frame_id: str) -> bool:  # noqa: N802
        """True for a frame that has a parent (Noetic reads the YAML's keys: a root is not)."""
        return frame_id in self.getFrameStrings()

    def getFrameStrings(self) -> list[str]:  # noqa: N802
        """The frames that have a parent (the keys of ``all_frames_as_yaml``)."""
        data = yaml.safe_load(self._buffer.all_frames_as_yaml()) or {}
        return [str(p) for p in data]

    def getLatestCommonTime(self, source_frame: str, dest_frame: str) -> Any:  # noqa: N802
        """The latest time both frames are known at (tf2's ``get_latest_common_time``)."""
        return self._buffer.get_latest_common_time(strip_leading_slash(source_frame),
                                                   strip_leading_slash(dest_frame))

    def lookupTransform(self, target_frame: str, source_frame: str,  # noqa: N802
                        time: Any) -> tuple[list[float], list[float]]:
        """``([x, y, z], [x, y, z, w])`` of the transform from source to target at ``time``."""
        msg = self._buffer.lookup_transform(strip_leading_slash(target_frame),
                                            strip_leading_slash(source_frame), time)
        return _pair(msg)

    def lookupTransformFull(self, target_frame: str, target_time: Any,  # noqa: N802
                            source_frame: str, source_time: Any,
                            fixed_frame: str) -> tuple[list[float], list[float]]:
        """``lookupTransform`` of the advanced API."""
        msg = self._buffer.lookup_transform_full(
            strip_leading_slash(target_frame), target_time, strip_leading_slash(source_frame),
            source_time, strip_leading_slash(fixed_frame))
        return _pair(msg)

    def setUsingDedicatedThread(self, value: bool) -> None:  # noqa: N802
        """Allow (True) or refuse (False) ``waitForTransform``."""
        self._using_dedicated_thread = value

    def getTFPrefix(self) -> str:  # noqa: N802
        """tf2 has no tf prefix: ``""``."""
        return ""


def _pair(msg: Any) -> tuple[list[float], list[float]]:
    t = msg.transform.translation
    r = msg.transform.rotation
    return [t.x, t.y, t.z], [r.x, r.y, r.z, r.w]


def _matrix(translation: Sequence[float], rotation: Sequence[float]) -> list[list[float]]:
    return _t.concatenate_matrices(_t.translation_matrix(translation),
                                   _t.quaternion_matrix(rotation))


def _apply(m: Sequence[Sequence[float]], x: float, y: float, z: float,
           w: float) -> tuple[float, float, float]:
    a, b, c = (float(m[r][0] * x + m[r][1] * y + m[r][2] * z + m[r][3] * w) for r in range(3))
    return a, b, c


class TransformerROS(Transformer):
    """tf.TransformerROS: a Transformer that transforms geometry_msgs stamped messages."""

    def _lookup_matrix(self, target_frame: str, hdr: Any) -> list[list[float]]:
        translation, rotation = self.lookupTransform(target_frame, hdr.frame_id, hdr.stamp)
        return _matrix(translation, rotation)

    def asMatrix(self, target_frame: str, hdr: Any) -> Any:  # noqa: N802
        """The 4x4 matrix of the transform from ``hdr.frame_id`` at ``hdr.stamp``."""
        return _array(self._lookup_matrix(target_frame, hdr))

    def fromTranslationRotation(self, translation: Sequence[float],  # noqa: N802
                                rotation: Sequence[float]) -> Any:
        """The 4x4 matrix ``translation_matrix(t) . quaternion_matrix(q)``."""
        return _array(_matrix(translation, rotation))

    def transformPoint(self, target_frame: str, ps: Any) -> Any:  # noqa: N802
        """A PointStamped in ``target_frame`` (stamp kept)."""
        m = self._lookup_matrix(target_frame, ps.header)
        r = _stamped(ps, target_frame)
        r.point.x, r.point.y, r.point.z = _apply(m, ps.point.x, ps.point.y, ps.point.z, 1.0)
        return r

    def transformVector3(self, target_frame: str, v3s: Any) -> Any:  # noqa: N802
        """A Vector3Stamped in ``target_frame``: rotated only."""
        m = self._lookup_matrix(target_frame, v3s.header)
        m[0][3] = m[1][3] = m[2][3] = 0.0
        r = _stamped(v3s, target_frame)
        r.vector.x, r.vector.y, r.vector.z = _apply(m, v3s.vector.x, v3s.vector.y,
                                                    v3s.vector.z, 1.0)
        return r

    def transformQuaternion(self, target_frame: str, ps: Any) -> Any:  # noqa: N802
        """A QuaternionStamped in ``target_frame``."""
        m = self._lookup_matrix(target_frame, ps.header)
        q = ps.quaternion
        pose = _t.quaternion_matrix((q.x, q.y, q.z, q.w))
        quat = _t.quaternion_from_matrix(_t.concatenate_matrices(m, pose))
        r = _stamped(ps, target_frame)
        r.quaternion.x, r.quaternion.y, r.quaternion.z, r.quaternion.w = quat
        return r

    def transformPose(self, target_frame: str, ps: Any) -> Any:  # noqa: N802
        """A PoseStamped in ``target_frame``."""
        m = self._lookup_matrix(target_frame, ps.header)
        p, o = ps.pose.position, ps.pose.orientation
        pose = _matrix((p.x, p.y, p.z), (o.x, o.y, o.z, o.w))
        tx = _t.concatenate_matrices(m, pose)
        r = _stamped(ps, target_frame)
        r.pose.position.x, r.pose.position.y, r.pose.position.z = _t.translation_from_matrix(tx)
        (r.pose.orientation.x, r.pose.orientation.y, r.pose.orientation.z,
         r.pose.orientation.w) = _t.quaternion_from_matrix(tx)
        return r

    def transformPointCloud(self, target_frame: str, point_cloud: Any) -> Any:  # noqa: N802
        """A sensor_msgs/PointCloud in ``target_frame`` (channels kept)."""
        m = self._lookup_matrix(target_frame, point_cloud.header)
        r = _stamped(point_cloud, target_frame)
        r.channels = point_cloud.channels
        r.points = [type(p)(*_apply(m, p.x, p.y, p.z, 1.0)) for p in point_cloud.points]
        return r


def _stamped(msg: Any, target_frame: str) -> Any:
    """A new message of ``msg``'s class with its stamp and ``target_frame``."""
    r = type(msg)()
    r.header.stamp = msg.header.stamp
    r.header.frame_id = target_frame
    return r


class TransformListener(TransformerROS):
    """tf.TransformListener(): a TransformerROS filled from /tf and /tf_static by a tf2_ros
    TransformListener on the script's node; ``waitForTransform`` may block."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        TransformerROS.__init__(self, *args, **kwargs)
        self._listener = tf2_ros.TransformListener(self._buffer)
        self.setUsingDedicatedThread(True)
