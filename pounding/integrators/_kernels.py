"""Compiled kernels of the Newmark/HHT time loop: impact log layout, element evaluation, residual and
tangent, Newton, the linear and condensed contact steps, events and the loop itself (the law dispatch,
the event helpers and the linear algebra live in ``_dispatch``, ``_events`` and ``_linalg``)."""

from __future__ import annotations

import math

# --------------------------------------------------------------------------------------------------
# Newmark / HHT-alpha time loop
# --------------------------------------------------------------------------------------------------
import numpy as np  # noqa: E402

from pounding._numba import jit, jit_inline  # noqa: F401  (re-exported: the kernels' decorators)

# The kernels' parts, by concern; names re-exported here for the integrators and the tests.
from pounding.integrators._dispatch import (  # noqa: F401
    BILINEAR_ID,
    bilinear_rate,
    bouc_wen_rate,
    bouc_wen_slide,
    contact_eval,
    contact_stored_energy,
    friction_eval,
    friction_hysteretic_eval,
)
from pounding.integrators._events import _hermite, first_drop, ground_at, hermite_root  # noqa: F401
from pounding.integrators._linalg import (  # noqa: F401
    _band_bilinear,
    _band_inverse,
    _band_matvec_add,
    _band_quadratic,
    _dense_matvec_add,
    _gauss_solve,
    _mv,
    _solve_small,
    _transpose,
    _woodbury_solve,
    band_ldl,
    band_solve,
    bandwidth,
    to_band,
)
from pounding.integrators.base import PATH_POINTS  # noqa: E402
from pounding.system import FRICTION_BOUC_WEN, FRICTION_COULOMB

#: Layout of the float row of the impact log.
IMP_START, IMP_END, IMP_V0, IMP_VEND, IMP_FMAX, IMP_DMAX, IMP_IMPULSE = range(7)
#: Columns of the impact log after those fields: points kept, steps per kept point, steps seen, then
#: PATH_POINTS (penetration [m], force [N]) pairs at integration steps through the impact, from the
#: closure to the separation; a longer impact keeps every 2nd, 4th, ... step (force-penetration loops
#: drawn from the output grid missed the peak of a 70-90 ms impact by up to 40 %).
IMP_NPTS, IMP_STRIDE, IMP_SEEN, IMP_PATH = 7, 8, 9, 10
IMP_COLUMNS = IMP_PATH + 2 * PATH_POINTS
#: Layout of the integer counters array.
CNT_IMPACTS, CNT_SUBSTEPS, CNT_NEWTON, CNT_LOCATED, CNT_STATUS, CNT_HALVINGS = range(6)
CNT_FRICTION = 6  # located stick-slip events
STATUS_NO_CONVERGENCE, STATUS_IMPACT_LOG_FULL = 1, 2  # 0: success
#: The dense map is used for the open-gap step while its 3n² products cost less than this many times
#: the band products 3n(2 bw + 1) (small systems, where loop overhead dominates the band form).
DENSE_MAP_RATIO = 0.35
# an event (closure, separation) due within this fraction of a step is taken at the step's end
EVENT_FRACTION = 1e-3
#: After an onset (adaptive stepping) the contact step starts 2^GRADED_STEPS times smaller and doubles.
GRADED_STEPS = 6
#: A contact step is stretched by up to this fraction to end at the base step's end.
SLIVER = 1e-2
#: A step shorter than this fraction of the base step restarts its end acceleration from equilibrium.
SHORT_STEP = 1e-3
#: Columns of the friction state (one row per friction element): stuck (1/0), sliding direction
#: (±1), Bouc-Wen z at the step start, force at the step start [N], trial force [N], trial z,
#: trial tangent ∂f/∂u_b [N/m] (inf for a stuck slab: a constraint).
FS_STUCK, FS_DIR, FS_Z0, FS_F0, FS_F1, FS_Z1, FS_KF = range(7)
N_FS = 7
#: Break-away is located to this fraction of μ_s N, re-sticking to this fraction of the speed scale.
FRICTION_FORCE_TOL = 1e-10
FRICTION_SPEED_TOL = 1e-9


@jit
def path_start(row):
    """Start the step path of an impact (its log row) at the closure: no penetration, no force."""
    row[IMP_NPTS] = 1.0
    row[IMP_STRIDE] = 1.0
    row[IMP_SEEN] = 0.0
    row[IMP_PATH] = 0.0
    row[IMP_PATH + 1] = 0.0


@jit
def path_add(row, d, f, last):
    """Add the step ending at penetration d [m] and force f [N] to the impact's path: every
    stride-th step, always the last; a full path drops every other point and doubles the stride."""
    seen = row[IMP_SEEN] + 1.0
    row[IMP_SEEN] = seen
    stride = row[IMP_STRIDE]
    n = int(row[IMP_NPTS])
    if seen % stride != 0.0 and not last:
        return
    if n == PATH_POINTS:
        if last:
            n -= 1  # the separation replaces the latest kept step
        else:
            half = PATH_POINTS // 2
            for j in range(half):
                row[IMP_PATH + 2 * j] = row[IMP_PATH + 4 * j]
                row[IMP_PATH + 2 * j + 1] = row[IMP_PATH + 4 * j + 1]
            n = half
            stride *= 2.0
            row[IMP_STRIDE] = stride
            row[IMP_NPTS] = n
            if seen % stride != 0.0:
                return
    row[IMP_PATH + 2 * n] = d
    row[IMP_PATH + 2 * n + 1] = f
    row[IMP_NPTS] = n + 1


@jit
def _eval_contacts(u1, v1, el_dof, el_sign, el_gap, el_law, el_params, el_in, el_v0, el_hd, el_hf,
                   el_off, d, dd, f, kd, cd):  # fmt: skip
    """δ, δ̇ (the system's sign arrays), force and tangents of every element at (u1, v1).

    Elements flagged in ``el_off`` are held open: the step ends at their closure, and a law whose
    force jumps at δ = 0⁺ (c v0 of the Kelvin family) must not act before it."""
    active = False
    for c in range(el_gap.size):
        a = el_dof[c, 0]
        b = el_dof[c, 1]
        dc = -el_gap[c]
        vc = 0.0
        if a >= 0:
            dc += el_sign[c, 0] * u1[a]
            vc += el_sign[c, 0] * v1[a]
        if b >= 0:
            dc += el_sign[c, 1] * u1[b]
            vc += el_sign[c, 1] * v1[b]
        d[c] = dc
        dd[c] = vc
        if el_off[c]:
            f[c] = 0.0
            kd[c] = 0.0
            cd[c] = 0.0
            continue
        # before the onset is registered, the approach speed itself stands in for v0
        v0 = el_v0[c] if el_in[c] else max(vc, 0.0)
        fc, kc, cc = contact_eval(el_law[c], dc, vc, v0, el_hd[c], el_hf[c], el_params[c])
        f[c] = fc
        kd[c] = kc
        cd[c] = cc
        if fc != 0.0 or kc != 0.0:
            active = True
    return active


@jit
def _eval_friction(u, u1, v1, c1, fr_dof, fr_kind, fr_law, fr_params, fr_bw, fr_normal, fr_state):
    """Trial force f1 and tangent ∂f1/∂u1 = c1 ∂f/∂v (+ ∂f/∂z ∂z1/∂u1) of every friction element.

    A stuck Coulomb slab is a constraint (tangent inf, force a reaction found after the step); a
    sliding one carries μ_d N against its direction. Returns True when a law is nonlinear."""
    nonlinear = False
    for k in range(fr_dof.size):
        b = fr_dof[k]
        kind = fr_kind[k]
        if kind == FRICTION_COULOMB:
            if fr_state[k, FS_STUCK] != 0.0:
                fr_state[k, FS_KF] = np.inf
            else:
                fr_state[k, FS_F1] = fr_state[k, FS_DIR] * fr_params[k, 1] * fr_normal[k]
                fr_state[k, FS_KF] = 0.0
        elif kind == FRICTION_BOUC_WEN:
            z1, dz = bouc_wen_slide(fr_state[k, FS_Z0], u1[b] - u[b], fr_bw[k])
            f, dfdv, dfdz = friction_hysteretic_eval(fr_law[k], v1[b], fr_normal[k], z1,
                                                     fr_params[k])  # fmt: skip
            fr_state[k, FS_Z1] = z1
            fr_state[k, FS_F1] = f
            fr_state[k, FS_KF] = c1 * dfdv + dfdz * dz
            nonlinear = True
        else:
            f, dfdv = friction_eval(fr_law[k], v1[b], fr_normal[k], fr_params[k])
            fr_state[k, FS_F1] = f
            fr_state[k, FS_KF] = c1 * dfdv
            nonlinear = True
    return nonlinear


