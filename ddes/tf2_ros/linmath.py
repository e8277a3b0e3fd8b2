"""The rotation arithmetic of the ROS tools, operation for operation.

Two C++ libraries turn quaternions into matrices and back in ROS, each its own way, and the
tools show the results (the sign of a printed quaternion, the branch of an Euler angle):

* tf's LinearMath (``tf/LinearMath/Matrix3x3.h``, Bullet's): ``tf_echo`` and tf1's
  ``static_transform_publisher`` keep a rotation as a matrix (``setRotation``) and print or send
  the quaternion ``getRotation`` computes from it, and the angles of ``getEulerYPR``;
* KDL (``kdl/frames.cpp``): ``tf2_geometry_msgs``'s ``do_transform_*`` multiply KDL frames
  (``Rotation::Quaternion``, not normalising) and read ``GetQuaternion``.

Only IEEE basic operations, ``sqrt`` (correctly rounded everywhere) and the deterministic
``sin``/``cos``/``atan2``/``asin`` of :mod:`ddes.transformations` take part, in the C++ order, so
the results are the same bits on every machine.
"""

from __future__ import annotations

import math

from ddes.transformations import asin, atan2, cos, sin

__all__ = ["Matrix", "Quat", "Vec", "kdl_frame_mul", "kdl_matrix_to_quat", "kdl_quat_to_matrix",
           "mat_vec", "tf_matrix_to_quat", "tf_quat_to_matrix", "tf_rpy", "tf_set_rpy"]

#: A 3x3 matrix, row by row (``m[3 * row + col]``).
Matrix = tuple[float, float, float, float, float, float, float, float, float]
#: A quaternion ``(x, y, z, w)``.
Quat = tuple[float, float, float, float]
Vec = tuple[float, float, float]


def tf_quat_to_matrix(x: float, y: float, z: float, w: float) -> Matrix:
    """tf ``Matrix3x3::setRotation(q)``: the rotation of ``q`` scaled by ``2 / |q|^2``."""
    d = x * x + y * y + z * z + w * w
    s = 2.0 / d
    xs, ys, zs = x * s, y * s, z * s
    wx, wy, wz = w * xs, w * ys, w * zs
    xx, xy, xz = x * xs, x * ys, x * zs
    yy, yz, zz = y * ys, y * zs, z * zs
    return (1.0 - (yy + zz), xy - wz, xz + wy,
            xy + wz, 1.0 - (xx + zz), yz - wx,
            xz - wy, yz + wx, 1.0 - (xx + yy))


def tf_matrix_to_quat(m: Matrix) -> Quat:
    """tf ``Matrix3x3::getRotation``: the quaternion of ``m`` (``w >= 0`` when the trace is > 0)."""
    trace = m[0] + m[4] + m[8]
    temp = [0.0, 0.0, 0.0, 0.0]
    if trace > 0.0:
        s = math.sqrt(trace + 1.0)
        temp[3] = s * 0.5
        s = 0.5 / s
        temp[0] = (m[7] - m[5]) * s
        temp[1] = (m[2] - m[6]) * s
        temp[2] = (m[3] - m[1]) * s
    else:
        if m[0] < m[4]:
            i = 2 if m[4] < m[8] else 1
        else:
            i = 2 if m[0] < m[8] else 0
        j = (i + 1) % 3
        k = (i + 2) % 3
        s = math.sqrt(m[4 * i] - m[4 * j] - m[4 * k] + 1.0)
        temp[i] = s * 0.5
        s = 0.5 / s
        temp[3] = (m[3 * k + j] - m[3 * j + k]) * s
        temp[j] = (m[3 * j + i] + m[3 * i + j]) * s
        temp[k] = (m[3 * k + i] + m[3 * i + k]) * s
    return (temp[0], temp[1], temp[2], temp[3])


