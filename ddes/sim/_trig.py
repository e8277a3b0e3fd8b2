"""Deterministic sin, cos and atan2 for the simulator, made only of IEEE basic operations.

A private stand-in for ``ddes.transformations`` (pure-Python deterministic trig written
alongside): once that module lands, :mod:`ddes.sim` imports from it instead and this file
goes.  ``math.sin``/``math.cos``/``math.atan2`` call the platform's libm, whose last bit
differs between C libraries (glibc, macOS, musl); these functions use only ``+ - * /``
and comparisons on doubles, which CPython evaluates with IEEE round-to-nearest and no
fused multiply-add, so they give the same bits on every machine.

The polynomials are fdlibm's (``k_sin.c``, ``k_cos.c`` as in FreeBSD's msun, ``s_atan.c``;
Copyright (C) 1993 by Sun Microsystems, freely distributable), the argument reduction a
three-part Cody-Waite one.  Accuracy: within 1 ulp of the correctly rounded result for
|x| <= 2**19 * pi/2 (tests/sim/test_trig.py compares with libm); larger arguments raise.
"""

from __future__ import annotations

from math import copysign

__all__ = ["atan2", "cos", "sin", "sincos"]

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

_INVPIO2 = 6.36619772367581382433e-01
_PIO2_1 = 1.57079632673412561417e+00   # first 33 bits of pi/2
_PIO2_1T = 6.07710050650619224932e-11  # pi/2 - _PIO2_1
_PIO2_2 = 6.07710050630396597660e-11   # second 33 bits
_PIO2_2T = 2.02226624879595063154e-21  # pi/2 - (_PIO2_1 + _PIO2_2)
_PIO4 = 7.85398163397448278999e-01
_LIMIT = 823549.6561842185  # 2**19 * pi/2: n * _PIO2_1 and n * _PIO2_2 stay exact below it


def _ksin(x: float, y: float) -> float:
    z = x * x
    v = z * x
    r = _S2 + z * (_S3 + z * (_S4 + z * (_S5 + z * _S6)))
    return x - ((z * (0.5 * y - v * r) - y) - v * _S1)


def _kcos(x: float, y: float) -> float:
    z = x * x
    w = z * z
    r = z * (_C1 + z * (_C2 + z * _C3)) + w * w * (_C4 + z * (_C5 + z * _C6))
    hz = 0.5 * z
    w = 1.0 - hz
    return w + (((1.0 - w) - hz) + (z * r - x * y))


def _reduce(x: float) -> tuple[int, float, float]:
    """``x = n*pi/2 + (y0 + y1)`` with |y0 + y1| <= ~pi/4 (n mod 4 returned)."""
    if not -_LIMIT <= x <= _LIMIT:
        if x != x:
            return 0, x, 0.0
        raise ValueError(f"deterministic sin/cos take |x| <= {_LIMIT!r} (got {x!r}); "
                         "wrap the angle first")
    fn = float(int(x * _INVPIO2 + (0.5 if x >= 0 else -0.5)))
    r = x - fn * _PIO2_1
    w = fn * _PIO2_1T
    t = r
    w = fn * _PIO2_2
    r = t - w
    w = fn * _PIO2_2T - ((t - r) - w)
    y0 = r - w
    y1 = (r - y0) - w
    return int(fn) & 3, y0, y1


def sincos(x: float) -> tuple[float, float]:
    """``(sin(x), cos(x))``, bit-identical on every machine."""
    if -_PIO4 <= x <= _PIO4:
        if -7.450580596923828e-09 < x < 7.450580596923828e-09:  # 2**-27
            return x, 1.0
        return _ksin(x, 0.0), _kcos(x, 0.0)
    n, y0, y1 = _reduce(x)
    s = _ksin(y0, y1)
    c = _kcos(y0, y1)
    if n == 0:
        return s, c
    if n == 1:
        return c, -s
    if n == 2:
        return -s, -c
    return -c, s


def sin(x: float) -> float:
    """Deterministic ``sin(x)``."""
    return sincos(x)[0]


def cos(x: float) -> float:
    """Deterministic ``cos(x)``."""
    return sincos(x)[1]


_ATANHI = (4.63647609000806093515e-01, 7.85398163397448278999e-01,
           9.82793723247329054082e-01, 1.57079632679489655800e+00)
_ATANLO = (2.26987774529616870924e-17, 3.06161699786838301793e-17,
           1.39033110312309984516e-17, 6.12323399573676603587e-17)
_AT = (3.33333333333329318027e-01, -1.99999999998764832476e-01, 1.42857142725034663711e-01,
       -1.11111104054623557880e-01, 9.09088713343650656196e-02, -7.69187620504482999495e-02,
       6.66107313738753120669e-02, -5.83357013379057348645e-02, 4.97687799461593236017e-02,
       -3.65315727442169155270e-02, 1.62858201153657823623e-02)
_PI = 3.1415926535897931160e+00
_PI_LO = 1.2246467991473531772e-16
_PIO2 = 1.57079632679489655800e+00


def _atan_pos(x: float) -> float:
    """fdlibm's atan for 0 <= x (finite or +inf)."""
    if x >= 7.378697629483821e19:  # 2**66
        return _ATANHI[3] + _ATANLO[3]
    if x < 0.4375:
        if x < 7.450580596923828e-09:
            return x
        k = -1
    elif x < 1.1875:
        if x < 0.6875:
            k, x = 0, (2.0 * x - 1.0) / (2.0 + x)
        else:
            k, x = 1, (x - 1.0) / (x + 1.0)
    elif x < 2.4375:
        k, x = 2, (x - 1.5) / (1.0 + 1.5 * x)
    else:
        k, x = 3, -1.0 / x
    a = _AT
    z = x * x
    w = z * z
    s1 = z * (a[0] + w * (a[2] + w * (a[4] + w * (a[6] + w * (a[8] + w * a[10])))))
    s2 = w * (a[1] + w * (a[3] + w * (a[5] + w * (a[7] + w * a[9]))))
    if k < 0:
        return x - x * (s1 + s2)
    return _ATANHI[k] - ((x * (s1 + s2) - _ATANLO[k]) - x)


def atan2(y: float, x: float) -> float:
    """Deterministic ``atan2(y, x)`` (fdlibm's quadrant rules; signed zeros as libm)."""
    if x != x or y != y:
        return x + y
    neg_y = copysign(1.0, y) < 0.0  # copysign is exact: it only moves the sign bit
    neg_x = copysign(1.0, x) < 0.0
    ay = -y if neg_y else y
    ax = -x if neg_x else x
    if ay == 0.0:
        z = _PI if neg_x else 0.0
    elif ax == 0.0:
        z = _PIO2
    elif ax == float("inf"):
        if ay == float("inf"):
            z = 3.0 * _PIO4 if neg_x else _PIO4
        else:
            z = _PI if neg_x else 0.0
    elif ay == float("inf"):
        z = _PIO2
    else:
        q = ay / ax
        if q > 1.152921504606847e18:  # 2**60: |y/x| huge, the angle is pi/2 to the last bit
            z = _PIO2
        else:
            z = _atan_pos(q)
            if neg_x:
                z = _PI - (z - _PI_LO)
    return -z if neg_y else z
