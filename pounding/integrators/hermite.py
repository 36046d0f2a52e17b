"""The cubic Hermite interpolant of one step, compiled: from (value, slope) at both ends of a step
of length h, the value and slope inside it and the extremum where the slope changes sign.

One definition for every user: the time loop's event location (:mod:`pounding.integrators._events`),
the exact extremes of the modal recurrence (:mod:`pounding.spectra`) and the peak separation of an
ivp history (:mod:`pounding.separation`). With θ = t/h ∈ [0, 1] and the basis
h₀₀ = 2θ³ − 3θ² + 1, h₁₀ = θ³ − 2θ² + θ, h₀₁ = −2θ³ + 3θ², h₁₁ = θ³ − θ²:

.. math::

    y(θ) = h_{00}\\, y_0 + h_{10}\\, h\\, s_0 + h_{01}\\, y_1 + h_{11}\\, h\\, s_1
"""

from __future__ import annotations

from pounding._numba import jit


@jit
def hermite(y0, s0, y1, s1, h, th):
    """Value at θ of the cubic Hermite interpolant of (y0, slope s0) -> (y1, s1) over h."""
    t2 = th * th
    t3 = t2 * th
    return (
        (2 * t3 - 3 * t2 + 1) * y0
        + (t3 - 2 * t2 + th) * h * s0
        + (-2 * t3 + 3 * t2) * y1
        + (t3 - t2) * h * s1
    )


@jit
def hermite_slope(y0, s0, y1, s1, h, th):
    """Slope dy/dt at θ of the same interpolant [units of y per unit of h]."""
    t2 = th * th
    return (
        (6 * t2 - 6 * th) * y0 / h
        + (3 * t2 - 4 * th + 1) * s0
        + (-6 * t2 + 6 * th) * y1 / h
        + (3 * t2 - 2 * th) * s1
    )


@jit
def hermite_zero(y0, s0, y1, s1, h, of_slope):
    """θ in [0, 1] where the interpolant (``of_slope`` False) or its slope (True), of opposite signs
    at the two ends, vanishes: bisection to 1e-13 in θ."""
    lo, hi = 0.0, 1.0
    f_lo = s0 if of_slope else y0
    th = 0.5
    for _ in range(60):
        th = 0.5 * (lo + hi)
        f = hermite_slope(y0, s0, y1, s1, h, th) if of_slope else hermite(y0, s0, y1, s1, h, th)
        if (f > 0.0) == (f_lo > 0.0):
            lo = th
            f_lo = f
        else:
            hi = th
        if hi - lo < 1e-13:
            break
    return 0.5 * (lo + hi)


@jit
def hermite_extremum(y0, s0, y1, s1, h):
    """Value of the interpolant where its slope, of opposite signs at the two ends, vanishes."""
    return hermite(y0, s0, y1, s1, h, hermite_zero(y0, s0, y1, s1, h, True))