def tf_rpy(m: Matrix) -> Vec:
    """tf ``Matrix3x3::getRPY(roll, pitch, yaw)`` (``getEulerYPR``, solution 1)."""
    m20, m21, m22 = m[6], m[7], m[8]
    if abs(m20) >= 1.0:
        delta = atan2(m21, m22)
        pitch = math.pi / 2.0 if m20 < 0 else -math.pi / 2.0
        return (delta, pitch, 0.0)
    pitch = -asin(m20)
    c = cos(pitch)
    roll = atan2(m21 / c, m22 / c)
    yaw = atan2(m[3] / c, m[0] / c)
    return (roll, pitch, yaw)


def tf_set_rpy(roll: float, pitch: float, yaw: float) -> Quat:
    """tf2 (and tf) ``Quaternion::setRPY(roll, pitch, yaw)``: rotations about fixed X, Y, Z."""
    hy, hp, hr = yaw * 0.5, pitch * 0.5, roll * 0.5
    cy, sy = cos(hy), sin(hy)
    cp, sp = cos(hp), sin(hp)
    cr, sr = cos(hr), sin(hr)
    return (sr * cp * cy - cr * sp * sy,
            cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy,
            cr * cp * cy + sr * sp * sy)


def kdl_quat_to_matrix(x: float, y: float, z: float, w: float) -> Matrix:
    """KDL ``Rotation::Quaternion(x, y, z, w)`` (no normalisation, as KDL)."""
    x2, y2, z2, w2 = x * x, y * y, z * z, w * w
    return (w2 + x2 - y2 - z2, 2 * x * y - 2 * w * z, 2 * x * z + 2 * w * y,
            2 * x * y + 2 * w * z, w2 - x2 + y2 - z2, 2 * y * z - 2 * w * x,
            2 * x * z - 2 * w * y, 2 * y * z + 2 * w * x, w2 - x2 - y2 + z2)


def kdl_matrix_to_quat(m: Matrix) -> Quat:
    """KDL ``Rotation::GetQuaternion``."""
    trace = m[0] + m[4] + m[8]
    if trace > 1e-12:
        s = 0.5 / math.sqrt(trace + 1.0)
        return ((m[7] - m[5]) * s, (m[2] - m[6]) * s, (m[3] - m[1]) * s, 0.25 / s)
    if m[0] > m[4] and m[0] > m[8]:
        s = 2.0 * math.sqrt(1.0 + m[0] - m[4] - m[8])
        return (0.25 * s, (m[1] + m[3]) / s, (m[2] + m[6]) / s, (m[7] - m[5]) / s)
    if m[4] > m[8]:
        s = 2.0 * math.sqrt(1.0 + m[4] - m[0] - m[8])
        return ((m[1] + m[3]) / s, 0.25 * s, (m[5] + m[7]) / s, (m[2] - m[6]) / s)
    s = 2.0 * math.sqrt(1.0 + m[8] - m[0] - m[4])
    return ((m[2] + m[6]) / s, (m[5] + m[7]) / s, 0.25 * s, (m[3] - m[1]) / s)


def mat_vec(m: Matrix, v: Vec) -> Vec:
    """``m * v`` (KDL ``Rotation * Vector``)."""
    return (m[0] * v[0] + m[1] * v[1] + m[2] * v[2],
            m[3] * v[0] + m[4] * v[1] + m[5] * v[2],
            m[6] * v[0] + m[7] * v[1] + m[8] * v[2])


def _mat_mul(a: Matrix, b: Matrix) -> Matrix:
    """``a * b`` (KDL ``Rotation * Rotation``)."""
    out = [0.0] * 9
    for r in range(3):
        for c in range(3):
            out[3 * r + c] = a[3 * r] * b[c] + a[3 * r + 1] * b[3 + c] + a[3 * r + 2] * b[6 + c]
    return (out[0], out[1], out[2], out[3], out[4], out[5], out[6], out[7], out[8])


def kdl_frame_mul(am: Matrix, ap: Vec, bm: Matrix, bp: Vec) -> tuple[Matrix, Vec]:
    """KDL ``Frame * Frame``: ``(a.M * b.M, a.M * b.p + a.p)``."""
    rp = mat_vec(am, bp)
    return _mat_mul(am, bm), (rp[0] + ap[0], rp[1] + ap[1], rp[2] + ap[2])
