"""The planar EKF of ``robot_localization/ekf_localization_node`` (``two_d_mode: true``), in pure
Python floats with the deterministic trig of :mod:`ddes.sim._trig`.

robot_localization (``cra-ros-pkg/robot_localization``, noetic: ``src/filter_base.cpp``,
``src/ekf.cpp``) keeps a 15-element state ``X Y Z ROLL PITCH YAW VX VY VZ VROLL VPITCH VYAW AX
AY AZ``.  In ``two_d_mode`` every measurement is forced to ``Z = ROLL = PITCH = VZ = VROLL =
VPITCH = AZ = 0`` with variance 1e-6 (``RosFilter::forceTwoD``), so those seven never couple to the
planar ones; this filter carries only the eight planar states
``X Y YAW VX VY VYAW AX AY`` (:data:`PLANAR`, indices into the 15-state vector) and gives the
same estimate for them.  The steps are upstream's:

* ``process_measurement``: the first measurement initialises the measured states and their
  covariance; later ones predict by ``delta = t - last`` when ``delta > 0`` (a ``delta`` over
  100000 s becomes 0.01 s, ``FilterBase::validateDelta``), then correct; the last measurement
  time moves only forwards.
* ``predict``: the omnidirectional constant-acceleration model of ``Ekf::predict`` with roll =
  pitch = 0; ``P = J P Jᵀ + delta·Q``.
* ``correct``: the measured, finite entries; variances below 1e-9 raised to 1e-9, negative ones
  made positive; angle innovations wrapped to [-π, π]; the Mahalanobis gate; Joseph-form
  covariance update; angles wrapped.

Times are integer nanoseconds; ``delta`` is ``(t - last) / 1e9``.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from typing import Any

from ddes.errors import DdesValueError
from ddes.sim._trig import sincos

__all__ = ["DEFAULT_INITIAL_COVARIANCE", "DEFAULT_PROCESS_NOISE", "PLANAR", "STATE_NAMES",
           "PlanarEkf", "wrap"]

#: robot_localization's state names, in its 15-state order.
STATE_NAMES = ("X", "Y", "Z", "ROLL", "PITCH", "YAW", "X_VELOCITY", "Y_VELOCITY", "Z_VELOCITY",
               "ROLL_VELOCITY", "PITCH_VELOCITY", "YAW_VELOCITY", "X_ACCELERATION",
               "Y_ACCELERATION", "Z_ACCELERATION")
#: The 15-state indices this filter carries: X Y YAW VX VY VYAW AX AY.
PLANAR = (0, 1, 5, 6, 7, 11, 12, 13)
N = len(PLANAR)
_YAW = 2  # the only angle among the planar states
#: ``process_noise_covariance``'s default diagonal (15 entries, robot_localization's).
DEFAULT_PROCESS_NOISE = (0.05, 0.05, 0.06, 0.03, 0.03, 0.06, 0.025, 0.025, 0.04, 0.01, 0.01,
                         0.02, 0.01, 0.01, 0.015)
#: ``initial_estimate_covariance``'s default diagonal (1e-9 for every state).
DEFAULT_INITIAL_COVARIANCE = (1e-9,) * 15

_TAU = 2.0 * math.pi


def wrap(a: float) -> float:
    """robot_localization's ``clampRotation``: into [-π, π] by whole turns (an infinite or NaN
    angle is returned as it is: whole turns never bring it into range)."""
    if not -math.inf < a < math.inf:
        return a
    while a > math.pi:
        a -= _TAU
    while a < -math.pi:
        a += _TAU
    return a


def _planar(matrix15: Sequence[float]) -> list[list[float]]:
    """The 8×8 planar block of a row-major 15×15 matrix."""
    return [[float(matrix15[15 * i + j]) for j in PLANAR] for i in PLANAR]


def _solve_inverse(a: list[list[float]]) -> list[list[float]]:
    """The inverse of a small square matrix (Gauss-Jordan, partial pivoting)."""
    m = len(a)
    aug = [list(row) + [1.0 if i == j else 0.0 for j in range(m)] for i, row in enumerate(a)]
    for col in range(m):
        piv = max(range(col, m), key=lambda r: abs(aug[r][col]))
        if aug[piv][col] == 0.0:
            raise DdesValueError("the innovation covariance is singular; give the measurement a "
                                 "nonzero variance")
        aug[col], aug[piv] = aug[piv], aug[col]
        p = aug[col][col]
        row = [v / p for v in aug[col]]
        aug[col] = row
        for r in range(m):
            if r != col:
                f = aug[r][col]
                if f != 0.0:
                    rr = aug[r]
                    aug[r] = [x - f * y for x, y in zip(rr, row)]
    return [row[m:] for row in aug]


class PlanarEkf:
    """The filter state: ``x`` (8 floats), ``P`` (8×8), ``last_ns``, ``initialized``.

    ``process_noise`` and ``initial_covariance`` are robot_localization's row-major 15×15
    parameters (or 15-entry diagonals); the planar block is used.
    """

    def __init__(self, process_noise: Sequence[float] = DEFAULT_PROCESS_NOISE,
                 initial_covariance: Sequence[float] = DEFAULT_INITIAL_COVARIANCE,
                 sensor_timeout: float = 1.0 / 30.0) -> None:
        self.q = _planar(_full(process_noise))
        self.p0 = _planar(_full(initial_covariance))
        self.sensor_timeout = float(sensor_timeout)
        self.reset()

    def reset(self) -> None:
        self.x = [0.0] * N
        self.P = [list(row) for row in self.p0]
        self.last_ns = 0
        self.initialized = False

    # -- FilterBase::processMeasurement ------------------------------------------------------
    def process(self, t_ns: int, z: dict[int, float], cov: dict[tuple[int, int], float],
                threshold: float = math.inf) -> bool:
        """Fuse measurement ``z`` (planar index → value; ``cov`` by index pairs) stamped
        ``t_ns``.  False when the Mahalanobis gate rejected it."""
        ok = True
        if not self.initialized:
            for i, v in z.items():
                self.x[i] = v
            for i in z:
                for j in z:
                    self.P[i][j] = cov.get((i, j), 0.0)
            self.initialized = True
            self.last_ns = t_ns
            return True
        delta_ns = t_ns - self.last_ns
        if delta_ns > 0:
            self.predict(delta_ns / 1e9)
        ok = self.correct(z, cov, threshold)
        if delta_ns >= 0:
            self.last_ns = t_ns
        return ok

    def predict_to(self, t_ns: int) -> None:
        """Project the state to ``t_ns`` (the sensor-timeout prediction of
        ``RosFilter::integrateMeasurements``)."""
        self.predict((t_ns - self.last_ns) / 1e9)
        self.last_ns = t_ns

    # -- Ekf::predict --------------------------------------------------------------------------
    def predict(self, delta: float) -> None:
        if delta > 100000.0:  # FilterBase::validateDelta
            delta = 0.01
        x = self.x
        yaw, vx, vy, vyaw, ax, ay = x[2], x[3], x[4], x[5], x[6], x[7]
        s, c = sincos(yaw)
        half = 0.5 * delta * delta
        # the transfer function (roll = pitch = 0)
        x[0] += (c * vx - s * vy) * delta + (c * ax - s * ay) * half
        x[1] += (s * vx + c * vy) * delta + (s * ax + c * ay) * half
        x[2] = wrap(yaw + vyaw * delta)
        x[3] = vx + ax * delta
        x[4] = vy + ay * delta
        # its Jacobian J: identity plus the entries of rows 0-4 below; P' = J P Jᵀ + delta·Q
        jxy = (-s * vx - c * vy) * delta + (-s * ax - c * ay) * half
        jyy = (c * vx - s * vy) * delta + (c * ax - s * ay) * half
        cd, sd, ch, sh = c * delta, s * delta, c * half, s * half
        self.P = _predict_covariance(self.P, self.q, jxy, jyy, cd, sd, ch, sh, delta)

    # -- Ekf::correct --------------------------------------------------------------------------
    def correct(self, z: dict[int, float], cov: dict[tuple[int, int], float],
                threshold: float = math.inf) -> bool:
        idx = [i for i in sorted(z) if math.isfinite(z[i])]
        if not idx:
            return True
        m = len(idx)
        r = [[cov.get((i, j), 0.0) for j in idx] for i in idx]
        for k in range(m):
            if r[k][k] < 0.0:
                r[k][k] = -r[k][k]
            if r[k][k] < 1e-9:
                r[k][k] = 1e-9
        x, p = self.x, self.P
        y = [z[i] - x[i] for i in idx]
        for k, i in enumerate(idx):
            if i == _YAW:
                y[k] = wrap(y[k])
        pht = [[p[i][j] for j in idx] for i in range(N)]  # P Hᵀ (8×m)
        s = [[pht[i][b] + r[a][b] for b in range(m)] for a, i in enumerate(idx)]
        s_inv = _solve_inverse(s)
        # Every sum below adds left to right from 0.0 (what sum() did up to Python 3.11; from
        # 3.12 sum() compensates float rounding, which would change the filter's last bits).
        rng_m = range(m)
        if threshold < math.inf:  # FilterBase::checkMahalanobisThreshold
            d2 = 0.0
            for a in rng_m:
                sya = 0.0
                for sab, yb in zip(s_inv[a], y):
                    sya += sab * yb
                d2 += y[a] * sya
            if d2 >= threshold * threshold:
                return False
        new = _gain_update(m)(p, pht, s, s_inv, y, x)
        self.P = new
        x[_YAW] = wrap(x[_YAW])
        return True


def _make_predict_covariance() -> Callable[..., list[list[float]]]:
    """``P' = J P Jᵀ + delta·Q`` of :meth:`PlanarEkf.predict` as one straight-line function of
    scalars: ``f(P, Q, jxy, jyy, cd, sd, ch, sh, delta)``.  Each entry is the expression of the
    row-wise loops it replaces, term for term in the same order (``JP = J P`` first, then
    ``JP Jᵀ + delta·Q``), so the results are the same floats."""
    rows = range(N)
    lines = ["def predict_covariance(p, q, jxy, jyy, cd, sd, ch, sh, delta):"]
    for i in rows:
        lines.append(f"    {', '.join(f'p{i}_{k}' for k in rows)} = p[{i}]")
        lines.append(f"    {', '.join(f'q{i}_{k}' for k in rows)} = q[{i}]")
    for k in rows:  # JP = J P: rows 0-4 of J differ from the identity
        lines.append(f"    a0_{k} = p0_{k} + jxy * p2_{k} + cd * p3_{k} - sd * p4_{k} + ch * p6_{k}"
                     f" - sh * p7_{k}")
        lines.append(f"    a1_{k} = p1_{k} + jyy * p2_{k} + sd * p3_{k} + cd * p4_{k} + sh * p6_{k}"
                     f" + ch * p7_{k}")
        lines.append(f"    a2_{k} = p2_{k} + delta * p5_{k}")
        lines.append(f"    a3_{k} = p3_{k} + delta * p6_{k}")
        lines.append(f"    a4_{k} = p4_{k} + delta * p7_{k}")
        lines += [f"    a{i}_{k} = p{i}_{k}" for i in (5, 6, 7)]
    out = []
    for i in rows:  # (JP) Jᵀ + delta·Q
        r = [f"a{i}_{k}" for k in rows]
        entries = [
            f"{r[0]} + jxy * {r[2]} + cd * {r[3]} - sd * {r[4]} + ch * {r[6]} - sh * {r[7]}"
            f" + delta * q{i}_0",
            f"{r[1]} + jyy * {r[2]} + sd * {r[3]} + cd * {r[4]} + sh * {r[6]} + ch * {r[7]}"
            f" + delta * q{i}_1",
            f"{r[2]} + delta * {r[5]} + delta * q{i}_2",
            f"{r[3]} + delta * {r[6]} + delta * q{i}_3",
            f"{r[4]} + delta * {r[7]} + delta * q{i}_4",
            f"{r[5]} + delta * q{i}_5",
            f"{r[6]} + delta * q{i}_6",
            f"{r[7]} + delta * q{i}_7",
        ]
        out.append("[" + ", ".join(entries) + "]")
    lines.append(f"    return [{', '.join(out)}]")
    space: dict[str, Any] = {}
    exec(compile("\n".join(lines) + "\n", "<ddes.sim.ekf predict>", "exec"), space)  # noqa: S102 - generated from constants
    fn: Callable[..., list[list[float]]] = space["predict_covariance"]
    return fn


_predict_covariance = _make_predict_covariance()


@functools.cache
def _gain_update(m: int) -> Callable[..., list[list[float]]]:
    """The gain and update of :meth:`PlanarEkf.correct` for ``m`` measured states, as one
    straight-line function of scalars (generated from ``m`` alone): ``f(P, PHᵀ, S, S⁻¹, y, x)``
    adds ``K y`` to ``x`` in place and returns the Joseph-form ``P``, with ``K = PHᵀ S⁻¹``.

    Every product and sum is the one of the plain loops it replaces, in the same order: each
    sum starts at 0.0 and adds left to right (what ``sum()`` did up to Python 3.11; from 3.12
    ``sum()`` compensates float rounding, which would change the filter's last bits), and each
    covariance entry is ``P[i][j] - K[i][b]·PHᵀ[j][b] - U[i][b]·K[j][b]`` for b = 0 … m-1 in
    turn, with ``U = PHᵀ - K S``.
    """
    rows, cols = range(N), range(m)

    def total(terms: list[str]) -> str:
        return "0.0 + " + " + ".join(terms)

    lines = ["def update(p, pht, s, s_inv, y, x):"]
    for i in rows:
        lines.append(f"    {', '.join(f'h{i}_{b}' for b in cols)}, = pht[{i}]")
    for c in cols:
        lines.append(f"    {', '.join(f'v{c}_{b}' for b in cols)}, = s_inv[{c}]")
        lines.append(f"    {', '.join(f's{c}_{b}' for b in cols)}, = s[{c}]")
    lines.append(f"    {', '.join(f'y{b}' for b in cols)}, = y")
    for i in rows:  # K = P Hᵀ S⁻¹, then x += K y
        for b in cols:
            lines.append(f"    k{i}_{b} = {total([f'h{i}_{c} * v{c}_{b}' for c in cols])}")
        lines.append(f"    x[{i}] += {total([f'k{i}_{b} * y{b}' for b in cols])}")
    for i in rows:  # U = P Hᵀ - K S
        for b in cols:
            ks = total([f"k{i}_{c} * s{c}_{b}" for c in cols])
            lines.append(f"    u{i}_{b} = h{i}_{b} - ({ks})")
    out = []
    for i in rows:
        lines.append(f"    r = p[{i}]")
        entries = []
        for j in rows:
            e = f"r[{j}]"
            for b in cols:
                e = f"({e} - k{i}_{b} * h{j}_{b} - u{i}_{b} * k{j}_{b})"
            entries.append(e)
        lines.append(f"    n{i} = [{', '.join(entries)}]")
        out.append(f"n{i}")
    lines.append(f"    return [{', '.join(out)}]")
    space: dict[str, Any] = {}
    exec(compile("\n".join(lines) + "\n", f"<ddes.sim.ekf update m={m}>", "exec"), space)  # noqa: S102 - generated from an int
    fn: Callable[..., list[list[float]]] = space["update"]
    return fn


def _full(values: Sequence[float]) -> list[float]:
    """A row-major 15×15 matrix from itself or from its 15-entry diagonal."""
    vals = [float(v) for v in values]
    if len(vals) == 225:
        return vals
    if len(vals) == 15:
        out = [0.0] * 225
        for i, v in enumerate(vals):
            out[16 * i] = v
        return out
    raise DdesValueError(f"a covariance parameter needs 225 (15×15) or 15 (diagonal) numbers, "
                     f"got {len(vals)}")