@jit
def _residual(Mb, Cb, Kb, bw, Mi, g, u, v, a, el_dof, el_sign, f, n_el, fr_state, r):
    """r = M a + C v + K u + Bᵀ f + f_friction + M ι a_g: what the state fails the equation of
    motion by at one instant (zero for Newmark's end-of-step states; the α-weighted lag of HHT)."""
    n = u.size
    for i in range(n):
        r[i] = Mi[i] * g
    _band_matvec_add(Mb, bw, a, 1.0, r)
    _band_matvec_add(Cb, bw, v, 1.0, r)
    _band_matvec_add(Kb, bw, u, 1.0, r)
    for c in range(el_dof.shape[0]):
        fc = f[c] if c < n_el else fr_state[c - n_el, FS_F1]
        for s in range(2):
            i = el_dof[c, s]
            if i >= 0:
                r[i] += el_sign[c, s] * fc


@jit
def _tangent_band(hs, Mb, Cb, Kb, gamma, beta, alpha):
    """Band rows of the Newmark/HHT tangent without contacts, c0 M + (1 + α)(c1 C + K)."""
    c0 = 1.0 / (beta * hs * hs)
    c1 = gamma / (beta * hs)
    w = 1.0 + alpha
    Jb = np.empty_like(Mb)
    for i in range(Mb.shape[0]):
        for k in range(Mb.shape[1]):
            Jb[i, k] = c0 * Mb[i, k] + w * (c1 * Cb[i, k] + Kb[i, k])
    return Jb


@jit
def _newton(hs, t, u, v, a, f0, M, C, K, Mi, ag, ag_dt, gamma, beta, alpha,
            el_dof, el_sign, el_gap, el_law, el_params, el_in, el_v0, el_hd, el_hf, el_off,
            fr_dof, fr_kind, fr_law, fr_params, fr_bw, fr_normal, fr_state,
            tol, max_iter, J_inv, L, D, h_inv, Mb, Cb, Kb, bw, dense, work, Z, S,
            u1, v1, a1, d1, dd1, f1, kd1, cd1, R, J):  # fmt: skip
    """One Newmark/HHT step of length hs from (u, v, a); fills the *1 arrays. Returns (ok, iterations).

    ``el_dof``/``el_sign`` hold the gap elements followed by one row per friction element (its base
    dof, sign +1), so one Woodbury update covers active contacts, sliding tangents and stuck-slab
    constraints. When hs equals ``h_inv``, the step whose inverse tangent without contacts ``J_inv``
    is known, each iteration solves by that update; otherwise the full tangent is assembled and
    solved."""
    n = u.size
    n_el = el_gap.size
    n_fr = fr_dof.size
    n_x = n_el + n_fr
    c0 = 1.0 / (beta * hs * hs)
    c1 = gamma / (beta * hs)
    c2 = 1.0 / (beta * hs)
    c3 = 0.5 / beta - 1.0
    c4 = gamma / beta - 1.0
    c5 = hs * (0.5 * gamma / beta - 1.0)
    w = 1.0 + alpha
    g_eff = w * ground_at(ag, ag_dt, t + hs) - alpha * ground_at(ag, ag_dt, t)
    known = abs(hs - h_inv) <= 1e-8 * h_inv
    old = work[0]
    y = work[1]
    step = work[2]
    kc = work[3, :n_x]
    # the α-weighted old internal forces plus the load: −α (C v + K u + Bᵀ f0 + E f0_fr) + M ι g_eff
    for i in range(n):
        old[i] = Mi[i] * g_eff
    if alpha != 0.0:
        _mv(C, Cb, bw, dense, v, -alpha, old)
        _mv(K, Kb, bw, dense, u, -alpha, old)
        for c in range(n_el):
            if f0[c] != 0.0:
                for s in range(2):
                    i = el_dof[c, s]
                    if i >= 0:
                        old[i] -= alpha * el_sign[c, s] * f0[c]
        for k in range(n_fr):
            # a stuck slab's row is replaced by its constraint
            if fr_state[k, FS_STUCK] == 0.0:
                old[fr_dof[k]] -= alpha * fr_state[k, FS_F0]
    u_scale = 1e-3
    for i in range(n):
        # predictor: constant acceleration over the step (one Newton iteration fewer than u1 = u)
        u1[i] = u[i] + hs * v[i] + 0.5 * hs * hs * a[i]
        u_scale = max(u_scale, abs(u[i]))
    small = False
    prev_active = True
    for it in range(max_iter + 1):
        for i in range(n):
            du = u1[i] - u[i]
            a1[i] = c0 * du - c2 * v[i] - c3 * a[i]
            v1[i] = c1 * du - c4 * v[i] - c5 * a[i]
        active = _eval_contacts(u1, v1, el_dof, el_sign, el_gap, el_law, el_params, el_in, el_v0,
                                el_hd, el_hf, el_off, d1, dd1, f1, kd1, cd1)  # fmt: skip
        if n_fr > 0:
            if _eval_friction(u, u1, v1, c1, fr_dof, fr_kind, fr_law, fr_params, fr_bw, fr_normal,
                              fr_state):  # fmt: skip
                active = True
        if it > 0 and (small or (not active and not prev_active)):
            return True, it
        if it == max_iter:
            return False, it
        prev_active = active
        # residual of the weighted equation of motion
        for i in range(n):
            R[i] = old[i]
        _mv(M, Mb, bw, dense, a1, 1.0, R)
        _mv(C, Cb, bw, dense, v1, w, R)
        _mv(K, Kb, bw, dense, u1, w, R)
        for c in range(n_el):
            kc[c] = w * (kd1[c] + c1 * cd1[c])
            if f1[c] != 0.0:
                for s in range(2):
                    i = el_dof[c, s]
                    if i >= 0:
                        R[i] += w * el_sign[c, s] * f1[c]
        for k in range(n_fr):
            kc[n_el + k] = w * fr_state[k, FS_KF]
            if fr_state[k, FS_STUCK] == 0.0:
                R[fr_dof[k]] += w * fr_state[k, FS_F1]
        solved = False
        if known:
            solved = _woodbury_solve(J_inv, L, D, bw, dense, R, el_dof, el_sign, kc, Z, S, y, step)
        if not solved:
            for i in range(n):
                for j in range(n):
                    J[i, j] = c0 * M[i, j] + w * (c1 * C[i, j] + K[i, j])
            for c in range(n_x):
                if kc[c] != 0.0 and not math.isinf(kc[c]):
                    for s in range(2):
                        i = el_dof[c, s]
                        if i < 0:
                            continue
                        for r in range(2):
                            j = el_dof[c, r]
                            if j >= 0:
                                J[i, j] += kc[c] * el_sign[c, s] * el_sign[c, r]
            for c in range(n_el, n_x):
                if math.isinf(kc[c]):  # a stuck slab: its row becomes u1_b − u_b = 0
                    i = el_dof[c, 0]
                    for j in range(n):
                        J[i, j] = 0.0
                    J[i, i] = 1.0
                    R[i] = 0.0
            _gauss_solve(J, R, step)
            for i in range(n):
                step[i] = -step[i]
        big = 0.0
        u_max = u_scale
        for i in range(n):
            u1[i] += step[i]
            big = max(big, abs(step[i]))
            u_max = max(u_max, abs(u1[i]))
        for k in range(n_fr):
            if fr_state[k, FS_STUCK] != 0.0:
                u1[fr_dof[k]] = u[fr_dof[k]]  # exactly, not to round-off
        if not math.isfinite(big):
            return False, it
        small = big <= tol * u_max
    return False, max_iter


@jit
def _dense_map(hs, M, C, K, Mi, gamma, beta, alpha):
    """Q (n × 3n) and p (n) with u1 = Q [u; v; a] + p g_eff: one Newmark/HHT step of the linear
    system, for small systems (see :func:`_linear_step`)."""
    n = M.shape[0]
    bw = bandwidth(M, C, K)
    L, D = band_ldl(
        _tangent_band(hs, to_band(M, bw), to_band(C, bw), to_band(K, bw), gamma, beta, alpha), bw
    )
    J_inv = np.empty((n, n))
    _band_inverse(L, D, bw, J_inv)
    c0 = 1.0 / (beta * hs * hs)
    c1 = gamma / (beta * hs)
    c2 = 1.0 / (beta * hs)
    c3 = 0.5 / beta - 1.0
    c4 = gamma / beta - 1.0
    c5 = hs * (0.5 * gamma / beta - 1.0)
    w = 1.0 + alpha
    Q = np.zeros((n, 3 * n))
    pg = np.zeros(n)
    for i in range(n):
        for k in range(n):
            jik = J_inv[i, k]
            pg[i] -= jik * Mi[k]
            for j in range(n):
                Q[i, j] += jik * (c0 * M[k, j] + w * c1 * C[k, j] + alpha * K[k, j])
                Q[i, n + j] += jik * (c2 * M[k, j] + (w * c4 + alpha) * C[k, j])
                Q[i, 2 * n + j] += jik * (c3 * M[k, j] + w * c5 * C[k, j])
    return Q, pg


