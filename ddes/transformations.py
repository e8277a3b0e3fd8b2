"""tf.transformations' names and conventions, bit-identical on every CPU.

Quaternions are ``[x, y, z, w]``; matrices are 4x4 homogeneous matrices as lists of rows; Euler
angles take any of the 24 axis sequences (``'sxyz'`` by default: static axes, roll about x, then
pitch about y, then yaw about z), exactly as ``tf.transformations`` (Christoph Gohlke's
transformations.py, the copy ROS ships).

Everything is built from IEEE basic operations (``+ - * /`` and ``math.sqrt``, which IEEE 754
requires to be correctly rounded) and the deterministic :func:`sin`, :func:`cos`, :func:`atan2`,
:func:`asin` and :func:`acos` of this module (fdlibm's algorithms as musl writes them: argument
reduction by pi/2 in three parts, or exactly with integers for huge arguments, then a minimax
polynomial; within 1 ulp of the true value).  The platform's ``math.sin`` and numpy's
transcendental functions differ by an ulp between C libraries and CPUs (with and without
AVX-512); these do not, so a trace that uses them hashes the same everywhere.

Results are plain Python lists (tf.transformations returns numpy arrays; numpy is not a
dependency of ddes).  Inputs may be any sequences of numbers, numpy arrays included.  A rospy
script's ``import tf.transformations`` gets :mod:`ddes.compat.tf.transformations`: these
functions with tf's numpy return types.

Beyond the functions above, :func:`rotation_matrix`, :func:`scale_matrix`,
:func:`compose_matrix`, :func:`is_same_transform`, :func:`random_quaternion` and
:func:`random_rotation_matrix` follow tf.transformations too; the last two take their three
uniform numbers ``rand`` as an argument (tf's default, ``numpy.random.rand(3)``, is the
caller's to choose).  The functions of tf.transformations that need an eigen-decomposition
or a singular value decomposition (``rotation_from_matrix``, ``decompose_matrix``,
``superimposition_matrix``...) are not here: LAPACK's results differ by CPU.
"""

from __future__ import annotations

import math
import struct
from collections.abc import Sequence

from ddes.errors import DdesValueError

__all__ = [
    "acos",
    "asin",
    "atan",
    "atan2",
    "compose_matrix",
    "concatenate_matrices",
    "cos",
    "euler_from_matrix",
    "euler_from_quaternion",
    "euler_matrix",
    "identity_matrix",
    "inverse_matrix",
    "is_same_transform",
    "quaternion_about_axis",
    "quaternion_conjugate",
    "quaternion_from_euler",
    "quaternion_from_matrix",
    "quaternion_inverse",
    "quaternion_matrix",
    "quaternion_multiply",
    "quaternion_slerp",
    "random_quaternion",
    "random_rotation_matrix",
    "rotation_matrix",
    "scale_matrix",
    "sin",
    "translation_from_matrix",
    "translation_matrix",
    "unit_vector",
    "vector_norm",
]

Matrix = list[list[float]]

# --- deterministic elementary functions (fdlibm / musl) ------------------------------------


_pack_d = struct.Struct("<d").pack
_unpack_d = struct.Struct("<d").unpack
_unpack_q = struct.Struct("<q").unpack
_unpack_high = struct.Struct("<4xI").unpack  # the high word of a little-endian double


def _bits(x: float) -> int:
    return int(_unpack_q(_pack_d(x))[0])


def _high(x: float) -> int:
    """The high 32-bit word of a double, sign bit included (fdlibm's GET_HIGH_WORD)."""
    return int(_unpack_high(_pack_d(x))[0])


def _clear_low(x: float) -> float:
    """x with its low 32 bits zeroed (fdlibm's SET_LOW_WORD(x, 0))."""
    return float(_unpack_d(b"\x00\x00\x00\x00" + _pack_d(x)[4:])[0])


def _hex(h: int) -> float:
    return float(struct.unpack("<d", struct.pack("<Q", h))[0])


_S1 = -1.66666666666666324348e-01
_S2 = 8.33333333332248946124e-03
_S3 = -1.98412698298579493134e-04
_S4 = 2.75573137070700676789e-06
_S5 = -2.50507602534068634195e-08
_S6 = 1.58969099521155010221e-10
_C1 = 4.16666666666666019037e-02
_C2 = -1.38888888888741095749e-03
_C3 = 2.48015872894767294178e-05
_C4 = -2.75573143513906633035e-07
_C5 = 2.08757232129817482790e-09
_C6 = -1.13596475577881948265e-11

