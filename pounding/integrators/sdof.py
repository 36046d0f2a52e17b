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
)

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
