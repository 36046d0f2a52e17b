"""The Newmark/HHT coefficients of one step, the tangent without contacts and the end-of-step update:
written once for every step kind of the compiled core."""

from __future__ import annotations

from collections import namedtuple

import numpy as np

from pounding._numba import jit, jit_inline

#: Coefficients of a step of length h: a1 = c0 Δu − c2 v − c3 a, v1 = c1 Δu − c4 v − c5 a, and the
#: HHT weight w = 1 + α of the end-of-step forces (α the lag weight of the start-of-step ones).
Coef = namedtuple("Coef", "c0 c1 c2 c3 c4 c5 w alpha")


@jit_inline
def newmark_coefficients(h, sch):
    """:class:`Coef` of a step of length h [s] for the scheme ``sch`` (γ, β, α)."""
    gamma = sch.gamma
    beta = sch.beta
    return Coef(
        1.0 / (beta * h * h),
        gamma / (beta * h),
        1.0 / (beta * h),
        0.5 / beta - 1.0,
        gamma / beta - 1.0,
        h * (0.5 * gamma / beta - 1.0),
        1.0 + sch.alpha,
        sch.alpha,
    )


@jit_inline
def end_of_step(cf, u, v, a, u1, v1, a1):
    """a1 and v1 from the end displacement u1 by the Newmark relations."""
    for i in range(u.size):
        du = u1[i] - u[i]
        a1[i] = cf.c0 * du - cf.c2 * v[i] - cf.c3 * a[i]
        v1[i] = cf.c1 * du - cf.c4 * v[i] - cf.c5 * a[i]


@jit
def tangent_band(h, Mb, Cb, Kb, sch):
    """Band rows of the tangent without contacts, c0 M + w (c1 C + K), of a step of length h."""
    Jb = np.empty_like(Mb)
    tangent_band_into(h, Mb, Cb, Kb, sch, Jb)
    return Jb


@jit
def tangent_band_into(h, Mb, Cb, Kb, sch, Jb):
    """:func:`tangent_band` into Jb, for code that must not allocate."""
    cf = newmark_coefficients(h, sch)
    for i in range(Mb.shape[0]):
        for k in range(Mb.shape[1]):
            Jb[i, k] = cf.c0 * Mb[i, k] + cf.w * (cf.c1 * Cb[i, k] + Kb[i, k])


@jit
def tangent_dense(cf, M, C, K, J):
    """The same tangent, dense, into J."""
    n = M.shape[0]
    for i in range(n):
        for j in range(n):
            J[i, j] = cf.c0 * M[i, j] + cf.w * (cf.c1 * C[i, j] + K[i, j])
