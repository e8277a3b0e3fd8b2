"""tf.transformations (Noetic's copy of Gohlke's transformations.py) for a rospy script.

``import tf.transformations``, ``from tf.transformations import euler_from_quaternion`` and
``tf.transformations.quaternion_from_euler(...)`` in a script resolve here (as does
``tf_conversions.transformations``).  Each function has Noetic's name and signature and computes
through :mod:`ddes.transformations` (the platform's and numpy's ``sin``/``cos``/``atan2`` differ by
an ulp between CPUs; ddes's do not), then answers with Noetic's types: ``numpy.ndarray`` of
``float64`` where Noetic returns an array, a tuple of Python floats from ``euler_from_matrix`` /
``euler_from_quaternion``, a Python float from ``vector_norm`` of a 1-D vector, a bool from
``is_same_transform``.

Deliberate deviations from Noetic:

* without numpy (an optional dependency of ddes) the arrays are nested Python lists;
* ``inverse_matrix`` inverts 4x4 matrices only (Gauss-Jordan with partial pivoting, not
  LAPACK: the same within rounding, and the same bits on every CPU); a singular matrix raises
  :class:`ddes.errors.DdesValueError` (Noetic: numpy's ``LinAlgError``);
* an unknown Euler axis sequence raises :class:`ddes.errors.DdesValueError` naming the 24
  (Noetic: ``KeyError``);
* ``random_quaternion()`` / ``random_rotation_matrix()`` without ``rand`` draw from the running
  world's seeded generator (``world.rng_for("tf.transformations.random")``), not numpy's global
  one, so a run repeats; outside a running script pass ``rand``;
* the functions that need an eigen- or singular value decomposition, and the rest that students
  do not use (``rotation_from_matrix``, ``decompose_matrix``, ``superimposition_matrix``,
  ``reflection_*``, ``projection_*``, ``shear_*``, ``scale_from_matrix``, ``clip_matrix``,
  ``orthogonalization_matrix``, ``random_vector``, ``Arcball``, ``arcball_*``) are not
  provided: using one raises an ``AttributeError`` saying so.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from ddes import transformations as _t
from ddes.errors import DdesValueError
from ddes.graph.blocking import current_task


def _numpy() -> Any:
    """numpy, imported when a function first needs it (an optional dependency of ddes), or
    None without it."""
    try:
        import numpy
    except ImportError:  # pragma: no cover - numpy is installed wherever the suite runs
        return None
    return numpy

__all__ = [
    "compose_matrix", "concatenate_matrices", "euler_from_matrix", "euler_from_quaternion",
    "euler_matrix", "identity_matrix", "inverse_matrix", "is_same_transform",
    "quaternion_about_axis", "quaternion_conjugate", "quaternion_from_euler",
    "quaternion_from_matrix", "quaternion_inverse", "quaternion_matrix", "quaternion_multiply",
    "quaternion_slerp", "random_quaternion", "random_rotation_matrix", "rotation_matrix",
    "scale_matrix", "translation_from_matrix", "translation_matrix", "unit_vector",
    "vector_norm",
]

#: Names of Noetic's tf.transformations that ddes leaves out (see the module's docstring).
_NOT_PROVIDED = frozenset({
    "reflection_matrix", "reflection_from_matrix", "rotation_from_matrix", "scale_from_matrix",
    "projection_matrix", "projection_from_matrix", "clip_matrix", "shear_matrix",
    "shear_from_matrix", "decompose_matrix", "orthogonalization_matrix",
    "superimposition_matrix", "random_vector", "Arcball", "arcball_map_to_sphere",
    "arcball_constrain_to_axis", "arcball_nearest_axis",
})

_RNG_KEY = "compat.tf.transformations.rng"

Axes = str | tuple[int, int, int, int]


def __getattr__(name: str) -> Any:
    if name in _NOT_PROVIDED:
        raise AttributeError(
            f"ddes's tf.transformations does not provide {name}: it needs an eigen- or "
            "singular value decomposition (LAPACK's results differ between CPUs) or is seldom "
            "used; the functions it does provide are listed in "
            "ddes.compat.tf.transformations.__all__")
    raise AttributeError(f"module 'tf.transformations' has no attribute '{name}'")


def _array(value: Any) -> Any:
    """A list (of lists) as Noetic's ``numpy.ndarray`` of float64 (the list without numpy)."""
    _np = _numpy()
    if _np is None:
        return value
    return _np.array(value, dtype=_np.float64)