@jit
def _dense_step(Q, pg, g_eff, hs, gamma, beta, u, v, a, u1, v1, a1):
    """Apply the dense map (explicit loops: no allocation, no BLAS call overhead)."""
    n = u.size
    c0 = 1.0 / (beta * hs * hs)
    c1 = gamma / (beta * hs)
    c2 = 1.0 / (beta * hs)
    c3 = 0.5 / beta - 1.0
    c4 = gamma / beta - 1.0
    c5 = hs * (0.5 * gamma / beta - 1.0)
    for i in range(n):
        acc = pg[i] * g_eff
        for j in range(n):
            acc += Q[i, j] * u[j] + Q[i, n + j] * v[j] + Q[i, 2 * n + j] * a[j]
        u1[i] = acc
    for i in range(n):
        du = u1[i] - u[i]
        a1[i] = c0 * du - c2 * v[i] - c3 * a[i]
        v1[i] = c1 * du - c4 * v[i] - c5 * a[i]


@jit
def _linear_step(Mb, Cb, Kb, bw, L, D, Mi, g_eff, hs, gamma, beta, alpha, u, v, a, u1, v1, a1,
                 lin):  # fmt: skip
    """One Newmark/HHT step of the linear system (no contact force), solved for the increment:

    J Δu = M(c2 v + c3 a) + C((w c4 + α) v + w c5 a) − K u − M ι g_eff,  J = c0 M + w(c1 C + K),

    from the weighted equation M a1 + w(C v1 + K u1) − α(C v + K u) = −M ι g_eff (w = 1 + α) and the
    Newmark relations. Band matrix products and the band factors of J: O(n bw) per step, and the
    increment keeps its digits at small steps (u1 − u would not)."""
    n = u.size
    c0 = 1.0 / (beta * hs * hs)
    c1 = gamma / (beta * hs)
    c2 = 1.0 / (beta * hs)
    c3 = 0.5 / beta - 1.0
    c4 = gamma / beta - 1.0
    c5 = hs * (0.5 * gamma / beta - 1.0)
    w = 1.0 + alpha
    p, q, rhs, du = lin
    for i in range(n):
        p[i] = c2 * v[i] + c3 * a[i]
        q[i] = (w * c4 + alpha) * v[i] + w * c5 * a[i]
    for i in range(n):
        acc = -Mi[i] * g_eff
        for k in range(max(0, bw - i), min(2 * bw + 1, n - i + bw)):
            j = i - bw + k
            acc += Mb[i, k] * p[j] + Cb[i, k] * q[j] - Kb[i, k] * u[j]
        rhs[i] = acc
    band_solve(L, D, bw, rhs, du)
    for i in range(n):
        u1[i] = u[i] + du[i]
        a1[i] = c0 * du[i] - c2 * v[i] - c3 * a[i]
        v1[i] = c1 * du[i] - c4 * v[i] - c5 * a[i]


@jit
def _linear_step_coulomb(Mb, Cb, Kb, bw, L, D, Q, pg, Mi, g_eff, hs, gamma, beta, alpha, J_inv,
                         fr_dof, fr_params, fr_normal, fr_state, S, u, v, a, u1, v1, a1,
                         lin):  # fmt: skip
    """The linear map with Coulomb slabs: sliding ones load their base with the known force
    w f1 − α f0 (f = ±μ_d N), stuck ones hold u_b by reactions λ solved from J⁻¹ restricted to the
    stuck bases (the constrained step, no Newton)."""
    n = u.size
    w = 1.0 + alpha
    if Q.shape[0] == n:
        _dense_step(Q, pg, g_eff, hs, gamma, beta, u, v, a, u1, v1, a1)
    else:
        _linear_step(Mb, Cb, Kb, bw, L, D, Mi, g_eff, hs, gamma, beta, alpha, u, v, a, u1, v1, a1,
                     lin)  # fmt: skip
    m = 0
    for k in range(fr_dof.size):
        b = fr_dof[k]
        if fr_state[k, FS_STUCK] != 0.0:
            m += 1
            continue
        f1 = fr_state[k, FS_DIR] * fr_params[k, 1] * fr_normal[k]
        fr_state[k, FS_F1] = f1
        phi = w * f1 - alpha * fr_state[k, FS_F0]
        for i in range(n):
            u1[i] -= J_inv[i, b] * phi
    if m > 0:
        rhs_col = S.shape[1] - 1
        r = 0
        for k in range(fr_dof.size):
            if fr_state[k, FS_STUCK] == 0.0:
                continue
            q = 0
            for k2 in range(fr_dof.size):
                if fr_state[k2, FS_STUCK] != 0.0:
                    S[r, q] = J_inv[fr_dof[k], fr_dof[k2]]
                    q += 1
            S[r, rhs_col] = u1[fr_dof[k]] - u[fr_dof[k]]
            r += 1
        _solve_small(S, m)
        q = 0
        for k in range(fr_dof.size):
            if fr_state[k, FS_STUCK] == 0.0:
                continue
            lam = S[q, rhs_col]
            for i in range(n):
                u1[i] -= J_inv[i, fr_dof[k]] * lam
            q += 1
        for k in range(fr_dof.size):
            if fr_state[k, FS_STUCK] != 0.0:
                u1[fr_dof[k]] = u[fr_dof[k]]
    c0 = 1.0 / (beta * hs * hs)
    c1 = gamma / (beta * hs)
    c2 = 1.0 / (beta * hs)
    c3 = 0.5 / beta - 1.0
    c4 = gamma / beta - 1.0
    c5 = hs * (0.5 * gamma / beta - 1.0)
    for i in range(n):
        du = u1[i] - u[i]
        a1[i] = c0 * du - c2 * v[i] - c3 * a[i]
        v1[i] = c1 * du - c4 * v[i] - c5 * a[i]


@jit_inline
def _gaps(u1, v1, el_dof, el_sign, el_gap, d, dd):
    """δ and δ̇ of every element from the system's sign arrays; True when any gap is closed."""
    closed = False
    for c in range(el_gap.size):
        dc = -el_gap[c]
        vc = 0.0
        for s in range(2):
            i = el_dof[c, s]
            if i >= 0:
                dc += el_sign[c, s] * u1[i]
                vc += el_sign[c, s] * v1[i]
        d[c] = dc
        dd[c] = vc
        if dc > 0.0:
            closed = True
    return closed


@jit
def _condense_map(J_inv, el_dof, el_sign, Z, S):
    """Z = J⁻¹ B (n × C) and S = Bᵀ J⁻¹ B (C × C), B the gap elements' sign columns: how contact
    forces move every dof and every gap through one step of the linear system (in place)."""
    n = J_inv.shape[0]
    n_el = Z.shape[1]
    for c in range(n_el):
        for i in range(n):
            z = 0.0
            for s in range(2):
                k = el_dof[c, s]
                if k >= 0:
                    z += J_inv[i, k] * el_sign[c, s]
            Z[i, c] = z
    for r in range(n_el):
        for c in range(n_el):
            acc = 0.0
            for s in range(2):
                k = el_dof[r, s]
                if k >= 0:
                    acc += el_sign[r, s] * Z[k, c]
            S[r, c] = acc


