"""The simulator's trig: :mod:`ddes.transformations`' deterministic sin, cos and atan2.

``math.sin``/``math.cos``/``math.atan2`` call the platform's libm, whose last bit differs
between C libraries; ``ddes.transformations`` computes them from IEEE basic operations only
(fdlibm's polynomials), the same bits on every machine.  This module only pairs sin and cos.
"""

from __future__ import annotations

from ddes.transformations import atan2, cos, sin

__all__ = ["atan2", "cos", "sin", "sincos"]


def sincos(x: float) -> tuple[float, float]:
    """``(sin(x), cos(x))``, bit-identical on every machine."""
    return sin(x), cos(x)
