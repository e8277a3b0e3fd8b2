"""The simulator's trig: :mod:`ddes.transformations`' deterministic sin, cos and atan2.

``math.sin``/``math.cos``/``math.atan2`` call the platform's libm, whose last bit differs
between C libraries; ``ddes.transformations`` computes them from IEEE basic operations only
(fdlibm's polynomials), the same bits on every machine.

:func:`sincos` gives ``(sin(x), cos(x))`` with exactly the bits of the two calls, for about
the price of one: the argument is reduced once (``ddes.transformations._rem_pio2``, the same
reduction both functions do) and both of fdlibm's kernels are evaluated with the same
operations in the same order (``tests/sim/test_trig.py`` compares them bit for bit).
"""

from __future__ import annotations

from ddes.transformations import (
    _C1,
    _C2,
    _C3,
    _C4,
    _C5,
    _C6,
    _S1,
    _S2,
    _S3,
    _S4,
    _S5,
    _S6,
    _SIN_KERNEL,
    _SIN_TINY,
    _hex,
    _kcos,
    _ksin,
    _rem_pio2,
    atan2,
    cos,
    sin,
)

__all__ = ["atan2", "cos", "sin", "sincos"]

#: |x| < _COS_TINY exactly when |x|'s high word is < 0x3E46A09E (fdlibm's cos returns 1.0).
_COS_TINY = _hex(0x3E46A09E00000000)


def sincos(x: float) -> tuple[float, float]:
    """``(sin(x), cos(x))``, bit-identical on every machine and to ``(sin(x), cos(x))``."""
    x = float(x)
    if -_SIN_KERNEL < x < _SIN_KERNEL:  # |x| <= ~pi/4: both kernels with y = 0, inline
        if -_COS_TINY < x < _COS_TINY:
            return x, 1.0
        z = x * x
        w = z * z
        r = z * (_C1 + z * (_C2 + z * _C3)) + w * w * (_C4 + z * (_C5 + z * _C6))
        hz = 0.5 * z
        c = 1.0 - hz
        c = c + (((1.0 - c) - hz) + (z * r - x * 0.0))
        if -_SIN_TINY < x < _SIN_TINY:
            return x, c
        r = _S2 + z * (_S3 + z * _S4) + z * w * (_S5 + z * _S6)
        return x + z * x * (_S1 + z * r), c
    if x != x or x in (_INF, -_INF):
        return x - x, x - x
    n, y0, y1 = _rem_pio2(x)
    s = _ksin(y0, y1, 1)
    c = _kcos(y0, y1)
    if n == 0:
        return s, c
    if n == 1:
        return c, -s
    if n == 2:
        return -s, -c
    return -c, s


_INF = float("inf")