@jit
def _contact_step(Z, S, hs, gamma, beta, alpha, u, u1, v1, a1, el_dof, el_sign, el_gap, el_law,
                  el_params, el_in, el_v0, el_hd, el_hf, el_off, f0, tol, max_iter, cw, act, Sm,
                  d1, dd1, f1, kd1, cd1):  # fmt: skip
    """A step with gap elements, condensed onto the gaps. On entry (u1, v1, a1) is the step of the
    linear system (no new contact force); Z and S are :func:`_condense_map` of the tangent that step
    used. The structure is linear apart from the contact forces, so the end of the step is

        u1 = u_lin + Z (α f0 − w f1),   δ = δ_lin + S (α f0 − w f1),   δ̇ = δ̇_lin + c1 (δ − δ_lin),

    and Newton runs on the C gap openings alone (no n × n work per iteration) before one O(nC)
    update of u1, v1, a1. Only the A gaps with a contact stiffness couple the Newton system, so each
    iteration solves A × A and back-substitutes the others: O(A³ + CA), not O(C³), for a long row
    of contacts with few closed. ``cw`` (4 × C) holds δ_lin, δ̇_lin, the stiffness columns and the
    residual; ``act`` the active gaps. Returns (ok, Newton iterations), as :func:`_newton`."""
    n = u.size
    n_el = el_gap.size
    c0 = 1.0 / (beta * hs * hs)
    c1 = gamma / (beta * hs)
    w = 1.0 + alpha
    rhs_col = Sm.shape[1] - 1
    d_lin = cw[0]
    dd_lin = cw[1]
    _gaps(u1, v1, el_dof, el_sign, el_gap, d_lin, dd_lin)
    u_scale = 1e-3
    for i in range(n):
        u_scale = max(u_scale, abs(u[i]), abs(u1[i]))
    tol_d = tol * u_scale
    # start from the forces of the step start (f1 ≈ f0 inside a contact, 0 outside)
    for c in range(n_el):
        acc = d_lin[c]
        for q in range(n_el):
            acc -= S[c, q] * f0[q]
        d1[c] = acc
    ok = False
    n_it = max_iter
    small = False
    prev_active = True
    for it in range(max_iter + 1):
        active = False
        for c in range(n_el):
            dd1[c] = dd_lin[c] + c1 * (d1[c] - d_lin[c])
            if el_off[c]:
                f1[c] = 0.0
                kd1[c] = 0.0
                cd1[c] = 0.0
                continue
            v0 = el_v0[c] if el_in[c] else max(dd1[c], 0.0)
            pc = (el_params[c, 0], el_params[c, 1], el_params[c, 2], el_params[c, 3])
            fc, kc, cc = contact_eval(el_law[c], d1[c], dd1[c], v0, el_hd[c], el_hf[c], pc)
            f1[c] = fc
            kd1[c] = kc
            cd1[c] = cc
            if fc != 0.0 or kc != 0.0:
                active = True
        if it > 0 and (small or (not active and not prev_active)):
            ok = True
            n_it = it
            break
        if it == max_iter:
            n_it = it
            break
        prev_active = active
        # r = δ − δ_lin − S (α f0 − w f1),  ∂r/∂δ = I + w S diag(k + c1 c): a column is zero
        # but for its unit diagonal where a gap has no stiffness
        n_act = 0
        for q in range(n_el):
            kq = w * (kd1[q] + c1 * cd1[q])
            cw[2, q] = kq
            if kq != 0.0:
                act[n_act] = q
                n_act += 1
        for r in range(n_el):
            acc = d1[r] - d_lin[r]
            for q in range(n_el):
                acc -= S[r, q] * (alpha * f0[q] - w * f1[q])
            cw[3, r] = -acc
        for ia in range(n_act):
            r = act[ia]
            for ja in range(n_act):
                q = act[ja]
                Sm[ia, ja] = S[r, q] * cw[2, q]
            Sm[ia, ia] += 1.0
            Sm[ia, rhs_col] = cw[3, r]
        if not _solve_small(Sm, n_act):
            n_it = it
            break
        for ia in range(n_act):
            cw[3, act[ia]] = Sm[ia, rhs_col]
        big = 0.0
        for c in range(n_el):
            if cw[2, c] == 0.0:
                for ja in range(n_act):
                    q = act[ja]
                    cw[3, c] -= S[c, q] * cw[2, q] * cw[3, q]
            d1[c] += cw[3, c]
            big = max(big, abs(cw[3, c]))
        if not math.isfinite(big):
            n_it = it
            break
        small = big <= tol_d
    if ok:
        for i in range(n):
            acc = 0.0
            for c in range(n_el):
                acc += Z[i, c] * (alpha * f0[c] - w * f1[c])
            u1[i] += acc
            v1[i] += c1 * acc
            a1[i] += c0 * acc
    return ok, n_it


@jit
def _stick_force(b, g1, Mi, C, K, u1, v1, el_dof, el_sign, f1, n_el):
    """Force p [N] that holds base dof b at rest: m_b u_b'' = p − f, p = −m_b a_g − (C u̇ + K u)_b
    − (Bᵀ F)_b. A stuck slab's friction equals p; it slides towards sign(p) once |p| > μ_s N."""
    p = -Mi[b] * g1
    for j in range(u1.size):
        p -= C[b, j] * v1[j] + K[b, j] * u1[j]
    for c in range(n_el):
        for s in range(2):
            if el_dof[c, s] == b:
                p -= el_sign[c, s] * f1[c]
    return p


@jit
def _friction_gap(k, b, fr_state, fr_params, fr_normal, v1, p1, sign):
    """Distance to the next stick-slip event of Coulomb element k (>= 0 before it): dir u̇_b while
    sliding; μ_s N − sign p while stuck (sign = the side the push is on)."""
    if fr_state[k, FS_STUCK] != 0.0:
        return fr_params[k, 0] * fr_normal[k] - sign * p1
    return fr_state[k, FS_DIR] * v1[b]


@jit
def _equilibrium(g1, u1, v1, a1, M_inv, Mi, C, K, el_dof, el_sign, f1, n_el,
                 fr_dof, fr_kind, fr_params, fr_normal, fr_state, rhs):  # fmt: skip
    """Restart the acceleration from equilibrium at (u1, v1), with the friction forces; a stuck
    Coulomb slab is tested: it keeps sticking (f = p, ü_b = 0) while |p| <= μ_s N, else it breaks
    away towards sign(p) against μ_d N. Returns True when a slab broke away."""
    n = u1.size
    broke = False
    for i in range(n):
        acc = -Mi[i] * g1
        for j in range(n):
            acc -= C[i, j] * v1[j] + K[i, j] * u1[j]
        rhs[i] = acc
    for c in range(n_el):
        for s in range(2):
            i = el_dof[c, s]
            if i >= 0:
                rhs[i] -= el_sign[c, s] * f1[c]
    for k in range(fr_dof.size):
        b = fr_dof[k]
        if fr_kind[k] == FRICTION_COULOMB and fr_state[k, FS_STUCK] != 0.0:
            p = rhs[b]
            if abs(p) <= fr_params[k, 0] * fr_normal[k]:
                fr_state[k, FS_F1] = p
                rhs[b] = 0.0
                continue
            fr_state[k, FS_STUCK] = 0.0
            fr_state[k, FS_DIR] = 1.0 if p > 0.0 else -1.0
            fr_state[k, FS_F1] = fr_state[k, FS_DIR] * fr_params[k, 1] * fr_normal[k]
            broke = True
        rhs[b] -= fr_state[k, FS_F1]
    for i in range(n):
        acc = 0.0
        for j in range(n):
            acc += M_inv[i, j] * rhs[j]
        a1[i] = acc
    for k in range(fr_dof.size):
        if fr_state[k, FS_STUCK] != 0.0:
            a1[fr_dof[k]] = 0.0
            v1[fr_dof[k]] = 0.0
    return broke


