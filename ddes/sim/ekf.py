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

import math
from collections.abc import Sequence

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
    """robot_localization's ``clampRotation``: into [-π, π] by whole turns."""
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
        p = self.P
        p0, p1, p2, p3, p4, p5, p6, p7 = p
        jp = [
            [a + jxy * b + cd * c_ - sd * d + ch * e - sh * f
             for a, b, c_, d, e, f in zip(p0, p2, p3, p4, p6, p7)],
            [a + jyy * b + sd * c_ + cd * d + sh * e + ch * f
             for a, b, c_, d, e, f in zip(p1, p2, p3, p4, p6, p7)],
            [a + delta * b for a, b in zip(p2, p5)],
            [a + delta * b for a, b in zip(p3, p6)],
            [a + delta * b for a, b in zip(p4, p7)],
            list(p5), list(p6), list(p7),
        ]
        q = self.q
        out = []
        for i in range(N):
            r = jp[i]
            r0, r1, r2, r3, r4, r5, r6, r7 = r
            qi = q[i]
            out.append([
                r0 + jxy * r2 + cd * r3 - sd * r4 + ch * r6 - sh * r7 + delta * qi[0],
                r1 + jyy * r2 + sd * r3 + cd * r4 + sh * r6 + ch * r7 + delta * qi[1],
                r2 + delta * r5 + delta * qi[2],
                r3 + delta * r6 + delta * qi[3],
                r4 + delta * r7 + delta * qi[4],
                r5 + delta * qi[5],
                r6 + delta * qi[6],
                r7 + delta * qi[7],
            ])
        self.P = out

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
        if threshold < math.inf:  # FilterBase::checkMahalanobisThreshold
            sy = [sum(s_inv[a][b] * y[b] for b in range(m)) for a in range(m)]
            if sum(y[a] * sy[a] for a in range(m)) >= threshold * threshold:
                return False
        rng_m = range(m)
        k_gain = [[sum(row[c] * s_inv[c][b] for c in rng_m) for b in rng_m] for row in pht]
        for i in range(N):
            ki = k_gain[i]
            x[i] += sum(ki[b] * y[b] for b in rng_m)
        # Joseph form (I - K H) P (I - K H)ᵀ + K R Kᵀ, expanded with H a selection:
        # P - K (H P) - (P Hᵀ) Kᵀ + K (H P Hᵀ + R) Kᵀ
        #   = P - Σ_b K[:, b] ⊗ PHᵀ[:, b] - Σ_b U[:, b] ⊗ K[:, b],  U = P Hᵀ - K S
        ks = [[sum(ki[c] * s[c][b] for c in rng_m) for b in rng_m] for ki in k_gain]
        cols_k = [[k_gain[j][b] for j in range(N)] for b in rng_m]
        cols_ph = [[pht[j][b] for j in range(N)] for b in rng_m]
        new = []
        for i in range(N):
            row = p[i]
            ki, phi, ksi = k_gain[i], pht[i], ks[i]
            for b in rng_m:
                a, u = ki[b], phi[b] - ksi[b]
                row = [r - a * h - u * k for r, h, k in zip(row, cols_ph[b], cols_k[b])]
            new.append(row if m else list(row))
        self.P = new
        x[_YAW] = wrap(x[_YAW])
        return True


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