_TOINT = 6755399441055744.0  # 1.5 / DBL_EPSILON
_INVPIO2 = _hex(0x3FE45F306DC9C883)
_PIO2_1 = _hex(0x3FF921FB54400000)
_PIO2_1T = _hex(0x3DD0B4611A626331)
_PIO2_2 = _hex(0x3DD0B4611A600000)
_PIO2_2T = _hex(0x3BA3198A2E037073)
_PIO2_3 = _hex(0x3BA3198A2E000000)
_PIO2_3T = _hex(0x397B839A252049C1)
_PIO4 = _hex(0x3FE921FB54442D18)


def _ksin(x: float, y: float, iy: int) -> float:
    z = x * x
    w = z * z
    r = _S2 + z * (_S3 + z * _S4) + z * w * (_S5 + z * _S6)
    v = z * x
    if iy == 0:
        return x + v * (_S1 + z * r)
    return x - ((z * (0.5 * y - v * r) - y) - v * _S1)


def _kcos(x: float, y: float) -> float:
    z = x * x
    w = z * z
    r = z * (_C1 + z * (_C2 + z * _C3)) + w * w * (_C4 + z * (_C5 + z * _C6))
    hz = 0.5 * z
    w = 1.0 - hz
    return w + (((1.0 - w) - hz) + (z * r - x * y))


_PIO2_FIXED: list[int] = []  # [pi/2 * 2**_FIX_BITS], computed on first use
_FIX_BITS = 1300