@jit
def newmark_run(M, C, K, iota, ag, ag_dt, h, n_steps, out_every, gamma, beta, alpha,
                el_dof, el_sign, el_gap, el_law, el_params, below,
                fr_dof, fr_kind, fr_law, fr_params, fr_bw, fr_normal,
                tol, max_iter, max_halvings, locate_onset, d_tol, v0_floor,
                adaptive, steps_per_contact, el_tc_coef, el_tc_exp,
                out_u, out_v, out_a, out_ag, out_d, out_f, out_e, out_ff, out_st,
                peak_u, peak_drift, peak_aabs, peak_f, peak_d,
                imp_el, imp_val, counters):  # fmt: skip
    """Integrate from rest over n_steps base steps of h; outputs every out_every steps (row 0 = t 0).

    ``el_dof``/``el_sign`` list the C gap elements followed by one row per friction element
    ([base dof, -1], [+1, 0]); ``fr_*`` describe the friction elements (pounding.system.FrictionElements).
    While every gap is open and every slab is stuck or sliding under Coulomb friction, a step is the
    precomputed linear map (no Newton). A step in which a gap closes is shortened to end at the
    closure; one in which a Coulomb slab turns back or breaks away, to end there. With ``adaptive``,
    steps inside a contact are t_c(v0)/steps_per_contact, t_c(v0) = el_tc_coef v0^el_tc_exp the
    element's undamped contact duration at the impact's own v0; otherwise every step is h. Returns
    the final time reached; ``counters[CNT_STATUS]`` tells success or the failure kind.
    """
    n = M.shape[0]
    n_el = el_gap.size
    n_fr = fr_dof.size
    n_x = n_el + n_fr
    Mi = np.zeros(n)
    _dense_matvec_add(M, iota, 1.0, Mi)
    u = np.zeros(n)
    v = np.zeros(n)
    a = np.zeros(n)
    g_0 = ground_at(ag, ag_dt, 0.0)
    for i in range(n):
        a[i] = -iota[i] * g_0
    u1 = np.zeros(n)
    v1 = np.zeros(n)
    a1 = np.zeros(n)
    R = np.zeros(n)
    J = np.zeros((n, n))
    d0 = np.zeros(n_el)
    dd0 = np.zeros(n_el)
    f0 = np.zeros(n_el)
    d1 = np.zeros(n_el)
    dd1 = np.zeros(n_el)
    f1 = np.zeros(n_el)
    kd1 = np.zeros(n_el)
    cd1 = np.zeros(n_el)
    el_in = np.zeros(n_el, dtype=np.bool_)
    el_v0 = np.zeros(n_el)
    el_hd = np.zeros(n_el)
    el_hf = np.zeros(n_el)
    el_imp = -np.ones(n_el, dtype=np.int64)
    closing = np.zeros(n_el, dtype=np.bool_)
    separating = np.zeros(n_el, dtype=np.bool_)
    none_off = np.zeros(n_el, dtype=np.bool_)
    open_off = np.zeros(n_el, dtype=np.bool_)
    theta = np.zeros(n_el)
    fr_state = np.zeros((n_fr, N_FS))
    fr_p = np.zeros(n_fr)
    fr_event = np.zeros(n_fr, dtype=np.bool_)
    n_coulomb = 0
    fr_linear = True
    for k in range(n_fr):
        if fr_kind[k] == FRICTION_COULOMB:
            n_coulomb += 1
            fr_state[k, FS_STUCK] = 1.0
        else:
            fr_linear = False
        fr_state[k, FS_DIR] = 1.0
    # band storage: a row of shear buildings has tridiagonal M, C (Rayleigh), K, so every per-step
    # product and solve is O(n); dense damping or an isolation slab widens the band, never beyond n
    bw = bandwidth(M, C, K)
    Mb = to_band(M, bw)
    Cb = to_band(C, bw)
    Kb = to_band(K, bw)
    # diagonal-major copies for the quadratic forms of the energy ledger
    MbT = _transpose(Mb)
    CbT = _transpose(Cb)
    KbT = _transpose(Kb)
    L_h, D_h = band_ldl(_tangent_band(h, Mb, Cb, Kb, gamma, beta, alpha), bw)
    # the inverses from the SPD band factors (the tangent and M are symmetric positive definite)
    J_inv = np.empty((n, n))
    _band_inverse(L_h, D_h, bw, J_inv)
    M_inv = np.empty((n, n))
    L_m, D_m = band_ldl(Mb, bw)
    _band_inverse(L_m, D_m, bw, M_inv)
    lin = (np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n))
    dense = n * (2 * bw + 1) * 3 >= DENSE_MAP_RATIO * n * n
    if dense:
        Q, pg = _dense_map(h, M, C, K, Mi, gamma, beta, alpha)
    else:
        Q = np.zeros((0, 3 * n))
        pg = np.zeros(0)
    h_contact = h
    grade = 0
    h_sep = np.inf  # largest step that keeps a receding contact's separation graded
    # the contact step size's tangent: filled in place (arrays reassigned inside the loop would cost
    # reference-count traffic on every step)
    J_inv_c = J_inv.copy()
    L_c = L_h.copy()
    D_c = D_h.copy()
    h_inv_c = h
    work = np.zeros((4, max(n, n_x)))
    # the contact step condensed onto the gaps (no friction elements): Z, S of the base step and of
    # the current contact step size
    Zh = np.zeros((n, n_el))
    Sh = np.zeros((n_el, n_el))
    _condense_map(J_inv, el_dof, el_sign, Zh, Sh)
    Zc = Zh.copy()
    Sc = Sh.copy()
    cw = np.zeros((4, n_el))
    act = np.zeros(n_el, dtype=np.int64)
    Sm = np.zeros((max(n_el, 1), max(n_el, 1) + 1))
    Z = np.zeros((n, max(n_x, 1)))
    S = np.zeros((max(n_x, 1), max(n_x, 1) + 1))
    # initial gaps (a contact may start closed when a gap is 0)
    for c in range(n_el):
        d0[c] = -el_gap[c]
    if n_fr > 0:
        # slabs start stuck (Coulomb) unless the first push already exceeds μ_s N
        _equilibrium(ground_at(ag, ag_dt, 0.0), u, v, a, M_inv, Mi, C, K, el_dof, el_sign, f0,
                     n_el, fr_dof, fr_kind, fr_params, fr_normal, fr_state, R)  # fmt: skip
        for k in range(n_fr):
            fr_state[k, FS_F0] = fr_state[k, FS_F1]
    e_in = 0.0
    e_damp = 0.0
    w_c = 0.0
    e_fr = 0.0
    e_alg = 0.0
    # the ledger is the scheme's own energy identity (work form, module docstring of newmark.py):
    # exact for average acceleration; other schemes add their algorithmic term
    algorithmic = alpha != 0.0 or gamma != 0.5 or beta != 0.25
    du = np.zeros(n)
    vs = np.zeros(n)
    r0 = np.zeros(n)
    r1 = np.zeros(n)
    if algorithmic:
        _residual(Mb, Cb, Kb, bw, Mi, ground_at(ag, ag_dt, 0.0), u, v, a, el_dof, el_sign, f0,
                  n_el, fr_state, r0)  # fmt: skip
    cap = imp_el.size
    t = 0.0
    # ground acceleration at the step start, carried from the last accepted step end
    g_start = ground_at(ag, ag_dt, 0.0)
    _store(np.int64(0), t, u, v, a, ag, ag_dt, d0, f0, e_in, e_damp, w_c, e_fr, e_alg, MbT, KbT, bw, el_law, el_params,
           fr_state, out_u, out_v, out_a, out_ag, out_d, out_f, out_e, out_ff, out_st)  # fmt: skip
    for k in range(n_steps):
        t = k * h
        t_next = (k + 1) * h
        scale = 1.0
        halvings = 0
        while t < t_next - 1e-9 * h:
            in_contact = False
            for c in range(n_el):
                in_contact = in_contact or el_in[c]
                # with onset location, trial steps hold every open gap open: a closure is then located
                # on the smooth contact-free motion, not on a trial that already bounced off the contact
                open_off[c] = locate_onset and not el_in[c]
            hs = (min(h_contact * 0.5**grade, h_sep) if in_contact else h) * scale
            if t_next - t - hs < SLIVER * hs:
                # end at the base step rather than leave a sliver: a step of 1e-9 h turns the
                # round-off of u into an acceleration error of order c0 ε u = 4 ε u / hs²
                hs = t_next - t
            if abs(hs - h) <= 1e-8 * h:
                hs = h  # a full base step: (k + 1) h − k h is not bit-equal to h
            ok = True
            its = 0
            t_g = t + hs
            g_tg = ground_at(ag, ag_dt, t_g)
            if not in_contact and hs == h and fr_linear:
                # open gaps, Coulomb slabs stuck or sliding: the exact linear step
                g_eff = (1.0 + alpha) * g_tg - alpha * g_start
                if n_fr == 0:
                    if Q.shape[0] == n:
                        _dense_step(Q, pg, g_eff, hs, gamma, beta, u, v, a, u1, v1, a1)
                    else:
                        _linear_step(Mb, Cb, Kb, bw, L_h, D_h, Mi, g_eff, hs, gamma, beta, alpha,
                                     u, v, a, u1, v1, a1, lin)  # fmt: skip
                else:
                    _linear_step_coulomb(Mb, Cb, Kb, bw, L_h, D_h, Q, pg, Mi, g_eff, hs, gamma, beta,
                                         alpha, J_inv, fr_dof, fr_params, fr_normal, fr_state, S, u, v, a,
                                         u1, v1, a1, lin)  # fmt: skip
                closed = _gaps(u1, v1, el_dof, el_sign, el_gap, d1, dd1)
                for c in range(n_el):
                    f1[c] = 0.0
                if closed and not locate_onset and n_fr == 0:
                    ok, its = _contact_step(Zh, Sh, hs, gamma, beta, alpha, u, u1, v1, a1, el_dof,
                                            el_sign, el_gap, el_law, el_params, el_in, el_v0, el_hd,
                                            el_hf, none_off, f0, tol, max_iter, cw, act, Sm,
                                            d1, dd1, f1, kd1, cd1)  # fmt: skip
                elif closed and not locate_onset:
                    ok, its = _newton(hs, t, u, v, a, f0, M, C, K, Mi, ag, ag_dt, gamma, beta, alpha,
                                      el_dof, el_sign, el_gap, el_law, el_params, el_in, el_v0, el_hd,
                                      el_hf, none_off, fr_dof, fr_kind, fr_law, fr_params, fr_bw,
                                      fr_normal, fr_state, tol, max_iter, J_inv, L_h, D_h, h, Mb, Cb, Kb, bw, dense, work, Z, S,
                                      u1, v1, a1, d1, dd1, f1, kd1, cd1, R, J)  # fmt: skip
            else:
                if in_contact and abs(hs - h_contact) <= 1e-8 * h_contact and h_inv_c != h_contact:
                    # a new contact step size: its tangent inverse serves every step of the impact
                    L_new, D_new = band_ldl(_tangent_band(hs, Mb, Cb, Kb, gamma, beta, alpha), bw)
                    _band_inverse(L_new, D_new, bw, J_inv_c)
                    for i in range(n):
                        D_c[i] = D_new[i]
                        for j in range(bw + 1):
                            L_c[i, j] = L_new[i, j]
                    h_inv_c = hs
                    _condense_map(J_inv_c, el_dof, el_sign, Zc, Sc)
                use_c = abs(hs - h_inv_c) <= 1e-8 * h_inv_c
                if use_c:
                    hs = h_inv_c  # the step whose stored tangent serves it, exactly
                    t_g = t + hs
                    g_tg = ground_at(ag, ag_dt, t_g)
                if n_fr == 0 and (hs == h or use_c):
                    # the linear step, then Newton on the gaps alone
                    g_eff = (1.0 + alpha) * g_tg - alpha * g_start
                    if hs == h:
                        if Q.shape[0] == n:
                            _dense_step(Q, pg, g_eff, hs, gamma, beta, u, v, a, u1, v1, a1)
                        else:
                            _linear_step(Mb, Cb, Kb, bw, L_h, D_h, Mi, g_eff, hs, gamma, beta,
                                         alpha, u, v, a, u1, v1, a1, lin)  # fmt: skip
                        ok, its = _contact_step(Zh, Sh, hs, gamma, beta, alpha, u, u1, v1, a1,
                                                el_dof, el_sign, el_gap, el_law, el_params, el_in,
                                                el_v0, el_hd, el_hf, open_off, f0, tol, max_iter,
                                                cw, act, Sm, d1, dd1, f1, kd1, cd1)  # fmt: skip
                    else:
                        _linear_step(Mb, Cb, Kb, bw, L_c, D_c, Mi, g_eff, hs, gamma, beta, alpha,
                                     u, v, a, u1, v1, a1, lin)  # fmt: skip
                        ok, its = _contact_step(Zc, Sc, hs, gamma, beta, alpha, u, u1, v1, a1,
                                                el_dof, el_sign, el_gap, el_law, el_params, el_in,
                                                el_v0, el_hd, el_hf, open_off, f0, tol, max_iter,
                                                cw, act, Sm, d1, dd1, f1, kd1, cd1)  # fmt: skip
                elif use_c:
                    ok, its = _newton(hs, t, u, v, a, f0, M, C, K, Mi, ag, ag_dt, gamma, beta,
                                      alpha, el_dof, el_sign, el_gap, el_law, el_params, el_in,
                                      el_v0, el_hd, el_hf, open_off, fr_dof, fr_kind, fr_law,
                                      fr_params, fr_bw, fr_normal, fr_state, tol, max_iter, J_inv_c,
                                      L_c, D_c, h_inv_c, Mb, Cb, Kb, bw, dense, work, Z, S, u1, v1,
                                      a1, d1, dd1, f1, kd1, cd1, R, J)  # fmt: skip
                else:
                    ok, its = _newton(hs, t, u, v, a, f0, M, C, K, Mi, ag, ag_dt, gamma, beta,
                                      alpha, el_dof, el_sign, el_gap, el_law, el_params, el_in,
                                      el_v0, el_hd, el_hf, open_off, fr_dof, fr_kind, fr_law,
                                      fr_params, fr_bw, fr_normal, fr_state, tol, max_iter, J_inv,
                                      L_h, D_h, h, Mb, Cb, Kb, bw, dense, work, Z, S, u1, v1, a1, d1,
                                      dd1, f1, kd1, cd1, R, J)  # fmt: skip
            counters[CNT_NEWTON] += its
            if not ok:
                halvings += 1
                counters[CNT_HALVINGS] += 1
                if halvings > max_halvings:
                    counters[CNT_STATUS] = STATUS_NO_CONVERGENCE
                    return t
                scale *= 0.5
                continue
            for c in range(n_el):
                closing[c] = False
            if locate_onset:
                # the earliest gap closure inside the step: shorten the step to end there, refining
                # until the closing gap is shut to within d_tol (a penetration below d_tol is
                # round-off, never an onset: identical neighbours at zero gap stay apart)
                th_min = 1.0
                for c in range(n_el):
                    if not el_in[c] and d0[c] <= d_tol < d1[c]:
                        th, _ = hermite_root(d0[c], dd0[c], d1[c], dd1[c], hs)
                        theta[c] = th
                        th_min = min(th_min, th)
                    else:
                        theta[c] = 2.0
                if th_min < 1.0:
                    for c in range(n_el):
                        closing[c] = theta[c] <= th_min * (1.0 + 1e-9)
                    counters[CNT_LOCATED] += 1
                    for _ in range(8):
                        hs = max(th_min * hs, 1e-12 * h)
                        ok, its = _newton(hs, t, u, v, a, f0, M, C, K, Mi, ag, ag_dt, gamma, beta,
                                          alpha, el_dof, el_sign, el_gap, el_law, el_params, el_in,
                                          el_v0, el_hd, el_hf, open_off, fr_dof, fr_kind, fr_law,
                                          fr_params, fr_bw, fr_normal, fr_state, tol, max_iter,
                                          J_inv, L_h, D_h, h, Mb, Cb, Kb, bw, dense, work, Z, S, u1, v1, a1, d1, dd1, f1, kd1, cd1,
                                          R, J)  # fmt: skip
                        counters[CNT_NEWTON] += its
                        if not ok:
                            break
                        d_hi = -1.0
                        th_min = 1.0
                        for c in range(n_el):
                            if closing[c]:
                                d_hi = max(d_hi, d1[c])
                                if d1[c] > d_tol:
                                    th, _ = hermite_root(d0[c], dd0[c], d1[c], dd1[c], hs)
                                    th_min = min(th_min, th)
                        if d_hi <= d_tol:
                            break
                    if not ok:
                        halvings += 1
                        counters[CNT_HALVINGS] += 1
                        if halvings > max_halvings:
                            counters[CNT_STATUS] = STATUS_NO_CONVERGENCE
                            return t
                        scale *= 0.5
                        continue
                    # a gap that stopped short of closing closes in a later step
                    for c in range(n_el):
                        if closing[c] and d1[c] < -d_tol:
                            closing[c] = False
                # the earliest separation inside the step: end the step there as well, so a contact
                # force acts down to δ = 0 and no further (a step that carried it past the
                # separation did work the contact never stored: energy out of nothing)
                th_min = 1.0
                for c in range(n_el):
                    separating[c] = False
                    if el_in[c] and d0[c] > 0.0 and d1[c] < -d_tol:
                        th, _ = hermite_root(d0[c], dd0[c], d1[c], dd1[c], hs)
                        theta[c] = th
                        th_min = min(th_min, th)
                    else:
                        theta[c] = 2.0
                if th_min < 1.0:
                    for c in range(n_el):
                        separating[c] = theta[c] <= th_min * (1.0 + 1e-9)
                    counters[CNT_LOCATED] += 1
                    for _ in range(8):
                        hs = max(th_min * hs, 1e-12 * h)
                        ok, its = _newton(hs, t, u, v, a, f0, M, C, K, Mi, ag, ag_dt, gamma, beta,
                                          alpha, el_dof, el_sign, el_gap, el_law, el_params, el_in,
                                          el_v0, el_hd, el_hf, open_off, fr_dof, fr_kind, fr_law,
                                          fr_params, fr_bw, fr_normal, fr_state, tol, max_iter,
                                          J_inv, L_h, D_h, h, Mb, Cb, Kb, bw, dense, work, Z, S, u1,
                                          v1, a1, d1, dd1, f1, kd1, cd1, R, J)  # fmt: skip
                        counters[CNT_NEWTON] += its
                        if not ok:
                            break
                        d_lo = 1.0
                        th_min = 1.0
                        for c in range(n_el):
                            if separating[c]:
                                d_lo = min(d_lo, d1[c])
                                if d1[c] < -d_tol:
                                    th, _ = hermite_root(d0[c], dd0[c], d1[c], dd1[c], hs)
                                    th_min = min(th_min, th)
                        if d_lo >= -d_tol:
                            break
                    if not ok:
                        halvings += 1
                        counters[CNT_HALVINGS] += 1
                        if halvings > max_halvings:
                            counters[CNT_STATUS] = STATUS_NO_CONVERGENCE
                            return t
                        scale *= 0.5
                        continue
                    for c in range(n_el):
                        # one still short of separating (δ > d_tol) separates in a later step
                        if separating[c] and d1[c] > d_tol:
                            separating[c] = False
                        if closing[c] and d1[c] < -d_tol:
                            closing[c] = False
            t1 = t + hs
            g1 = g_tg if t1 == t_g else ground_at(ag, ag_dt, t1)
            fr_restart = False
            if n_coulomb > 0:
                # Coulomb stick-slip: the earliest turn-back of a sliding slab or break-away of a
                # stuck one ends the step (regula falsi with the Illinois rule on the step length)
                ev = -1
                th_ev = 2.0
                for kk in range(n_fr):
                    fr_event[kk] = False
                    if fr_kind[kk] != FRICTION_COULOMB:
                        continue
                    b = fr_dof[kk]
                    if fr_state[kk, FS_STUCK] != 0.0:
                        p1 = _stick_force(b, g1, Mi, C, K, u1, v1, el_dof, el_sign, f1, n_el)
                        fr_p[kk] = p1
                        sg = 1.0 if p1 > 0.0 else -1.0
                        g_end = _friction_gap(kk, b, fr_state, fr_params, fr_normal, v1, p1, sg)
                        if g_end < 0.0:
                            fg_start = fr_params[kk, 0] * fr_normal[kk] - sg * fr_state[kk, FS_F0]
                            th = fg_start / (fg_start - g_end)
                            if th < th_ev:
                                th_ev = th
                                ev = kk
                    else:
                        dr = fr_state[kk, FS_DIR]
                        fg_start = dr * v[b]
                        g_end = dr * v1[b]
                        if g_end < 0.0:
                            th = first_drop(max(fg_start, 0.0), dr * a[b], g_end, dr * a1[b], hs)
                            if th < th_ev:
                                th_ev = th
                                ev = kk
                if ev >= 0:
                    counters[CNT_FRICTION] += 1
                    b = fr_dof[ev]
                    stuck_ev = fr_state[ev, FS_STUCK] != 0.0
                    sg = 1.0 if fr_p[ev] > 0.0 else -1.0
                    if stuck_ev:
                        g_lo = fr_params[ev, 0] * fr_normal[ev] - sg * fr_state[ev, FS_F0]
                        g_tol = FRICTION_FORCE_TOL * fr_params[ev, 0] * fr_normal[ev]
                        g_hi = _friction_gap(
                            ev, b, fr_state, fr_params, fr_normal, v1, fr_p[ev], sg
                        )
                    else:
                        g_lo = max(fr_state[ev, FS_DIR] * v[b], 0.0)
                        g_tol = FRICTION_SPEED_TOL * (abs(v[b]) + abs(a[b]) * hs) + 1e-300
                        g_hi = fr_state[ev, FS_DIR] * v1[b]
                    lo = 0.0
                    hi = hs
                    x = min(max(th_ev, 1e-6), 1.0 - 1e-6) * hs
                    side = 0
                    for it_loc in range(61):
                        if it_loc == 60:
                            x = hi  # not converged: end just past the event (g <= 0 there)
                        ok, its = _newton(x, t, u, v, a, f0, M, C, K, Mi, ag, ag_dt, gamma, beta,
                                          alpha, el_dof, el_sign, el_gap, el_law, el_params, el_in,
                                          el_v0, el_hd, el_hf, open_off, fr_dof, fr_kind, fr_law,
                                          fr_params, fr_bw, fr_normal, fr_state, tol, max_iter,
                                          J_inv, L_h, D_h, h, Mb, Cb, Kb, bw, dense, work, Z, S, u1, v1, a1, d1, dd1, f1, kd1, cd1,
                                          R, J)  # fmt: skip
                        counters[CNT_NEWTON] += its
                        if not ok:
                            break
                        g1 = ground_at(ag, ag_dt, t + x)
                        p1 = _stick_force(b, g1, Mi, C, K, u1, v1, el_dof, el_sign, f1, n_el)
                        fr_p[ev] = p1
                        gx = _friction_gap(ev, b, fr_state, fr_params, fr_normal, v1, p1, sg)
                        if abs(gx) <= g_tol or (hi - lo <= 1e-13 * h and gx <= 0.0) or it_loc == 60:
                            break
                        if gx > 0.0:
                            lo = x
                            g_lo = gx
                            if side == 1:
                                g_hi *= 0.5
                            side = 1
                        else:
                            hi = x
                            g_hi = gx
                            if side == -1:
                                g_lo *= 0.5
                            side = -1
                        x = hi - g_hi * (hi - lo) / (g_hi - g_lo)
                        if not (lo < x < hi) or hi - lo <= 1e-13 * h:
                            x = hi if hi - lo <= 1e-13 * h else 0.5 * (lo + hi)
                    if not ok:
                        halvings += 1
                        counters[CNT_HALVINGS] += 1
                        if halvings > max_halvings:
                            counters[CNT_STATUS] = STATUS_NO_CONVERGENCE
                            return t
                        scale *= 0.5
                        continue
                    hs = x
                    t1 = t + hs
                    fr_event[ev] = True
                    for c in range(n_el):
                        # a closure or separation the shortened step no longer reaches comes later
                        if closing[c] and d1[c] < -d_tol:
                            closing[c] = False
                        if separating[c] and d1[c] > d_tol:
                            separating[c] = False
                # transitions at the step end: the located event and any other slab at its own
                for kk in range(n_fr):
                    if fr_kind[kk] != FRICTION_COULOMB:
                        continue
                    b = fr_dof[kk]
                    if fr_state[kk, FS_STUCK] != 0.0:
                        p1 = _stick_force(b, g1, Mi, C, K, u1, v1, el_dof, el_sign, f1, n_el)
                        fr_state[kk, FS_F1] = p1
                        lim = fr_params[kk, 0] * fr_normal[kk]
                        if fr_event[kk] or abs(p1) > lim:
                            fr_state[kk, FS_STUCK] = 0.0
                            fr_state[kk, FS_DIR] = 1.0 if p1 > 0.0 else -1.0
                            fr_state[kk, FS_F1] = (
                                fr_state[kk, FS_DIR] * fr_params[kk, 1] * fr_normal[kk]
                            )
                            fr_restart = True
                    else:
                        dr = fr_state[kk, FS_DIR]
                        tol_v = FRICTION_SPEED_TOL * (abs(v[b]) + abs(a[b]) * hs) + 1e-300
                        if (
                            fr_event[kk]
                            or dr * v1[b] < 0.0
                            or (dr * v[b] > 0.0 and dr * v1[b] <= tol_v)
                        ):
                            # the slab stops: it sticks if the stick test passes (in _equilibrium)
                            v1[b] = 0.0
                            fr_state[kk, FS_STUCK] = 1.0
                            fr_restart = True
                if fr_restart:
                    _equilibrium(g1, u1, v1, a1, M_inv, Mi, C, K, el_dof, el_sign, f1, n_el,
                                 fr_dof, fr_kind, fr_params, fr_normal, fr_state, R)  # fmt: skip
            counters[CNT_SUBSTEPS] += 1
            # energy: work of the step-averaged forces on the step's displacement increment
            g_avg = 0.5 * (g_start + g1)
            for i in range(n):
                du[i] = u1[i] - u[i]
                vs[i] = v[i] + v1[i]
                e_in -= du[i] * Mi[i] * g_avg
            e_damp += 0.5 * _band_bilinear(CbT, bw, du, vs)
            for c in range(n_el):
                w_c += 0.5 * (f0[c] + f1[c]) * (d1[c] - d0[c])
            for kk in range(n_fr):
                b = fr_dof[kk]
                e_fr += 0.5 * (fr_state[kk, FS_F0] + fr_state[kk, FS_F1]) * (u1[b] - u[b])
            if algorithmic:
                # ΔE_alg = −Δuᵀ r̄ + h²(β − γ/2) Δaᵀ M ā − h(γ − ½) v̄ᵀ M Δa
                _residual(Mb, Cb, Kb, bw, Mi, g1, u1, v1, a1, el_dof, el_sign, f1, n_el,
                          fr_state, r1)  # fmt: skip
                e_alg_step = 0.0
                for i in range(n):
                    e_alg_step -= 0.5 * du[i] * (r0[i] + r1[i])
                    du[i] = a1[i] - a[i]  # Δa from here on
                    vs[i] = a[i] + a1[i]
                e_alg_step += 0.5 * hs * hs * (beta - 0.5 * gamma) * _band_bilinear(MbT, bw, du, vs)
                for i in range(n):
                    vs[i] = v[i] + v1[i]
                e_alg_step -= 0.5 * hs * (gamma - 0.5) * _band_bilinear(MbT, bw, vs, du)
                e_alg += e_alg_step
                for i in range(n):
                    r0[i] = r1[i]
            # impacts: onsets, running maxima, separations
            onset = False
            for c in range(n_el):
                # a gap that would close within EVENT_FRACTION of a step closes now: locating it
                # would take a step so short that its acceleration is lost to round-off
                soon = dd1[c] > 0.0 and d_tol - d1[c] < EVENT_FRACTION * hs * dd1[c]
                if not el_in[c] and (closing[c] or d1[c] > d_tol or soon):
                    if closing[c] or soon:
                        # the step was shortened to end at this closure (or ends just before it)
                        vc = dd1[c]
                        t_on = t1 + max(-d1[c], 0.0) / vc
                    else:
                        th, vc = hermite_root(d0[c], dd0[c], d1[c], dd1[c], hs)
                        t_on = t + th * hs
                    onset = True
                    el_in[c] = True
                    # a v0-scaled law sees at least v0_floor (integrators.base.V0_FRACTION)
                    el_v0[c] = max(vc, v0_floor)
                    el_hd[c] = 0.0
                    el_hf[c] = 0.0
                    i_imp = counters[CNT_IMPACTS]
                    if i_imp >= cap:
                        counters[CNT_STATUS] = STATUS_IMPACT_LOG_FULL
                        return t
                    counters[CNT_IMPACTS] += 1
                    el_imp[c] = i_imp
                    imp_el[i_imp] = c
                    imp_val[i_imp, IMP_START] = t_on
                    imp_val[i_imp, IMP_END] = np.nan
                    imp_val[i_imp, IMP_V0] = max(vc, 0.0)
                    imp_val[i_imp, IMP_VEND] = np.nan
                    imp_val[i_imp, IMP_FMAX] = 0.0
                    imp_val[i_imp, IMP_DMAX] = 0.0
                    imp_val[i_imp, IMP_IMPULSE] = 0.0
                    path_start(imp_val[i_imp])
                if el_in[c]:
                    i_imp = el_imp[c]
                    imp_val[i_imp, IMP_FMAX] = max(imp_val[i_imp, IMP_FMAX], f1[c])
                    imp_val[i_imp, IMP_DMAX] = max(imp_val[i_imp, IMP_DMAX], d1[c])
                    imp_val[i_imp, IMP_IMPULSE] += 0.5 * hs * (f0[c] + f1[c])
                    # separation (located: the step ends there); a grazing closure that never
                    # penetrated ends once it recedes
                    soon = dd1[c] < 0.0 and d1[c] < -EVENT_FRACTION * hs * dd1[c]
                    ends = (
                        separating[c]
                        or soon
                        or (d1[c] <= 0.0 and (imp_val[i_imp, IMP_DMAX] > 0.0 or dd1[c] < 0.0))
                    )
                    path_add(imp_val[i_imp], max(d1[c], 0.0), f1[c], ends)
                    if ends:
                        if separating[c] or (soon and d1[c] > 0.0):
                            vc = dd1[c]
                            imp_val[i_imp, IMP_END] = t1 + max(d1[c], 0.0) / -vc
                        elif d0[c] > 0.0:
                            th, vc = hermite_root(d0[c], dd0[c], d1[c], dd1[c], hs)
                            imp_val[i_imp, IMP_END] = t + th * hs
                        else:
                            vc = dd1[c]
                            imp_val[i_imp, IMP_END] = t1
                        imp_val[i_imp, IMP_VEND] = vc
                        el_in[c] = False
                        el_imp[c] = -1
                        el_hd[c] = 0.0
                        el_hf[c] = 0.0
                    else:
                        el_hd[c] = d1[c]
                        el_hf[c] = f1[c]
            if grade > 0:
                grade -= 1
            if onset and adaptive:
                # the force of some laws grows like a fractional power of time after the onset
                # (Jankowski: c ∝ δ^(1/4)); steps graded geometrically up to h_contact resolve it
                grade = GRADED_STEPS
            if adaptive:
                h_contact = h
                for c in range(n_el):
                    if el_in[c]:
                        tc = el_tc_coef[c] * max(el_v0[c], 1e-3) ** el_tc_exp[c]
                        h_contact = min(h_contact, tc / steps_per_contact)
                # the separation mirrors the onset: steps halve the time left to it (linear
                # estimate) down to the first graded step, so the trapezoidal work of a stiffening
                # law errs alike going in and coming out instead of only coming out
                h_sep = np.inf
                for c in range(n_el):
                    if el_in[c] and dd1[c] < 0.0 and d1[c] > 0.0:
                        t_sep = d1[c] / -dd1[c]
                        if t_sep < 2.0 * h_contact:
                            h_sep = min(h_sep, max(0.5 * t_sep, h_contact * 0.5**GRADED_STEPS))
            if onset or hs < SHORT_STEP * h:
                if onset:
                    # a law whose force jumps at δ = 0⁺ (c v0) changes the acceleration at the
                    # onset: restart the next step from equilibrium with that force
                    _eval_contacts(u1, v1, el_dof, el_sign, el_gap, el_law, el_params, el_in,
                                   el_v0, el_hd, el_hf, none_off, d1, dd1, f1, kd1, cd1)  # fmt: skip
                # after a short step (a located event) too: a1 = c0 (u1 − u) − … turns the
                # round-off of u1 into an error 4 ε |u| / hs² that the next step would integrate
                # a stuck slab hit by a jumping contact force may break away at once
                _equilibrium(g1, u1, v1, a1, M_inv, Mi, C, K, el_dof, el_sign, f1, n_el,
                             fr_dof, fr_kind, fr_params, fr_normal, fr_state, R)  # fmt: skip
                if algorithmic:
                    _residual(Mb, Cb, Kb, bw, Mi, g1, u1, v1, a1, el_dof, el_sign, f1, n_el,
                              fr_state, r0)  # fmt: skip
            # accept
            for i in range(n):
                u[i] = u1[i]
                v[i] = v1[i]
                a[i] = a1[i]
                au = abs(u1[i])
                if au > peak_u[i]:
                    peak_u[i] = au
                dr = abs(u1[i] - (u1[below[i]] if below[i] >= 0 else 0.0))
                if dr > peak_drift[i]:
                    peak_drift[i] = dr
                aa = abs(a1[i] + iota[i] * g1)
                if aa > peak_aabs[i]:
                    peak_aabs[i] = aa
            for c in range(n_el):
                d0[c] = d1[c]
                dd0[c] = dd1[c]
                f0[c] = f1[c]
                if f1[c] > peak_f[c]:
                    peak_f[c] = f1[c]
                if d1[c] > peak_d[c]:
                    peak_d[c] = d1[c]
            for kk in range(n_fr):
                fr_state[kk, FS_F0] = fr_state[kk, FS_F1]
                fr_state[kk, FS_Z0] = fr_state[kk, FS_Z1]
            t = t1
            g_start = g1
        if (k + 1) % out_every == 0:
            _store((k + 1) // out_every, t_next, u, v, a, ag, ag_dt, d0, f0, e_in, e_damp, w_c, e_fr,
                   e_alg, MbT, KbT, bw, el_law, el_params, fr_state, out_u, out_v, out_a, out_ag, out_d, out_f,
                   out_e, out_ff, out_st)  # fmt: skip
    return t