def identity_matrix() -> Any:
    """The 4x4 identity matrix."""
    return _array(_t.identity_matrix())


def translation_matrix(direction: Sequence[float]) -> Any:
    """The 4x4 matrix translating by ``direction[:3]``."""
    return _array(_t.translation_matrix(direction))


def translation_from_matrix(matrix: Any) -> Any:
    """The translation (3 values) of a 4x4 matrix."""
    return _array(_t.translation_from_matrix(matrix))


def concatenate_matrices(*matrices: Any) -> Any:
    """The product of 4x4 matrices, left to right."""
    return _array(_t.concatenate_matrices(*matrices))


def inverse_matrix(matrix: Any) -> Any:
    """The inverse of a 4x4 matrix."""
    return _array(_t.inverse_matrix(matrix))


def is_same_transform(matrix0: Any, matrix1: Any) -> bool:
    """True when the two matrices perform the same transformation (numpy's allclose)."""
    return _t.is_same_transform(matrix0, matrix1)


def _lanes(data: Any, axis: int | None) -> tuple[Any, Any]:
    """``data`` as float64 and its norms along ``axis`` (all of it when None), by ddes."""
    _np = _numpy()
    assert _np is not None
    arr = _np.array(data, dtype=_np.float64)
    if axis is None:
        return arr, _np.atleast_1d(_np.float64(_t.vector_norm(arr.ravel().tolist())))
    norms = _np.apply_along_axis(lambda v: _t.vector_norm(v.tolist()), axis, arr)
    return arr, _np.atleast_1d(_np.asarray(norms, dtype=_np.float64))


def vector_norm(data: Any, axis: int | None = None, out: Any = None) -> Any:
    """The Euclidean norm: a float for a 1-D vector, else an array of norms along ``axis``
    (written into ``out`` when given, which then returns None)."""
    _np = _numpy()
    if _np is None or (out is None and _np.ndim(data) == 1):
        return _t.vector_norm(data)
    _arr, norms = _lanes(data, axis)
    if out is None:
        return norms
    out[...] = norms.reshape(_np.shape(out))
    return None


def unit_vector(data: Any, axis: int | None = None, out: Any = None) -> Any:
    """``data`` divided by its norm (along ``axis``); into ``out`` (returning None) if given."""
    _np = _numpy()
    if _np is None:
        return _t.unit_vector(data)
    if out is None and _np.ndim(data) == 1:
        return _array(_t.unit_vector(data))
    arr, norms = _lanes(data, axis)
    if axis is not None:
        norms = _np.expand_dims(norms, axis)
    result = arr / norms
    if out is None:
        return result
    out[...] = result
    return None


def rotation_matrix(angle: float, direction: Sequence[float],
                    point: Sequence[float] | None = None) -> Any:
    """The 4x4 matrix rotating by ``angle`` about ``direction`` through ``point``."""
    return _array(_t.rotation_matrix(angle, direction, point))


def scale_matrix(factor: float, origin: Sequence[float] | None = None,
                 direction: Sequence[float] | None = None) -> Any:
    """The 4x4 matrix scaling by ``factor`` about ``origin`` (along ``direction``)."""
    return _array(_t.scale_matrix(factor, origin, direction))


def compose_matrix(scale: Sequence[float] | None = None, shear: Sequence[float] | None = None,
                   angles: Sequence[float] | None = None,
                   translate: Sequence[float] | None = None,
                   perspective: Sequence[float] | None = None) -> Any:
    """The 4x4 matrix of a sequence of transformations (the inverse of decompose_matrix)."""
    return _array(_t.compose_matrix(scale, shear, angles, translate, perspective))


