"""The SDOF oscillator under a piecewise-linear base acceleration, compiled: the exact recurrence
of Nigam and Jennings (1969) (coefficients in :func:`pounding.ground_motion.nigam_jennings_coefficients`).

The kernel of response spectra (:mod:`pounding.spectra`), separation estimates and floor response
spectra of a result; it lives with the integrators so that the analysis layer can use it without
the spectra module's xarray.
"""

from __future__ import annotations

import math

import numpy as np

from pounding._numba import jit
from pounding.errors import PoundingInputError
from pounding.ground_motion import (
    MIN_SUBSTEPS,
    _check_damping,
    _check_periods,
    nigam_jennings_coefficients,
    substeps,
)
from pounding.integrators.hermite import hermite_extremum

#: :func:`pounding.ground_motion.nigam_jennings_coefficients`, compiled for the kernels.
nigam_jennings_step = jit(nigam_jennings_coefficients)


@jit
def spectral_peaks_kernel(
    acc, dt, periods, damping, steps_per_period, free_vibration, out
):  # pragma: no cover - compiled
    n = acc.size
    for j in range(periods.size):
        period = periods[j]
        w = 2.0 * math.pi / period
        # ground_motion.substeps, scalar (the compiled kernel cannot call the numpy helper)
        m = max(MIN_SUBSTEPS, int(math.ceil(steps_per_period * dt / period - 1e-9)))
        h = dt / m
        A, B, C, D, Ap, Bp, Cp, Dp = nigam_jennings_step(w, damping, h)
        w2 = w * w
        cw = 2.0 * damping * w
        x = 0.0
        v = 0.0
        xmax = 0.0
        vmax = 0.0
        amax = 0.0
        for i in range(n - 1):
            a0 = acc[i]
            da = (acc[i + 1] - a0) / m
            for k in range(m):
                p0 = a0 + k * da
                p1 = acc[i + 1] if k == m - 1 else a0 + (k + 1) * da
                xn = A * x + B * v + C * p0 + D * p1
                v = Ap * x + Bp * v + Cp * p0 + Dp * p1
                x = xn
                xmax = max(xmax, abs(x))
                vmax = max(vmax, abs(v))
                amax = max(amax, abs(w2 * x + cw * v))
        if free_vibration:
            # damped free vibration: the largest extremum of each quantity is in its first cycle
            for _ in range(int(math.ceil(period / h)) + 1):
                xn = A * x + B * v
                v = Ap * x + Bp * v
                x = xn
                xmax = max(xmax, abs(x))
                vmax = max(vmax, abs(v))
                amax = max(amax, abs(w2 * x + cw * v))
        out[j, 0] = xmax
        out[j, 1] = vmax
        out[j, 2] = amax


def spectral_peaks(
    acceleration: np.ndarray,
    dt: float,
    periods: np.ndarray,
    damping: float,
    *,
    steps_per_period: int = 100,
    free_vibration: bool = True,
) -> np.ndarray:
    """Peaks (Sd [m], Sv [m/s], Sa [m/s²]) for each period, shape (n_periods, 3).

    Plain-array entry to the compiled kernel; see :func:`response_spectrum` for the meaning.
    """
    acc = np.ascontiguousarray(acceleration, dtype=float)
    periods = np.ascontiguousarray(_check_periods(periods))
    damping = _check_damping(damping)
    if not (isinstance(steps_per_period, (int, np.integer)) and steps_per_period >= 1):
        raise PoundingInputError(
            f"steps_per_period must be a positive integer, got {steps_per_period!r}"
        )
    out = np.empty((periods.size, 3))
    spectral_peaks_kernel(
        acc, float(dt), periods, damping, int(steps_per_period), bool(free_vibration), out
    )
    return out