@jit
def _store(row, t, u, v, a, ag, ag_dt, d, f, e_in, e_damp, w_c, e_fr, e_alg, MbT, KbT, bw, el_law, el_params,
           fr_state, out_u, out_v, out_a, out_ag, out_d, out_f, out_e, out_ff, out_st):  # fmt: skip
    if row >= out_u.shape[0]:
        return
    # element loops, not row slices: a slice assignment compiles numba's broadcasting checks
    for i in range(u.size):
        out_u[row, i] = u[i]
        out_v[row, i] = v[i]
        out_a[row, i] = a[i]
    out_ag[row] = ground_at(ag, ag_dt, t)
    for c in range(d.size):
        out_d[row, c] = d[c]
        out_f[row, c] = f[c]
    for k in range(fr_state.shape[0]):
        out_ff[row, k] = fr_state[k, FS_F0]
        out_st[row, k] = fr_state[k, FS_STUCK]
    stored = 0.0
    for c in range(d.size):
        stored += contact_stored_energy(el_law[c], d[c], f[c], el_params[c])
    out_e[row, 0] = e_in
    out_e[row, 1] = 0.5 * _band_quadratic(MbT, bw, v)
    out_e[row, 2] = 0.5 * _band_quadratic(KbT, bw, u)
    out_e[row, 3] = e_damp
    out_e[row, 4] = w_c - stored
    out_e[row, 5] = stored
    out_e[row, 6] = e_fr
    out_e[row, 7] = e_alg