def euler_matrix(ai: float, aj: float, ak: float, axes: Axes = "sxyz") -> Any:
    """The 4x4 rotation matrix of Euler angles and an axis sequence."""
    return _array(_t.euler_matrix(ai, aj, ak, axes))


def euler_from_matrix(matrix: Any, axes: Axes = "sxyz") -> tuple[float, float, float]:
    """Euler angles of a 3x3 or 4x4 rotation matrix (a tuple, as Noetic)."""
    return _t.euler_from_matrix(matrix, axes)


def euler_from_quaternion(quaternion: Sequence[float],
                          axes: Axes = "sxyz") -> tuple[float, float, float]:
    """Euler angles of a quaternion ``(x, y, z, w)`` (a tuple, as Noetic)."""
    return _t.euler_from_quaternion(quaternion, axes)


def quaternion_from_euler(ai: float, aj: float, ak: float, axes: Axes = "sxyz") -> Any:
    """The quaternion ``(x, y, z, w)`` of Euler angles and an axis sequence."""
    return _array(_t.quaternion_from_euler(ai, aj, ak, axes))


def quaternion_about_axis(angle: float, axis: Sequence[float]) -> Any:
    """The quaternion of a rotation by ``angle`` about ``axis``."""
    return _array(_t.quaternion_about_axis(angle, axis))


def quaternion_matrix(quaternion: Sequence[float]) -> Any:
    """The 4x4 rotation matrix of a quaternion."""
    return _array(_t.quaternion_matrix(quaternion))


def quaternion_from_matrix(matrix: Any) -> Any:
    """The quaternion of a 4x4 rotation matrix."""
    return _array(_t.quaternion_from_matrix(matrix))


def quaternion_multiply(quaternion1: Sequence[float], quaternion0: Sequence[float]) -> Any:
    """The product ``quaternion1 * quaternion0``."""
    return _array(_t.quaternion_multiply(quaternion1, quaternion0))


def quaternion_conjugate(quaternion: Sequence[float]) -> Any:
    """The conjugate ``(-x, -y, -z, w)``."""
    return _array(_t.quaternion_conjugate(quaternion))


def quaternion_inverse(quaternion: Sequence[float]) -> Any:
    """The inverse: the conjugate over the squared norm."""
    return _array(_t.quaternion_inverse(quaternion))


def quaternion_slerp(quat0: Sequence[float], quat1: Sequence[float], fraction: float,
                     spin: int = 0, shortestpath: bool = True) -> Any:
    """Spherical linear interpolation between two quaternions."""
    return _array(_t.quaternion_slerp(quat0, quat1, fraction, spin, shortestpath))


def _rand(rand: Sequence[float] | None, what: str) -> Sequence[float]:
    if rand is not None:
        if len(rand) != 3:
            raise AssertionError(f"{what}(rand) takes three numbers in [0, 1), got {rand!r}")
        return rand
    task = current_task()
    if task is None:
        raise DdesValueError(
            f"{what}() without rand draws from the running world's seeded generator, and no "
            f"ddes script is running here: pass three numbers in [0, 1), {what}(rand)")
    rng = task.world.extension(_RNG_KEY, lambda w: w.rng_for("tf.transformations.random"))
    return [rng.random(), rng.random(), rng.random()]


def random_quaternion(rand: Sequence[float] | None = None) -> Any:
    """A uniformly distributed unit quaternion (``rand``: three numbers in [0, 1))."""
    return _array(_t.random_quaternion(_rand(rand, "random_quaternion")))


def random_rotation_matrix(rand: Sequence[float] | None = None) -> Any:
    """The rotation matrix of a uniformly distributed random quaternion."""
    return _array(_t.random_rotation_matrix(_rand(rand, "random_rotation_matrix")))