@jit
def modal_extremes_kernel(
    acc, dt, omega, damping, m, n_sub, rows, out_max, out_min
):  # pragma: no cover - compiled
    n_modes = omega.size
    n_rows = rows.shape[0]
    h = dt / m
    coef = np.empty((n_modes, 8))
    for j in range(n_modes):
        A, B, C, D, Ap, Bp, Cp, Dp = nigam_jennings_step(omega[j], damping[j], h)
        coef[j, 0] = A
        coef[j, 1] = B
        coef[j, 2] = C
        coef[j, 3] = D
        coef[j, 4] = Ap
        coef[j, 5] = Bp
        coef[j, 6] = Cp
        coef[j, 7] = Dp
    x = np.zeros(n_modes)
    v = np.zeros(n_modes)
    y_prev = np.zeros(n_rows)
    s_prev = np.zeros(n_rows)
    for r in range(n_rows):
        out_max[r] = 0.0  # at rest at t = 0
        out_min[r] = 0.0
    for k in range(n_sub):
        i = k // m
        q = k - i * m
        a0 = acc[i]
        da = (acc[i + 1] - a0) / m
        p0 = a0 + q * da
        p1 = acc[i + 1] if q == m - 1 else a0 + (q + 1) * da
        for j in range(n_modes):
            xn = coef[j, 0] * x[j] + coef[j, 1] * v[j] + coef[j, 2] * p0 + coef[j, 3] * p1
            v[j] = coef[j, 4] * x[j] + coef[j, 5] * v[j] + coef[j, 6] * p0 + coef[j, 7] * p1
            x[j] = xn
        for r in range(n_rows):
            y = 0.0
            s = 0.0
            for j in range(n_modes):
                y += rows[r, j] * x[j]
                s += rows[r, j] * v[j]
            if s_prev[r] * s < 0.0 or (s == 0.0 and s_prev[r] != 0.0):
                # an extremum inside the sub-step: the max/min of the cubic through both ends
                e = hermite_extremum(y_prev[r], s_prev[r], y, s, h)
                out_max[r] = max(out_max[r], e)
                out_min[r] = min(out_min[r], e)
            out_max[r] = max(out_max[r], y)
            out_min[r] = min(out_min[r], y)
            y_prev[r] = y
            s_prev[r] = s


def modal_extremes(
    acceleration: np.ndarray,
    dt: float,
    omega: np.ndarray,
    damping: np.ndarray,
    rows: np.ndarray,
    duration: float,
    *,
    steps_per_period: int = 20,
) -> tuple[np.ndarray, np.ndarray, float]:
    r"""Extremes over time of linear combinations of modal responses to a ground motion.

    Each mode j obeys :math:`\ddot D_j + 2\zeta_j\omega_j\dot D_j + \omega_j^2 D_j = -a_g(t)`
    from rest; row r is :math:`y_r(t) = \sum_j R_{rj} D_j(t)` (with :math:`R_{rj} = \phi_j \Gamma_j`
    a floor displacement of a classically damped building, Chopra 2017 §13.1). All modes advance
    together by the exact Nigam-Jennings recurrence (the record linear between samples) on a common
    sub-step of at most dt/4 and min(T)/``steps_per_period``; between sub-steps, where ẏ_r changes
    sign, the extremum of the cubic Hermite interpolant of (y, ẏ) is taken (error O(h⁴)).

    Parameters
    ----------
    acceleration : ndarray
        Ground acceleration samples a_g [m/s²], a_g(0) = 0 for a start from rest; zero after them.
    dt : float
        Record step [s].
    omega, damping : ndarray, shape (n_modes,)
        Modal circular frequencies ω_j [rad/s] > 0 and damping ratios ζ_j [-] in [0, 1).
    rows : ndarray, shape (n_rows, n_modes)
        Combination coefficients R [m per m of D_j].
    duration : float
        Analysed time [s] (rounded to whole sub-steps).
    steps_per_period : int
        Sub-steps per shortest period (default 20).

    Returns
    -------
    (max_t y_r, min_t y_r, sub-step [s])
        Both including y(0) = 0.
    """
    omega = np.ascontiguousarray(omega, dtype=float)
    damping = np.ascontiguousarray(damping, dtype=float)
    rows = np.ascontiguousarray(np.atleast_2d(rows), dtype=float)
    if omega.shape != damping.shape or rows.shape[1] != omega.size:
        raise PoundingInputError(
            f"modal_extremes: {omega.size} frequencies, {damping.size} damping ratios and "
            f"{rows.shape[1]} row coefficients per row must agree"
        )
    if not (np.all(omega > 0) and np.all((damping >= 0) & (damping < 1))):
        raise PoundingInputError(
            "modal_extremes: need omega > 0 and 0 <= damping < 1 for every mode"
        )
    m = int(substeps(2.0 * math.pi / float(omega.max()), dt, steps_per_period))
    h = dt / m
    n_sub = max(1, int(round(duration / h)))
    need = n_sub // m + 2
    acc = np.zeros(max(need, len(acceleration)))
    acc[: len(acceleration)] = acceleration
    out_max = np.empty(rows.shape[0])
    out_min = np.empty(rows.shape[0])
    modal_extremes_kernel(acc, float(dt), omega, damping, m, n_sub, rows, out_max, out_min)
    return out_max, out_min, h