def _pio2_fixed() -> int:
    """pi/2 to _FIX_BITS bits, as an integer, by Machin's formula in integer arithmetic."""
    if not _PIO2_FIXED:
        one = 1 << (_FIX_BITS + 64)

        def arctan_inv(n: int) -> int:
            total, term, k, sign = 0, one // n, 1, 1
            n2 = n * n
            while term:
                total += sign * (term // k)
                term //= n2
                k += 2
                sign = -sign
            return total

        pi = 16 * arctan_inv(5) - 4 * arctan_inv(239)
        _PIO2_FIXED.append(pi >> 65)
    return _PIO2_FIXED[0]


def _rem_pio2(x: float) -> tuple[int, float, float]:
    """x = n*pi/2 + (y0 + y1) with |y0 + y1| <= ~pi/4; returns (n mod 4, y0, y1)."""
    hx = _unpack_high(_pack_d(x))[0]
    ix = hx & 0x7FFFFFFF
    if ix < 0x413921FB:  # |x| < 2**20 * pi/2: Cody-Waite in three rounds (musl __rem_pio2)
        fn = x * _INVPIO2 + _TOINT - _TOINT
        n = int(fn)
        r = x - fn * _PIO2_1
        w = fn * _PIO2_1T
        if r - w < -_PIO4:
            n -= 1
            fn -= 1.0
            r = x - fn * _PIO2_1
            w = fn * _PIO2_1T
        elif r - w > _PIO4:
            n += 1
            fn += 1.0
            r = x - fn * _PIO2_1
            w = fn * _PIO2_1T
        y0 = r - w
        ex = ix >> 20
        ey = (_unpack_high(_pack_d(y0))[0] >> 20) & 0x7FF
        if ex - ey > 16:
            t = r
            w = fn * _PIO2_2
            r = t - w
            w = fn * _PIO2_2T - ((t - r) - w)
            y0 = r - w
            ey = (_unpack_high(_pack_d(y0))[0] >> 20) & 0x7FF
            if ex - ey > 49:
                t = r
                w = fn * _PIO2_3
                r = t - w
                w = fn * _PIO2_3T - ((t - r) - w)
                y0 = r - w
        y1 = (r - y0) - w
        return n & 3, y0, y1
    # Huge |x|: exact reduction with integers (pi/2 to 1300 bits covers every double).
    num, den = x.as_integer_ratio()  # den is a power of two, at most 2**32 here
    pio2 = _pio2_fixed()
    big = (num << _FIX_BITS) // den  # exact
    n = (2 * big + pio2) // (2 * pio2)
    rem = big - n * pio2
    scale = 1 << _FIX_BITS
    y0 = rem / scale  # int / int is correctly rounded
    h_num, h_den = y0.as_integer_ratio()
    y1 = (rem - h_num * (scale // h_den)) / scale
    return n & 3, y0, y1


#: |x| < _SIN_KERNEL exactly when |x|'s high word is <= 0x3FE921FB (sin's kernel range), and
#: |x| < _SIN_TINY when it is < 0x3E500000: float comparisons that decide as fdlibm's integer ones.
_SIN_KERNEL = _hex(0x3FE921FC00000000)
_SIN_TINY = _hex(0x3E50000000000000)


def sin(x: float) -> float:
    """sin(x), deterministic (fdlibm's algorithm, within 1 ulp)."""
    x = float(x)
    if -_SIN_KERNEL < x < _SIN_KERNEL:  # the common case, _ksin(x, 0.0, 0) inline
        if -_SIN_TINY < x < _SIN_TINY:
            return x
        z = x * x
        w = z * z
        r = _S2 + z * (_S3 + z * _S4) + z * w * (_S5 + z * _S6)
        return x + z * x * (_S1 + z * r)
    ix = _unpack_high(_pack_d(x))[0] & 0x7FFFFFFF
    if ix <= 0x3FE921FB:
        if ix < 0x3E500000:
            return x
        return _ksin(x, 0.0, 0)
    if ix >= 0x7FF00000:
        return x - x
    n, y0, y1 = _rem_pio2(x)
    if n == 0:
        return _ksin(y0, y1, 1)
    if n == 1:
        return _kcos(y0, y1)
    if n == 2:
        return -_ksin(y0, y1, 1)
    return -_kcos(y0, y1)


def cos(x: float) -> float:
    """cos(x), deterministic (fdlibm's algorithm, within 1 ulp)."""
    x = float(x)
    ix = _unpack_high(_pack_d(x))[0] & 0x7FFFFFFF
    if ix <= 0x3FE921FB:
        if ix < 0x3E46A09E:
            return 1.0
        return _kcos(x, 0.0)
    if ix >= 0x7FF00000:
        return x - x
    n, y0, y1 = _rem_pio2(x)
    if n == 0:
        return _kcos(y0, y1)
    if n == 1:
        return -_ksin(y0, y1, 1)
    if n == 2:
        return -_kcos(y0, y1)
    return _ksin(y0, y1, 1)


_ATANHI = (4.63647609000806093515e-01, 7.85398163397448278999e-01,
           9.82793723247329054082e-01, 1.57079632679489655800e+00)
_ATANLO = (2.26987774529616870924e-17, 3.06161699786838301793e-17,
           1.39033110312309984516e-17, 6.12323399573676603587e-17)
_AT = (3.33333333333329318027e-01, -1.99999999998764832476e-01, 1.42857142725034663711e-01,
       -1.11111104054623557880e-01, 9.09088713343650656196e-02, -7.69187620504482999495e-02,
       6.66107313738753120669e-02, -5.83357013379057348645e-02, 4.97687799461593236017e-02,
       -3.65315727442169155270e-02, 1.62858201153657823623e-02)


def atan(x: float) -> float:
    """atan(x), deterministic (fdlibm's algorithm, within 1 ulp)."""
    x = float(x)
    hx = _unpack_high(_pack_d(x))[0]
    sign = hx >> 31
    ix = hx & 0x7FFFFFFF
    if ix >= 0x44100000:  # |x| >= 2**66
        if x != x:
            return x
        return -_ATANHI[3] if sign else _ATANHI[3]
    if ix < 0x3FDC0000:  # |x| < 0.4375
        if ix < 0x3E400000:
            return x
        ident = -1
    else:
        x = abs(x)
        if ix < 0x3FF30000:
            if ix < 0x3FE60000:
                ident = 0
                x = (2.0 * x - 1.0) / (2.0 + x)
            else:
                ident = 1
                x = (x - 1.0) / (x + 1.0)
        elif ix < 0x40038000:
            ident = 2
            x = (x - 1.5) / (1.0 + 1.5 * x)
        else:
            ident = 3
            x = -1.0 / x
    z = x * x
    w = z * z
    a = _AT
    s1 = z * (a[0] + w * (a[2] + w * (a[4] + w * (a[6] + w * (a[8] + w * a[10])))))
    s2 = w * (a[1] + w * (a[3] + w * (a[5] + w * (a[7] + w * a[9]))))
    if ident < 0:
        return x - x * (s1 + s2)
    z = _ATANHI[ident] - (x * (s1 + s2) - _ATANLO[ident] - x)
    return -z if sign else z


_PI = 3.1415926535897931160e+00
_PI_LO = 1.2246467991473531772e-16


def atan2(y: float, x: float) -> float:
    """atan2(y, x), deterministic (fdlibm's algorithm, within 1 ulp; IEEE special cases)."""
    y = float(y)
    x = float(x)
    if x != x or y != y:
        return x + y
    bx = _bits(x) & 0xFFFFFFFFFFFFFFFF
    by = _bits(y) & 0xFFFFFFFFFFFFFFFF
    if bx == 0x3FF0000000000000:
        return atan(y)
    m = ((by >> 63) & 1) | ((bx >> 62) & 2)
    ix = (bx >> 32) & 0x7FFFFFFF
    iy = (by >> 32) & 0x7FFFFFFF
    if by & 0x7FFFFFFFFFFFFFFF == 0:
        if m in (0, 1):
            return y
        return _PI if m == 2 else -_PI
    if bx & 0x7FFFFFFFFFFFFFFF == 0:
        return -_PI / 2 if m & 1 else _PI / 2
    if ix == 0x7FF00000:
        if iy == 0x7FF00000:
            return (_PI / 4, -_PI / 4, 3 * _PI / 4, -3 * _PI / 4)[m]
        return (0.0, -0.0, _PI, -_PI)[m]
    if ix + (64 << 20) < iy or iy == 0x7FF00000:
        return -_PI / 2 if m & 1 else _PI / 2
    if (m & 2) and iy + (64 << 20) < ix:
        z = 0.0
    else:
        z = atan(abs(y / x))
    if m == 0:
        return z
    if m == 1:
        return -z
    if m == 2:
        return _PI - (z - _PI_LO)
    return (z - _PI_LO) - _PI


_PIO2_HI = 1.57079632679489655800e+00
_PIO2_LO = 6.12323399573676603587e-17
_PS = (1.66666666666666657415e-01, -3.25565818622400915405e-01, 2.01212532134862925881e-01,
       -4.00555345006794114027e-02, 7.91534994289814532176e-04, 3.47933107596021167570e-05)
_QS = (-2.40339491173441421878e+00, 2.02094576023350569471e+00, -6.88283971605453293030e-01,
       7.70381505559019352791e-02)


def _r(z: float) -> float:
    p = z * (_PS[0] + z * (_PS[1] + z * (_PS[2] + z * (_PS[3] + z * (_PS[4] + z * _PS[5])))))
    q = 1.0 + z * (_QS[0] + z * (_QS[1] + z * (_QS[2] + z * _QS[3])))
    return p / q


def asin(x: float) -> float:
    """asin(x), deterministic (fdlibm's algorithm, within 1 ulp); NaN outside [-1, 1]."""
    x = float(x)
    hx = _unpack_high(_pack_d(x))[0]
    ix = hx & 0x7FFFFFFF
    if ix >= 0x3FF00000:
        if x == 1.0 or x == -1.0:
            return x * _PIO2_HI
        return math.nan
    if ix < 0x3FE00000:
        if 0x00100000 <= ix < 0x3E500000:
            return x
        return x + x * _r(x * x)
    z = (1.0 - abs(x)) * 0.5
    s = math.sqrt(z)
    r = _r(z)
    if ix >= 0x3FEF3333:
        x = _PIO2_HI - (2 * (s + s * r) - _PIO2_LO)
    else:
        f = _clear_low(s)
        c = (z - f * f) / (s + f)
        x = 0.5 * _PIO2_HI - (2 * s * r - (_PIO2_LO - 2 * c) - (0.5 * _PIO2_HI - 2 * f))
    return -x if hx >> 31 else x


def acos(x: float) -> float:
    """acos(x), deterministic (fdlibm's algorithm, within 1 ulp); NaN outside [-1, 1]."""
    x = float(x)
    if 0.5 <= x < 1.0:  # high word in [0x3FE00000, 0x3FF00000), sign clear: the last case
        z = (1.0 - x) * 0.5
        s = math.sqrt(z)
        df = _unpack_d(b"\x00\x00\x00\x00" + _pack_d(s)[4:])[0]  # _clear_low(s)
        c = (z - df * df) / (s + df)
        w = _r(z) * s + c
        return 2 * (df + w)
    hx = _unpack_high(_pack_d(x))[0]
    ix = hx & 0x7FFFFFFF
    if ix >= 0x3FF00000:
        if x == 1.0:
            return 0.0
        if x == -1.0:
            return 2 * _PIO2_HI
        return math.nan
    if ix < 0x3FE00000:
        if ix <= 0x3C600000:
            return _PIO2_HI
        return _PIO2_HI - (x - (_PIO2_LO - x * _r(x * x)))
    if hx >> 31:
        z = (1.0 + x) * 0.5
        s = math.sqrt(z)
        w = _r(z) * s - _PIO2_LO
        return 2 * (_PIO2_HI - (s + w))
    z = (1.0 - x) * 0.5
    s = math.sqrt(z)
    df = _clear_low(s)
    c = (z - df * df) / (s + df)
    w = _r(z) * s + c
    return 2 * (df + w)


# --- tf.transformations ----------------------------------------------------------------------

#: 4 * machine epsilon, tf.transformations' tolerance.
_EPS = 2.220446049250313e-16 * 4.0

_NEXT_AXIS = [1, 2, 0, 1]

_AXES2TUPLE = {
    "sxyz": (0, 0, 0, 0), "sxyx": (0, 0, 1, 0), "sxzy": (0, 1, 0, 0),
    "sxzx": (0, 1, 1, 0), "syzx": (1, 0, 0, 0), "syzy": (1, 0, 1, 0),
    "syxz": (1, 1, 0, 0), "syxy": (1, 1, 1, 0), "szxy": (2, 0, 0, 0),
    "szxz": (2, 0, 1, 0), "szyx": (2, 1, 0, 0), "szyz": (2, 1, 1, 0),
    "rzyx": (0, 0, 0, 1), "rxyx": (0, 0, 1, 1), "ryzx": (0, 1, 0, 1),
    "rxzx": (0, 1, 1, 1), "rxzy": (1, 0, 0, 1), "ryzy": (1, 0, 1, 1),
    "rzxy": (1, 1, 0, 1), "ryxy": (1, 1, 1, 1), "ryxz": (2, 0, 0, 1),
    "rzxz": (2, 0, 1, 1), "rxyz": (2, 1, 0, 1), "rzyz": (2, 1, 1, 1)}

_TUPLE2AXES = {v: k for k, v in _AXES2TUPLE.items()}


def _axes(axes: str | tuple[int, int, int, int]) -> tuple[int, int, int, int]:
    if isinstance(axes, str) and axes.lower() in _AXES2TUPLE:
        return _AXES2TUPLE[axes.lower()]
    if isinstance(axes, tuple) and axes in _TUPLE2AXES:
        return axes
    raise DdesValueError(
        f"unknown Euler axis sequence {axes!r}; use one of the 24 of tf.transformations, "
        f"e.g. 'sxyz' (static x, y, z) or 'rzyx': {', '.join(sorted(_AXES2TUPLE))}")


def identity_matrix() -> Matrix:
    """The 4x4 identity matrix."""
    return [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0]]


def translation_matrix(direction: Sequence[float]) -> Matrix:
    """The 4x4 matrix translating by ``direction`` (x, y, z)."""
    m = identity_matrix()
    for r in range(3):
        m[r][3] = float(direction[r])
    return m


def translation_from_matrix(matrix: Sequence[Sequence[float]]) -> list[float]:
    """The translation [x, y, z] of a 4x4 matrix."""
    return [float(matrix[0][3]), float(matrix[1][3]), float(matrix[2][3])]


def _mat(matrix: Sequence[Sequence[float]]) -> Matrix:
    rows = [[float(v) for v in row] for row in matrix]
    if len(rows) != 4 or any(len(r) != 4 for r in rows):
        raise DdesValueError(f"expected a 4x4 matrix, got {len(rows)} rows of lengths "
                             f"{[len(r) for r in rows]}; pad a 3x3 rotation with "
                             "identity_matrix()'s last row and column")
    return rows


def _dot(a: Sequence[float], b: Sequence[float]) -> float:
    total = 0.0
    for u, v in zip(a, b, strict=True):
        total += u * v
    return total


def _matmul(a: Matrix, b: Matrix) -> Matrix:
    return [[a[r][0] * b[0][c] + a[r][1] * b[1][c] + a[r][2] * b[2][c] + a[r][3] * b[3][c]
             for c in range(4)] for r in range(4)]


def concatenate_matrices(*matrices: Sequence[Sequence[float]]) -> Matrix:
    """The product of 4x4 matrices, left to right (``concatenate_matrices(T, R)`` = T·R)."""
    m = identity_matrix()
    for other in matrices:
        m = _matmul(m, _mat(other))
    return m


def inverse_matrix(matrix: Sequence[Sequence[float]]) -> Matrix:
    """The inverse of a 4x4 matrix (Gauss-Jordan elimination with partial pivoting)."""
    a = _mat(matrix)
    inv = identity_matrix()
    for col in range(4):
        pivot = col
        for r in range(col + 1, 4):
            if abs(a[r][col]) > abs(a[pivot][col]):
                pivot = r
        if a[pivot][col] == 0.0:
            raise DdesValueError(f"matrix {a!r} is singular and has no inverse")
        a[col], a[pivot] = a[pivot], a[col]
        inv[col], inv[pivot] = inv[pivot], inv[col]
        p = a[col][col]
        a[col] = [v / p for v in a[col]]
        inv[col] = [v / p for v in inv[col]]
        for r in range(4):
            if r != col and a[r][col] != 0.0:
                f = a[r][col]
                a[r] = [u - f * v for u, v in zip(a[r], a[col], strict=True)]
                inv[r] = [u - f * v for u, v in zip(inv[r], inv[col], strict=True)]
    return inv


def vector_norm(data: Sequence[float]) -> float:
    """The Euclidean length of a vector."""
    v = [float(x) for x in data]
    return math.sqrt(_dot(v, v))


def unit_vector(data: Sequence[float]) -> list[float]:
    """``data`` divided by its length."""
    v = [float(x) for x in data]
    n = math.sqrt(_dot(v, v))
    return [x / n for x in v]


def euler_matrix(ai: float, aj: float, ak: float,
                 axes: str | tuple[int, int, int, int] = "sxyz") -> Matrix:
    """The 4x4 rotation matrix of Euler angles (roll ``ai``, pitch ``aj``, yaw ``ak``)."""
    firstaxis, parity, repetition, frame = _axes(axes)
    i = firstaxis
    j = _NEXT_AXIS[i + parity]
    k = _NEXT_AXIS[i - parity + 1]
    ai, aj, ak = float(ai), float(aj), float(ak)
    if frame:
        ai, ak = ak, ai
    if parity:
        ai, aj, ak = -ai, -aj, -ak
    si, sj, sk = sin(ai), sin(aj), sin(ak)
    ci, cj, ck = cos(ai), cos(aj), cos(ak)
    cc, cs = ci * ck, ci * sk
    sc, ss = si * ck, si * sk
    m = identity_matrix()
    if repetition:
        m[i][i] = cj
        m[i][j] = sj * si
        m[i][k] = sj * ci
        m[j][i] = sj * sk
        m[j][j] = -cj * ss + cc
        m[j][k] = -cj * cs - sc
        m[k][i] = -sj * ck
        m[k][j] = cj * sc + cs
        m[k][k] = cj * cc - ss
    else:
        m[i][i] = cj * ck
        m[i][j] = sj * sc - cs
        m[i][k] = sj * cc + ss
        m[j][i] = cj * sk
        m[j][j] = sj * ss + cc
        m[j][k] = sj * cs - sc
        m[k][i] = -sj
        m[k][j] = cj * si
        m[k][k] = cj * ci
    return m


def euler_from_matrix(matrix: Sequence[Sequence[float]],
                      axes: str | tuple[int, int, int, int] = "sxyz"
                      ) -> tuple[float, float, float]:
    """Euler angles (ai, aj, ak) of the rotation part of a 3x3 or 4x4 matrix."""
    firstaxis, parity, repetition, frame = _axes(axes)
    i = firstaxis
    j = _NEXT_AXIS[i + parity]
    k = _NEXT_AXIS[i - parity + 1]
    m = [[float(v) for v in row[:3]] for row in list(matrix)[:3]]
    if repetition:
        sy = math.sqrt(m[i][j] * m[i][j] + m[i][k] * m[i][k])
        if sy > _EPS:
            ax = atan2(m[i][j], m[i][k])
            ay = atan2(sy, m[i][i])
            az = atan2(m[j][i], -m[k][i])
        else:
            ax = atan2(-m[j][k], m[j][j])
            ay = atan2(sy, m[i][i])
            az = 0.0
    else:
        cy = math.sqrt(m[i][i] * m[i][i] + m[j][i] * m[j][i])
        if cy > _EPS:
            ax = atan2(m[k][j], m[k][k])
            ay = atan2(-m[k][i], cy)
            az = atan2(m[j][i], m[i][i])
        else:
            ax = atan2(-m[j][k], m[j][j])
            ay = atan2(-m[k][i], cy)
            az = 0.0
    if parity:
        ax, ay, az = -ax, -ay, -az
    if frame:
        ax, az = az, ax
    return ax, ay, az


def euler_from_quaternion(quaternion: Sequence[float],
                          axes: str | tuple[int, int, int, int] = "sxyz"
                          ) -> tuple[float, float, float]:
    """Euler angles (roll, pitch, yaw for 'sxyz') of a quaternion [x, y, z, w]."""
    return euler_from_matrix(quaternion_matrix(quaternion), axes)


def quaternion_from_euler(ai: float, aj: float, ak: float,
                          axes: str | tuple[int, int, int, int] = "sxyz") -> list[float]:
    """The quaternion [x, y, z, w] of Euler angles (roll ``ai``, pitch ``aj``, yaw ``ak``)."""
    firstaxis, parity, repetition, frame = _axes(axes)
    i = firstaxis
    j = _NEXT_AXIS[i + parity]
    k = _NEXT_AXIS[i - parity + 1]
    ai, aj, ak = float(ai), float(aj), float(ak)
    if frame:
        ai, ak = ak, ai
    if parity:
        aj = -aj
    ai /= 2.0
    aj /= 2.0
    ak /= 2.0
    ci, si = cos(ai), sin(ai)
    cj, sj = cos(aj), sin(aj)
    ck, sk = cos(ak), sin(ak)
    cc = ci * ck
    cs = ci * sk
    sc = si * ck
    ss = si * sk
    q = [0.0, 0.0, 0.0, 0.0]
    if repetition:
        q[i] = cj * (cs + sc)
        q[j] = sj * (cc + ss)
        q[k] = sj * (cs - sc)
        q[3] = cj * (cc - ss)
    else:
        q[i] = cj * sc - sj * cs
        q[j] = cj * ss + sj * cc
        q[k] = cj * cs - sj * sc
        q[3] = cj * cc + sj * ss
    if parity:
        q[j] *= -1
    return q


def quaternion_about_axis(angle: float, axis: Sequence[float]) -> list[float]:
    """The quaternion of a rotation by ``angle`` about ``axis``."""
    q = [float(axis[0]), float(axis[1]), float(axis[2]), 0.0]
    qlen = vector_norm(q)
    if qlen > _EPS:
        f = sin(angle / 2.0) / qlen
        q = [v * f for v in q]
    q[3] = cos(angle / 2.0)
    return q


def quaternion_matrix(quaternion: Sequence[float]) -> Matrix:
    """The 4x4 rotation matrix of a quaternion [x, y, z, w] (normalised first)."""
    q = [float(v) for v in list(quaternion)[:4]]
    nq = _dot(q, q)
    if nq < _EPS:
        return identity_matrix()
    f = math.sqrt(2.0 / nq)
    q = [v * f for v in q]
    o = [[a * b for b in q] for a in q]
    return [
        [1.0 - o[1][1] - o[2][2], o[0][1] - o[2][3], o[0][2] + o[1][3], 0.0],
        [o[0][1] + o[2][3], 1.0 - o[0][0] - o[2][2], o[1][2] - o[0][3], 0.0],
        [o[0][2] - o[1][3], o[1][2] + o[0][3], 1.0 - o[0][0] - o[1][1], 0.0],
        [0.0, 0.0, 0.0, 1.0]]


def quaternion_from_matrix(matrix: Sequence[Sequence[float]]) -> list[float]:
    """The quaternion [x, y, z, w] of the rotation part of a 4x4 matrix."""
    m = _mat(matrix)
    q = [0.0, 0.0, 0.0, 0.0]
    t = m[0][0] + m[1][1] + m[2][2] + m[3][3]
    if t > m[3][3]:
        q[3] = t
        q[2] = m[1][0] - m[0][1]
        q[1] = m[0][2] - m[2][0]
        q[0] = m[2][1] - m[1][2]
    else:
        i, j, k = 0, 1, 2
        if m[1][1] > m[0][0]:
            i, j, k = 1, 2, 0
        if m[2][2] > m[i][i]:
            i, j, k = 2, 0, 1
        t = m[i][i] - (m[j][j] + m[k][k]) + m[3][3]
        q[i] = t
        q[j] = m[i][j] + m[j][i]
        q[k] = m[k][i] + m[i][k]
        q[3] = m[k][j] - m[j][k]
    f = 0.5 / math.sqrt(t * m[3][3])
    return [v * f for v in q]


def quaternion_multiply(quaternion1: Sequence[float],
                        quaternion0: Sequence[float]) -> list[float]:
    """The product quaternion1 · quaternion0 (apply quaternion0 first)."""
    x0, y0, z0, w0 = (float(v) for v in quaternion0)
    x1, y1, z1, w1 = (float(v) for v in quaternion1)
    return [x1 * w0 + y1 * z0 - z1 * y0 + w1 * x0,
            -x1 * z0 + y1 * w0 + z1 * x0 + w1 * y0,
            x1 * y0 - y1 * x0 + z1 * w0 + w1 * z0,
            -x1 * x0 - y1 * y0 - z1 * z0 + w1 * w0]


def quaternion_conjugate(quaternion: Sequence[float]) -> list[float]:
    """[-x, -y, -z, w]."""
    x, y, z, w = (float(v) for v in quaternion)
    return [-x, -y, -z, w]


def quaternion_inverse(quaternion: Sequence[float]) -> list[float]:
    """The conjugate divided by the squared norm."""
    c = quaternion_conjugate(quaternion)
    n = _dot([float(v) for v in quaternion], [float(v) for v in quaternion])
    return [v / n for v in c]


def quaternion_slerp(quat0: Sequence[float], quat1: Sequence[float], fraction: float,
                     spin: int = 0, shortestpath: bool = True) -> list[float]:
    """Spherical linear interpolation from quat0 (fraction 0) to quat1 (fraction 1)."""
    q0 = unit_vector(list(quat0)[:4])
    q1 = unit_vector(list(quat1)[:4])
    if fraction == 0.0:
        return q0
    if fraction == 1.0:
        return q1
    d = _dot(q0, q1)
    if abs(abs(d) - 1.0) < _EPS:
        return q0
    if shortestpath and d < 0.0:
        d = -d
        q1 = [v * -1.0 for v in q1]
    angle = acos(d) + spin * _PI
    if abs(angle) < _EPS:
        return q0
    isin = 1.0 / sin(angle)
    f0 = sin((1.0 - fraction) * angle) * isin
    f1 = sin(fraction * angle) * isin
    return [a * f0 + b * f1 for a, b in zip(q0, q1, strict=True)]


def rotation_matrix(angle: float, direction: Sequence[float],
                    point: Sequence[float] | None = None) -> Matrix:
    """The 4x4 matrix rotating by ``angle`` about the axis ``direction`` through ``point``
    (the origin when None), as tf.transformations' ``rotation_matrix``."""
    sina, cosa = sin(float(angle)), cos(float(angle))
    d = unit_vector(list(direction)[:3])
    r = [[cosa, 0.0, 0.0], [0.0, cosa, 0.0], [0.0, 0.0, cosa]]
    for a in range(3):
        for b in range(3):
            r[a][b] += d[a] * d[b] * (1.0 - cosa)
    s = [v * sina for v in d]
    r[0][1] += -s[2]
    r[0][2] += s[1]
    r[1][0] += s[2]
    r[1][2] += -s[0]
    r[2][0] += -s[1]
    r[2][1] += s[0]
    m = identity_matrix()
    for a in range(3):
        m[a][:3] = r[a]
    if point is not None:
        p = [float(v) for v in list(point)[:3]]
        for a in range(3):
            m[a][3] = p[a] - (r[a][0] * p[0] + r[a][1] * p[1] + r[a][2] * p[2])
    return m


def scale_matrix(factor: float, origin: Sequence[float] | None = None,
                 direction: Sequence[float] | None = None) -> Matrix:
    """The 4x4 matrix scaling by ``factor`` about ``origin``, uniformly or along
    ``direction`` (tf.transformations' ``scale_matrix``)."""
    factor = float(factor)
    if direction is None:
        m = identity_matrix()
        for a in range(3):
            m[a][a] = factor
        if origin is not None:
            for a in range(3):
                m[a][3] = float(origin[a]) * (1.0 - factor)
        return m
    d = unit_vector(list(direction)[:3])
    f = 1.0 - factor
    m = identity_matrix()
    for a in range(3):
        for b in range(3):
            m[a][b] -= f * (d[a] * d[b])
    if origin is not None:
        k = f * _dot([float(v) for v in list(origin)[:3]], d)
        for a in range(3):
            m[a][3] = k * d[a]
    return m


def compose_matrix(scale: Sequence[float] | None = None, shear: Sequence[float] | None = None,
                   angles: Sequence[float] | None = None,
                   translate: Sequence[float] | None = None,
                   perspective: Sequence[float] | None = None) -> Matrix:
    """The 4x4 matrix of perspective, translation, static-xyz Euler ``angles``, shear and scale,
    in that order (tf.transformations' ``compose_matrix``)."""
    m = identity_matrix()
    if perspective is not None:
        p = identity_matrix()
        p[3] = [float(v) for v in list(perspective)[:4]]
        m = _matmul(m, p)
    if translate is not None:
        m = _matmul(m, translation_matrix(translate))
    if angles is not None:
        m = _matmul(m, euler_matrix(angles[0], angles[1], angles[2], "sxyz"))
    if shear is not None:
        z = identity_matrix()
        z[1][2] = float(shear[2])
        z[0][2] = float(shear[1])
        z[0][1] = float(shear[0])
        m = _matmul(m, z)
    if scale is not None:
        s = identity_matrix()
        for a in range(3):
            s[a][a] = float(scale[a])
        m = _matmul(m, s)
    w = m[3][3]
    return [[v / w for v in row] for row in m]


def is_same_transform(matrix0: Sequence[Sequence[float]],
                      matrix1: Sequence[Sequence[float]]) -> bool:
    """True when the two matrices, each divided by its ``[3][3]``, agree within numpy's
    ``allclose`` tolerances (``|a - b| <= 1e-8 + 1e-5 |b|``)."""
    a, b = _mat(matrix0), _mat(matrix1)
    a = [[v / a[3][3] for v in row] for row in a]
    b = [[v / b[3][3] for v in row] for row in b]
    return all(abs(x - y) <= 1e-8 + 1e-5 * abs(y)
               for ra, rb in zip(a, b, strict=True) for x, y in zip(ra, rb, strict=True))


def random_quaternion(rand: Sequence[float]) -> list[float]:
    """The uniformly distributed unit quaternion of three numbers ``rand`` uniform in [0, 1)
    (tf.transformations' ``random_quaternion(rand)``; here ``rand`` is required)."""
    if len(rand) != 3:
        raise DdesValueError(f"random_quaternion takes three numbers in [0, 1), got {rand!r}")
    u0, u1, u2 = (float(v) for v in rand)
    r1 = math.sqrt(1.0 - u0)
    r2 = math.sqrt(u0)
    pi2 = _PI * 2.0
    t1 = pi2 * u1
    t2 = pi2 * u2
    return [sin(t1) * r1, cos(t1) * r1, sin(t2) * r2, cos(t2) * r2]


def random_rotation_matrix(rand: Sequence[float]) -> Matrix:
    """The rotation matrix of :func:`random_quaternion` ``(rand)``."""
    return quaternion_matrix(random_quaternion(rand))
