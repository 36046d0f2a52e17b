"""Compiled event helpers of the time loop: the ground motion between samples and the location of
the roots and first drop of a step's cubic Hermite interpolant (:mod:`pounding.integrators.hermite`)."""

from __future__ import annotations

from pounding._numba import jit, jit_inline
from pounding.integrators.hermite import hermite, hermite_slope, hermite_zero


@jit_inline
def ground_at(ag, ag_dt, t):
    """Ground acceleration at t, linear between samples, 0 after the record."""
    x = t / ag_dt
    i = int(x)
    if i >= ag.size - 1:
        return ag[-1] if x <= ag.size - 1 + 1e-9 else 0.0
    if i < 0:
        return 0.0
    w = x - i
    return (1.0 - w) * ag[i] + w * ag[i + 1]


@jit
def hermite_root(d0, v0, d1, v1, h):
    """θ in [0, 1] where the cubic Hermite interpolant of (d0, v0) -> (d1, v1) over h first crosses 0,
    and its derivative there. Assumes d0 <= 0 < d1 or d0 > 0 >= d1 (a sign change)."""
    th = hermite_zero(d0, v0, d1, v1, h, False)
    return th, hermite_slope(d0, v0, d1, v1, h, th)


@jit
def first_drop(g0, s0, g1, s1, h):
    """θ in (0, 1] where the Hermite cubic of (g0 >= 0, s0) -> (g1 <= 0, s1) first falls to 0.

    Unlike :func:`hermite_root` it allows g0 = 0 with s0 > 0 (a slab that just started sliding and
    turns back inside the step): the cubic is scanned for its first fall from > 0 to <= 0."""
    lo = 0.0
    hi = 1.0
    prev_pos = g0 > 0.0
    for j in range(1, 33):
        th = j / 32.0
        pos = hermite(g0, s0, g1, s1, h, th) > 0.0
        if prev_pos and not pos:
            lo = (j - 1) / 32.0
            hi = th
            break
        if pos:
            prev_pos = True
            lo = th
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if hermite(g0, s0, g1, s1, h, mid) > 0.0:
            lo = mid
        else:
            hi = mid
        if hi - lo < 1e-13:
            break
    return hi
