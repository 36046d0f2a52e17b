"""The step kinds of the compiled Newmark/HHT core, on the named groups of :mod:`._layout`:

- the linear step (no element force changes): band solve or, for small systems, a dense map;
- the linear step with Coulomb slabs (sliding: known force; stuck: constraint reactions);
- the contact step condensed onto the gaps (Newton on the gap openings alone);
- the full Newton step over every element family (Woodbury update of the known tangent);
- the residual of the equation of motion, the stick force of a slab and the equilibrium restart.
"""

from __future__ import annotations

import math

import numpy as np

from pounding._numba import jit, jit_inline, jit_internal, jit_kernel, jit_setup
from pounding.integrators._coefficients import (
    end_of_step,
    newmark_coefficients,
    tangent_band,
    tangent_band_into,
    tangent_dense,
)
from pounding.integrators._dispatch import story_straight
from pounding.integrators._events import ground_at
from pounding.integrators._families import (
    add_forces,
    add_friction,
    add_row_tangent,
    band_rows_into,
    eval_element,
    eval_elements,
    eval_elements_here,
    eval_friction,
    eval_gaps,
    gap_force,
    gap_openings,
    gather,
    in_band,
    row_stiffness,
)
from pounding.integrators._layout import FS_DIR, FS_F0, FS_F1, FS_STUCK, Slopes
from pounding.integrators._linalg import (
    _band_inverse,
    _band_matvec_add,
    _dense_matvec_add,
    _gauss_solve,
    _mv,
    _solve_small,
    _woodbury_solve,
    band_ldl,
    band_ldl_into,
    band_solve,
    bandwidth,
    inverse_column,
    to_band,
    unit_column,
    woodbury_band_solve,
)
from pounding.stories import SS_KT
from pounding.system import FRICTION_COULOMB


@jit
def dense_map(h, M, C, K, Mi, sch):
    """Qᵀ (3n × n) and p (n) with u1 = Q [u; v; a] + p g_eff: one Newmark/HHT step of the linear
    system, for small systems (see :func:`linear_step`). Stored transposed: the step sums it column
    by column, a loop over the rows of u1 that vectorises (a row's dot product does not, its sum
    being a chain)."""
    n = M.shape[0]
    bw = bandwidth(M, C, K)
    L, D = band_ldl(tangent_band(h, to_band(M, bw), to_band(C, bw), to_band(K, bw), sch), bw)
    J_inv = np.empty((n, n))
    _band_inverse(L, D, bw, J_inv)
    cf = newmark_coefficients(h, sch)
    w = cf.w
    alpha = cf.alpha
    Q = np.zeros((3 * n, n))
    pg = np.zeros(n)
    for i in range(n):
        for k in range(n):
            jik = J_inv[i, k]
            pg[i] -= jik * Mi[k]
            for j in range(n):
                Q[j, i] += jik * (cf.c0 * M[k, j] + w * cf.c1 * C[k, j] + alpha * K[k, j])
                Q[n + j, i] += jik * (cf.c2 * M[k, j] + (w * cf.c4 + alpha) * C[k, j])
                Q[2 * n + j, i] += jik * (cf.c3 * M[k, j] + w * cf.c5 * C[k, j])
    return Q, pg


@jit_kernel
def dense_step(Q, pg, g_eff, cf, x0, x1):
    """Apply the dense map Qᵀ (explicit loops: no allocation, no BLAS call overhead); x1 = the end's
    (u1, v1, a1). Each u1_i sums its terms in the order of a row's dot product (the same digits),
    the columns taken in turn so that the rows go in vector lanes."""
    u, v, a = x0
    u1, v1, a1 = x1
    n = u.size
    for i in range(n):
        u1[i] = pg[i] * g_eff
    for j in range(n):
        uj = u[j]
        vj = v[j]
        aj = a[j]
        for i in range(n):
            u1[i] += Q[j, i] * uj + Q[n + j, i] * vj + Q[2 * n + j, i] * aj
    end_of_step(cf, u, v, a, u1, v1, a1)


@jit_inline
def linear_step(md, fac, g_eff, cf, x0, tr, lin):
    """:func:`linear_step_on` the arrays it needs of the model, factor and trial groups: a call
    copies every word of every group it is given (~0.15 µs a step for these three). A small
    system's dense map is called from here: through ``linear_step_on`` its ~150 words of arguments
    were 40 % of the contact-free loop (``benchmarks/profile_lines.py --gaps-open``)."""
    if fac.Q.shape[1] == tr.u1.size:
        dense_step(fac.Q, fac.pg, g_eff, cf, x0, (tr.u1, tr.v1, tr.a1))
        return
    linear_step_on(md.Mi, md.Mb, md.Cb, md.Kb, md.bw, fac.L, fac.D, g_eff, cf, x0,
                   (tr.u1, tr.v1, tr.a1), lin)  # fmt: skip


@jit_internal
def linear_step_on(Mi, Mb, Cb, Kb, bw, L, D, g_eff, cf, x0, x1, lin):
    """One Newmark/HHT step of the linear system (no change of element force), for the increment:

    J Δu = M(c2 v + c3 a) + C((w c4 + α) v + w c5 a) − K u − M ι g_eff,  J = c0 M + w(c1 C + K),

    from the weighted equation M a1 + w(C v1 + K u1) − α(C v + K u) = −M ι g_eff (w = 1 + α) and the
    Newmark relations; x1 = the end's (u1, v1, a1). Band products (Mi = M ι, band rows Mb, Cb, Kb
    of width bw) and the band factors (L, D) of J: O(n bw) per step, and the increment keeps its
    digits at small steps (small systems take the dense map, :func:`linear_step`)."""
    u, v, a = x0
    u1, v1, a1 = x1
    n = u.size
    p, q, rhs, du = lin
    for i in range(n):
        p[i] = cf.c2 * v[i] + cf.c3 * a[i]
        q[i] = (cf.w * cf.c4 + cf.alpha) * v[i] + cf.w * cf.c5 * a[i]
    for i in range(n):
        acc = -Mi[i] * g_eff
        for k in range(max(0, bw - i), min(2 * bw + 1, n - i + bw)):
            j = i - bw + k
            acc += Mb[i, k] * p[j] + Cb[i, k] * q[j] - Kb[i, k] * u[j]
        rhs[i] = acc
    band_solve(L, D, bw, rhs, du)
    for i in range(n):
        u1[i] = u[i] + du[i]
        a1[i] = cf.c0 * du[i] - cf.c2 * v[i] - cf.c3 * a[i]
        v1[i] = cf.c1 * du[i] - cf.c4 * v[i] - cf.c5 * a[i]


#: A correction this small relative to the displacements is their round-off (a few ε).
ROUND_OFF = 4.0 * np.finfo(np.float64).eps


@jit_inline
def settle_elements(bw, J_inv, L, D, cf, h, el, tr, lin, f_prev, tol, max_iter):
    """Complete the linear step with the element families' forces, found by fixed-point passes
    on the factors of J = c0 M + w(c1 C + K), which hold no element tangent. Returns False when
    they do not settle: Newton takes the step.

    The weighted equation gains −Bᵀ(w F1 − α f0). The first pass takes F1 along each element's
    last tangent from where the linear step took it, F1 ≈ f0 + kd (δ − δ0) (the load
    −Bᵀ(f0 + w kd (δ − δ0)), as w − α = 1); each further pass adds −w J⁻¹Bᵀ(F1 − F1_before) at
    the forces just evaluated. A pass contracts by about w |∂F/∂δ|/(c0 m + k), at most
    (ω h)²/(4 + (ω h)²) for a mode of frequency ω: ~1e-6 at an analysis' base step, so a story on a linear branch (elastic, hardening, Takeda's
    unloading, IMK's capping) or a smooth one (Bouc–Wen) is settled at its first evaluation in
    most steps: no tangent, no factorisation, no residual. As Newton, a pass that moves the state
    by ≤ ``tol`` of the displacements is the last (its state evaluated and taken); one within the
    round-off of u is not even taken. A pass that does not shrink tenfold means the step is too
    long for this: False."""
    if el is None:
        return True
    _, _, rhs, du = lin
    n = tr.u1.size
    w = cf.w
    loaded = False
    u_max = 1e-3
    for i in range(n):
        rhs[i] = 0.0
        u_max = max(u_max, abs(tr.u1[i]))
    for e in range(el.kind.size):
        df = 0.0
        if el.kd[e] != 0.0:  # on an elastic branch F − k δ stays f0
            d, _ = gather(el.dof, el.sign, e, tr.u1, tr.v1)
            df = el.kd[e] * (d - el.d0[e])
        f_prev[e] = el.f0[e] + df
        loaded = _load(el, e, el.f0[e] + w * df, rhs) or loaded
    last = np.inf
    final = False
    for it in range(max_iter + 1):
        if loaded:
            if J_inv.shape[0] == n:
                # the inverse of a small system's J: n² independent products, not a chain of
                # 2n dependent substitutions
                for i in range(n):
                    du[i] = 0.0
                _dense_matvec_add(J_inv, rhs, 1.0, du)
            else:
                band_solve(L, D, bw, rhs, du)
            big = 0.0
            for i in range(n):
                big = max(big, abs(du[i]))
            if it > 0:
                if big <= ROUND_OFF * u_max:
                    return True  # the state evaluated stands, to the round-off of u
                if big > 0.1 * last:
                    return False
                last = big
                final = big <= tol * u_max
            for i in range(n):
                tr.u1[i] += du[i]
                tr.a1[i] += cf.c0 * du[i]
                tr.v1[i] += cf.c1 * du[i]
                u_max = max(u_max, abs(tr.u1[i]))
        elif it > 0:
            return True  # the forces evaluated are the forces assumed
        if it == max_iter:
            break
        eval_elements_here(tr.u1, tr.v1, h, el)
        if final:
            return True  # as Newton: a correction within tol, then the state it gives
        loaded = False
        for i in range(n):
            rhs[i] = 0.0
        for e in range(el.kind.size):
            df = el.f1[e] - f_prev[e]
            # F − k δ of a story on its elastic branch, assumed constant, changes by round-off
            if abs(df) <= ROUND_OFF * (abs(el.trial[e, 0]) + abs(el.f1[e])):
                df = 0.0
            f_prev[e] = el.f1[e]
            loaded = _load(el, e, w * df, rhs) or loaded
    return False


#: Rank-one updates of the stories' condensation and straight map before both are rebuilt from
#: kd = 0, which drops the updates' round-off.
SLOPE_REFRESH = 64


@jit_inline
def straight_step(sl, g_eff, cf, x0, el, tr):
    """The step of a building whose every story goes straight on (the increment short of each
    story's next turning point, :func:`pounding.stories.story_straight`): each story force is then
    affine in its drift, g = c + kd δ (g = F − k δ, kd = k_t − k, c constant on the branch), and
    the weighted equation is that of a linear system with K + Bᵀ diag(kd) B and the load −Bᵀ c.
    Its dense map (:func:`straight_map`, updated when a kernel commits) takes the step in one
    product, as the elastic step: no passes, exact to round-off. False when it does not apply (a
    story turned inside the step, the map is unavailable or singular): the caller takes the
    linear step and the passes."""
    if el is None:
        return False
    n_el = el.kind.size
    if n_el == 0 or sl.Z.shape[0] != n_el:
        return False
    if sl.count[1] != 0:  # a kernel committed since the map was built
        if not straight_map(sl, el, cf.w, cf.alpha):
            return False
    dense_step(sl.Q, sl.pg, g_eff, cf, x0, (tr.u1, tr.v1, tr.a1))
    for i in range(tr.u1.size):  # the constant load's part (v1, a1 are linear in u1)
        tr.u1[i] += sl.p0[i]
        tr.a1[i] += cf.c0 * sl.p0[i]
        tr.v1[i] += cf.c1 * sl.p0[i]
    # the straight increments alone (the kernels' dispatch is not compiled into the loop again)
    for e in range(n_el):
        d, dd = gather(el.dof, el.sign, e, tr.u1, tr.v1)
        if el.written[e]:
            return False  # a kernel wrote its row before
        straight, f, kd = story_straight(d, el.state, el.trial, el.params, e)
        if not straight:
            # the story may turn here (a reversal, a corner): its kernel, and the step stands if
            # the force is on the line the map took (a reversal on that line, a corner of
            # another branch)
            f, kd = eval_element(el, e, d, dd, 0.0)  # (no straight model reads the step length)
            if not on_line(f, kd, el.f0[e], el.d0[e], sl.kd[e], d, el.params[e, 0]):
                return False
        # (a story's drift rate and damping tangent: unread, and 0 from every story kernel)
        el.d1[e] = d
        el.f1[e] = f
        el.kd[e] = kd
    return True


@jit_inline
def on_line(f, kd, f0, d0, kd_map, d, k):
    """True when a story's kernel gave, at drift d [m], the force g = F − k δ [N] and slope kd
    [N/m] of the line the straight map took from its committed (d0, f0): g = f0 + kd_map (d − d0),
    to 1e-12 of the story's force and stiffness k."""
    line = f0 + kd_map * (d - d0)
    return abs(kd - kd_map) <= 1e-12 * k and abs(f - line) <= 1e-12 * (abs(f) + k * abs(d))


@jit_internal
def straight_map(sl, el, w, alpha):
    """Bring the dense map of a step in which every story goes straight on (Q, pg, p0: u1 = Qᵀx +
    pg g + p0, x = [u; v; a]) to the stories' committed branches, g = c + kd δ on each: the
    system with K + Bᵀ diag(kd) B and the constant load −Bᵀ c. The slopes enter by rank one
    (:func:`slopes_update`); the constant load is p0 = −Zᵀ c, n_el × n products. False when a
    tangent is singular along a story."""
    if not slopes_update(sl, el, w, alpha):
        return False
    sl.count[1] = 0
    n = sl.Z.shape[1]
    for i in range(n):
        sl.p0[i] = 0.0
    for e in range(el.kind.size):
        c = el.f0[e] - sl.kd[e] * el.d0[e]
        if c != 0.0:
            for i in range(n):
                sl.p0[i] -= sl.Z[e, i] * c
    return True


@jit_internal
def slopes_update(sl, el, w, alpha):
    """Bring the stories' condensation ``sl`` and the straight map (Q, pg) to each story's slope
    ahead, kd = k_t − k, by rank-one (Sherman–Morrison) updates. For a change Δ of story e's kd,
    the tangent J_s = J + w Bᵀ diag(kd) B gains w Δ b bᵀ and the load α Δ b bᵀu, so with
    z = J_s⁻¹ b = Z[e] (before), s = S[e] and c = w Δ/(1 + w Δ S[e, e]):

    Z ← Z − c s ⊗ Z[e],  S ← S − c s ⊗ s,
    Qᵀ ← Qᵀ − c z (b Qᵀ) + (α Δ/(1 + w Δ S[e, e])) z bᵀ[I 0 0],  pg ← pg − c z (b·pg):

    n × 3n products per story that turned, where building the map anew costs that per story off
    its elastic slope. Rebuilt from kd = 0 (Z0, S0 and the linear map Q0, pg0) every
    SLOPE_REFRESH updates. False when a tangent is singular along a story
    (|1 + w Δ S[e, e]| < 1e-9): the passes, then Newton, take such steps."""
    n_el = el.kind.size
    n = sl.Z.shape[1]
    if sl.count[0] >= SLOPE_REFRESH:  # the updates' round-off, dropped
        for e in range(n_el):
            sl.kd[e] = 0.0
            for i in range(n):
                sl.Z[e, i] = sl.Z0[e, i]
            for f in range(n_el):
                sl.S[e, f] = sl.S0[e, f]
        for j in range(sl.Q.shape[0]):
            for i in range(n):
                sl.Q[j, i] = sl.Q0[j, i]
        for i in range(n):
            sl.pg[i] = sl.pg0[i]
        sl.count[0] = 0
    s = sl.s
    for e in range(n_el):
        kd = el.state[e, SS_KT] - el.params[e, 0]
        delta = w * (kd - sl.kd[e])
        if delta == 0.0:
            continue
        den = 1.0 + delta * sl.S[e, e]
        if abs(den) < 1e-9:
            sl.count[0] = SLOPE_REFRESH  # rebuilt from kd = 0 at the next call
            return False
        c = delta / den
        for j in range(sl.Q.shape[0]):
            bq, _ = gather(el.dof, el.sign, e, sl.Q[j], sl.Q[j])
            if bq != 0.0:
                for i in range(n):
                    sl.Q[j, i] -= c * bq * sl.Z[e, i]
        bq, _ = gather(el.dof, el.sign, e, sl.pg, sl.pg)
        for i in range(n):
            sl.pg[i] -= c * bq * sl.Z[e, i]
        t = alpha * (kd - sl.kd[e]) / den
        for r in range(el.dof.shape[1]):
            j = el.dof[e, r]
            if j >= 0:
                for i in range(n):
                    sl.Q[j, i] += t * el.sign[e, r] * sl.Z[e, i]
        for f in range(n_el):
            s[f] = sl.S[e, f]
        for f in range(n_el):
            if f != e and s[f] != 0.0:
                for i in range(n):
                    sl.Z[f, i] -= c * s[f] * sl.Z[e, i]
        for i in range(n):
            sl.Z[e, i] -= c * s[e] * sl.Z[e, i]
        for f in range(n_el):
            for g in range(n_el):
                sl.S[f, g] -= c * s[f] * s[g]
        sl.kd[e] = kd
        sl.count[0] += 1
    return True


@jit_setup
def slopes_prepare(J_inv, Q, pg, el, straight):
    """The stories' condensation on J⁻¹ at kd = 0 and the map of their straight steps (see
    :func:`straight_step`) from the linear system's dense map (Qᵀ, p); empty unless ``straight``
    (every element a story with straight branches) and J⁻¹ is at hand."""
    n_el = 0 if el is None else el.kind.size
    m = n_el if straight and J_inv.shape[0] > 0 else 0
    n = J_inv.shape[0] if m > 0 else 0
    Z0 = np.zeros((m, n))
    S0 = np.zeros((m, m))
    if el is not None and m > 0:
        # the stories' rows condensed as the gaps' are
        condense_map(J_inv, el.dof, el.sign, Z0, S0, np.zeros((m, 3), dtype=np.int64))
    Q0 = Q[: 3 * n, :n].copy()
    pg0 = pg[:n].copy()
    return Slopes(Z0.copy(), S0.copy(), Z0, S0, np.zeros(m), np.array([0, 1]), np.zeros(m),
                  Q0.copy(), pg0.copy(), np.zeros(n), Q0, pg0)  # fmt: skip


@jit_inline
def _load(el, e, f, rhs):
    """rhs −= b_e f for element e; True when f ≠ 0."""
    if f == 0.0:
        return False
    for s in range(el.dof.shape[1]):
        i = el.dof[e, s]
        if i >= 0:
            rhs[i] -= el.sign[e, s] * f
    return True


@jit_internal
def linear_step_coulomb(md, fac, g_eff, cf, x0, fr, tr, wk):
    """The linear step with Coulomb slabs: sliding ones load their base with the known force
    w f1 − α f0 (f = ±μ_d N), stuck ones hold u_b by reactions λ solved from J⁻¹ restricted to the
    stuck bases (the constrained step, no Newton)."""
    u, v, a = x0
    u1 = tr.u1
    n = u.size
    J_inv = fac.J_inv
    st = fr.state
    linear_step(md, fac, g_eff, cf, x0, tr, wk.lin)
    m = 0
    for k in range(fr.dof.size):
        b = fr.dof[k]
        if st[k, FS_STUCK] != 0.0:
            m += 1
            continue
        f1 = st[k, FS_DIR] * fr.params[k, 1] * fr.normal[k]
        st[k, FS_F1] = f1
        phi = cf.w * f1 - cf.alpha * st[k, FS_F0]
        for i in range(n):
            u1[i] -= J_inv[i, b] * phi
    if m > 0:
        S = wk.S
        rhs_col = S.shape[1] - 1
        r = 0
        for k in range(fr.dof.size):
            if st[k, FS_STUCK] == 0.0:
                continue
            q = 0
            for k2 in range(fr.dof.size):
                if st[k2, FS_STUCK] != 0.0:
                    S[r, q] = J_inv[fr.dof[k], fr.dof[k2]]
                    q += 1
            S[r, rhs_col] = u1[fr.dof[k]] - u[fr.dof[k]]
            r += 1
        _solve_small(S, m)
        q = 0
        for k in range(fr.dof.size):
            if st[k, FS_STUCK] == 0.0:
                continue
            lam = S[q, rhs_col]
            for i in range(n):
                u1[i] -= J_inv[i, fr.dof[k]] * lam
            q += 1
        for k in range(fr.dof.size):
            if st[k, FS_STUCK] != 0.0:
                u1[fr.dof[k]] = u[fr.dof[k]]
    end_of_step(cf, u, v, a, u1, tr.v1, tr.a1)


@jit_kernel
def condense_map(J_inv, dof, sign, Z, S, have):
    """Z = (J⁻¹ B)ᵀ (C × n: row c is J⁻¹ b_c) and S = Bᵀ J⁻¹ B (C × C, symmetric: row c is column
    c), B the gap elements' sign columns: how contact forces move every dof and every gap through
    one step of the linear system (in place). Every row solved, over all n dofs (``have``, as
    :func:`condensed_column` keeps it)."""
    n_el = Z.shape[0]
    n = Z.shape[1]
    for c in range(n_el):
        inverse_column(J_inv, dof, sign, c, Z[c])
        have[c, 0] = 1
        have[c, 1] = 0
        have[c, 2] = n
        for s in range(3, have.shape[1]):
            have[c, s] = 0
    for c in range(n_el):
        condensed_row(dof, sign, Z, S, c)


@jit_internal
def condensed_row(dof, sign, Z, S, q):
    """S[q] = Bᵀ Z[q]: how gap q's force opens every gap."""
    for r in range(dof.shape[0]):
        acc = 0.0
        for s in range(dof.shape[1]):
            k = dof[r, s]
            if k >= 0:
                acc += sign[r, s] * Z[q, k]
        S[q, r] = acc


@jit_internal
def condensed_column(fac, gaps, q, e):
    """Z[q] = J⁻¹ b_q and S[q] = Bᵀ Z[q] of gap q for the factor ``fac``, solved the first time the
    condensed step needs them under it: one :func:`unit_column` per dof of the gap (a few floors
    of each building, where J⁻¹ is not negligible), then O(C) for S. ``e`` is zero on entry and on
    return.

    ``fac.have[q, 0]`` is 1 once solved; ``fac.have[q, 1 + 2p]``, ``fac.have[q, 2 + 2p]`` the p-th
    range of rows (first, one past the last) outside which Z[q] is zero. (Kept in ``have`` rather
    than an eleventh field of Factor: that field alone made numba's code for the time loop 2.6 times
    slower on a small system.)"""
    have = fac.have
    if have[q, 0]:
        return
    Z = fac.Z
    for p in range((have.shape[1] - 1) // 2):  # the rows a previous factor wrote
        for i in range(have[q, 1 + 2 * p], have[q, 2 + 2 * p]):
            Z[q, i] = 0.0
        have[q, 1 + 2 * p] = 0
        have[q, 2 + 2 * p] = 0
    bw = fac.L.shape[1] - 1
    p = 0
    for s in range(gaps.dof.shape[1]):
        k = gaps.dof[q, s]
        if k < 0:
            continue
        lo, hi = unit_column(fac.L, fac.D, bw, k, fac.blk[0, k], fac.blk[1, k], e)
        sg = gaps.sign[q, s]
        for i in range(lo, hi):
            Z[q, i] += sg * e[i]
            e[i] = 0.0
        have[q, 1 + 2 * p] = lo
        have[q, 2 + 2 * p] = hi
        p += 1
    # overlapping ranges (two dofs of one building) merged, so each row is read once
    merged = True
    while merged:
        merged = False
        for a in range(p):
            for b in range(a + 1, p):
                a0, a1, b0, b1 = 1 + 2 * a, 2 + 2 * a, 1 + 2 * b, 2 + 2 * b
                if have[q, b0] < have[q, a1] and have[q, a0] < have[q, b1]:
                    have[q, a0] = min(have[q, a0], have[q, b0])
                    have[q, a1] = max(have[q, a1], have[q, b1])
                    have[q, b0] = 0
                    have[q, b1] = 0
                    merged = True
    condensed_row(gaps.dof, gaps.sign, Z, fac.S, q)
    have[q, 0] = 1


@jit_internal
def _forcing(alpha, f0, w, f1, nz, phi):
    """φ = α f0 − w f1 of every gap and the indices of the nonzero ones (their count returned)."""
    n_nz = 0
    for q in range(f0.size):
        p = alpha * f0[q] - w * f1[q]
        phi[q] = p
        if p != 0.0:
            nz[n_nz] = q
            n_nz += 1
    return n_nz


@jit_kernel
def contact_step(fac, cf, u, gaps, off, opts, tr, wk):
    """A step with gap elements, condensed onto the gaps. On entry ``tr`` holds the step of the
    linear system (no new contact force) taken with the tangent of ``fac``, whose Z and S are
    :func:`condense_map` (solved column by column as gaps act, :func:`condensed_column`). The
    structure is linear apart from the contact forces, so the step ends at

        u1 = u_lin + Zᵀ (α f0 − w f1),   δ = δ_lin + S (α f0 − w f1),   δ̇ = δ̇_lin + c1 (δ − δ_lin),

    and Newton runs on the C gap openings alone (no n × n work per iteration) before one update
    of u1, v1, a1 over the rows each acting gap's column reaches. Only the A gaps with a contact
    stiffness couple the Newton system, so each iteration solves A × A and back-substitutes the
    others: O(A³ + CA), not O(C³), for a long row of contacts with few closed. Returns (ok, Newton iterations), as :func:`newton`."""
    n = u.size
    n_el = gaps.gap.size
    Z = fac.Z
    S = fac.S
    f0 = gaps.f0
    alpha = cf.alpha
    w = cf.w
    cw = wk.cw
    act = wk.act
    nz = wk.nz
    phi = wk.phi
    Sm = wk.Sm
    d1 = tr.d1
    dd1 = tr.dd1
    rhs_col = Sm.shape[1] - 1
    d_lin = cw[0]
    dd_lin = cw[1]
    gap_openings(tr.u1, tr.v1, gaps, d_lin, dd_lin)
    u_scale = 1e-3
    for i in range(n):
        u_scale = max(u_scale, abs(u[i]), abs(tr.u1[i]))
    tol_d = opts.tol * u_scale
    # start from the forces of the step start (f1 ≈ f0 inside a contact, 0 outside); sums run over
    # the gaps whose force term is nonzero (nz): O(C A), not O(C²), for a long row with few closed
    e = wk.e
    # the Newton rows: gaps held open (every open gap while a closure is being located) carry no
    # force, so their openings follow from the forces once, after the iterations (O(C A) once,
    # not per iteration, for a long row with few gaps closed)
    live = wk.live
    n_live = 0
    for c in range(n_el):
        if off[c]:
            tr.f1[c] = 0.0
            tr.kd1[c] = 0.0
            tr.cd1[c] = 0.0
        else:
            live[n_live] = c
            n_live += 1
    n_nz = 0
    for q in range(n_el):
        if f0[q] != 0.0:
            nz[n_nz] = q
            n_nz += 1
            condensed_column(fac, gaps, q, e)
    for il in range(n_live):
        c = live[il]
        acc = d_lin[c]
        for iq in range(n_nz):
            q = nz[iq]
            acc -= S[q, c] * f0[q]
        d1[c] = acc
    ok = False
    n_it = opts.max_iter
    small = False
    prev_active = True
    for it in range(opts.max_iter + 1):
        active = False
        for il in range(n_live):
            c = live[il]
            dd1[c] = dd_lin[c] + cf.c1 * (d1[c] - d_lin[c])
            fc, kc, cc = gap_force(gaps, c, d1[c], dd1[c])
            tr.f1[c] = fc
            tr.kd1[c] = kc
            tr.cd1[c] = cc
            if fc != 0.0 or kc != 0.0:
                active = True
        if it > 0 and (small or (not active and not prev_active)):
            ok = True
            n_it = it
            break
        if it == opts.max_iter:
            n_it = it
            break
        prev_active = active
        # r = δ − δ_lin − S (α f0 − w f1),  ∂r/∂δ = I + w S diag(k + c1 c): a column is zero
        # but for its unit diagonal where a gap has no stiffness
        n_act = 0
        for il in range(n_live):
            q = live[il]
            kq = w * (tr.kd1[q] + cf.c1 * tr.cd1[q])
            cw[2, q] = kq
            if kq != 0.0:
                act[n_act] = q
                n_act += 1
                condensed_column(fac, gaps, q, e)
        n_nz = _forcing(alpha, f0, w, tr.f1, nz, phi)
        for iq in range(n_nz):
            condensed_column(fac, gaps, nz[iq], e)
        for il in range(n_live):
            r = live[il]
            acc = d1[r] - d_lin[r]
            for iq in range(n_nz):
                q = nz[iq]
                acc -= S[q, r] * phi[q]
            cw[3, r] = -acc
        for ia in range(n_act):
            r = act[ia]
            for ja in range(n_act):
                q = act[ja]
                Sm[ia, ja] = S[q, r] * cw[2, q]
            Sm[ia, ia] += 1.0
            Sm[ia, rhs_col] = cw[3, r]
        if not _solve_small(Sm, n_act):
            n_it = it
            break
        for ia in range(n_act):
            cw[3, act[ia]] = Sm[ia, rhs_col]
        big = 0.0
        for il in range(n_live):
            c = live[il]
            if cw[2, c] == 0.0:
                for ja in range(n_act):
                    q = act[ja]
                    cw[3, c] -= S[q, c] * cw[2, q] * cw[3, q]
            d1[c] += cw[3, c]
            big = max(big, abs(cw[3, c]))
        if not math.isfinite(big):
            n_it = it
            break
        small = big <= tol_d
    if ok:
        n_nz = _forcing(alpha, f0, w, tr.f1, nz, phi)
        for c in range(n_el):
            if off[c]:
                acc = d_lin[c]
                for iq in range(n_nz):
                    q = nz[iq]
                    acc += S[q, c] * phi[q]
                d1[c] = acc
                dd1[c] = dd_lin[c] + cf.c1 * (acc - d_lin[c])
        have = fac.have
        for iq in range(n_nz):
            c = nz[iq]
            p = phi[c]
            for sg in range((have.shape[1] - 1) // 2):
                for i in range(have[c, 1 + 2 * sg], have[c, 2 + 2 * sg]):
                    z = Z[c, i] * p
                    tr.u1[i] += z
                    tr.v1[i] += cf.c1 * z
                    tr.a1[i] += cf.c0 * z
    return ok, n_it


@jit_internal
def newton(hs, t, x0, md, sch, gaps, off, fr, el, fac, opts, tr, wk):
    """One Newmark/HHT step of length hs from x0 = (u, v, a), every element family included; fills
    ``tr``. Returns (ok, iterations).

    ``md.x_dof``/``md.x_sign`` hold the rows of the gaps, the friction elements (base dof, sign +1)
    and the element families, so one Woodbury update covers active contacts, sliding tangents,
    stuck-slab constraints and the families' tangents. When hs equals ``fac.h[0]``, the step whose
    inverse tangent without contacts is known, each iteration solves by that update; otherwise the
    full tangent is assembled and solved."""
    u, v, a = x0
    n = u.size
    n_el = gaps.gap.size
    n_fr = 0 if fr is None else fr.dof.size
    n_x = md.x_dof.shape[0]
    u1 = tr.u1
    cf = newmark_coefficients(hs, sch)
    w = cf.w
    alpha = cf.alpha
    g_eff = w * ground_at(md.ag, md.ag_dt, t + hs) - alpha * ground_at(md.ag, md.ag_dt, t)
    known = abs(hs - fac.h[0]) <= 1e-8 * fac.h[0]
    # family rows within the band (yielding stories) join the band tangent, refactored at every
    # iteration (O(n bw²)); the Woodbury update keeps only the rows outside it
    own = in_band(el, md.bw)
    # each iteration solves by band solves and the Woodbury update, O(n bw (1 + m)), not the dense
    # O(n³) elimination; another step length first factors its band tangent once (O(n bw²))
    banded = not md.dense and not own
    if banded:
        if not known:
            tangent_band_into(hs, md.Mb, md.Cb, md.Kb, sch, wk.Jb)
            band_ldl_into(wk.Jb, md.bw, wk.Lw, wk.Dw)
        for c in range(n_x):
            wk.have[c] = False
    old = wk.vec[0]
    y = wk.vec[1]
    step = wk.vec[2]
    kc = wk.vec[3, :n_x]
    # the α-weighted old internal forces plus the load: −α (C v + K u + Bᵀ f0) + M ι g_eff
    for i in range(n):
        old[i] = md.Mi[i] * g_eff
    if alpha != 0.0:
        _mv(md.C, md.Cb, md.bw, md.dense, v, -alpha, old)
        _mv(md.K, md.Kb, md.bw, md.dense, u, -alpha, old)
        # a stuck slab's row is replaced by its constraint
        add_forces(old, -alpha, gaps, gaps.f0, el, False)
        add_friction(old, -alpha, fr, FS_F0, True)
    u_scale = 1e-3
    for i in range(n):
        # predictor: constant acceleration over the step (one Newton iteration fewer than u1 = u)
        u1[i] = u[i] + hs * v[i] + 0.5 * hs * hs * a[i]
        u_scale = max(u_scale, abs(u[i]))
    small = False
    prev_active = True
    for it in range(opts.max_iter + 1):
        end_of_step(cf, u, v, a, u1, tr.v1, tr.a1)
        active = eval_gaps(u1, tr.v1, gaps, off, tr)
        if fr is not None and n_fr > 0 and eval_friction(u, u1, tr.v1, cf.c1, fr):
            active = True
        if el is not None and eval_elements(u1, tr.v1, hs, el):
            active = True
        if it > 0 and (small or (not active and not prev_active)):
            return True, it
        if it == opts.max_iter:
            return False, it
        prev_active = active
        # residual of the weighted equation of motion
        R = wk.R
        for i in range(n):
            R[i] = old[i]
        _mv(md.M, md.Mb, md.bw, md.dense, tr.a1, 1.0, R)
        _mv(md.C, md.Cb, md.bw, md.dense, tr.v1, w, R)
        _mv(md.K, md.Kb, md.bw, md.dense, u1, w, R)
        add_forces(R, w, gaps, tr.f1, el, True)
        add_friction(R, w, fr, FS_F1, True)
        row_stiffness(cf, tr, fr, el, kc)
        solved = False
        if own:
            tangent_band_into(hs, md.Mb, md.Cb, md.Kb, sch, wk.Jb)
            band_rows_into(el, n_el + n_fr, kc, md.bw, wk.Jb)
            band_ldl_into(wk.Jb, md.bw, wk.Lw, wk.Dw)
            for c in range(n_x):
                wk.have[c] = False
            solved = woodbury_band_solve(wk.Lw, wk.Dw, md.bw, md.blk_el, R, md.x_dof, md.x_sign,
                                         kc, wk.Z, wk.have, wk.S, y, step, wk.e)  # fmt: skip
            if not solved:
                row_stiffness(cf, tr, fr, el, kc)  # every row back for the dense fallback
        elif known and md.dense:
            solved = _woodbury_solve(fac.J_inv, R, md.x_dof, md.x_sign, kc, wk.Z, wk.S, y, step)
        elif known:
            solved = woodbury_band_solve(fac.L, fac.D, md.bw, fac.blk, R, md.x_dof, md.x_sign,
                                         kc, wk.Z, wk.have, wk.S, y, step, wk.e)  # fmt: skip
        elif banded:
            solved = woodbury_band_solve(wk.Lw, wk.Dw, md.bw, fac.blk, R, md.x_dof, md.x_sign,
                                         kc, wk.Z, wk.have, wk.S, y, step, wk.e)  # fmt: skip
        if not solved:
            J = wk.J
            tangent_dense(cf, md.M, md.C, md.K, J)
            add_row_tangent(md.x_dof, md.x_sign, kc, J)
            if fr is not None:
                for k in range(n_fr):
                    if math.isinf(kc[n_el + k]):  # a stuck slab: its row becomes u1_b − u_b = 0
                        i = fr.dof[k]
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
        if fr is not None:
            for k in range(n_fr):
                if fr.state[k, FS_STUCK] != 0.0:
                    u1[fr.dof[k]] = u[fr.dof[k]]  # exactly, not to round-off
        if not math.isfinite(big):
            return False, it
        small = big <= opts.tol * u_max
    return False, opts.max_iter


@jit_internal
def residual(md, g, u, v, a, gaps, f, fr, el, r):
    """r = M a + C v + K u + Bᵀ F + f_friction + M ι a_g: what the state fails the equation of motion
    by at one instant (zero for Newmark's end-of-step states; the α-weighted lag of HHT)."""
    for i in range(u.size):
        r[i] = md.Mi[i] * g
    _band_matvec_add(md.Mb, md.bw, a, 1.0, r)
    _band_matvec_add(md.Cb, md.bw, v, 1.0, r)
    _band_matvec_add(md.Kb, md.bw, u, 1.0, r)
    add_forces(r, 1.0, gaps, f, el, True)
    add_friction(r, 1.0, fr, FS_F1, False)


@jit_internal
def stick_force(b, g1, md, u1, v1, gaps, f1, el):
    """Force p [N] that holds base dof b at rest: m_b u_b'' = p − f, p = −m_b a_g − (C u̇ + K u)_b
    − (Bᵀ F)_b. A stuck slab's friction equals p; it slides towards sign(p) once |p| > μ_s N."""
    p = -md.Mi[b] * g1
    for j in range(u1.size):
        p -= md.C[b, j] * v1[j] + md.K[b, j] * u1[j]
    for c in range(f1.size):
        for s in range(gaps.dof.shape[1]):
            if gaps.dof[c, s] == b:
                p -= gaps.sign[c, s] * f1[c]
    if el is not None:
        for e in range(el.kind.size):
            for s in range(el.dof.shape[1]):
                if el.dof[e, s] == b:
                    p -= el.sign[e, s] * el.f1[e]
    return p


@jit_internal
def equilibrium(g1, md, tr, gaps, fr, el, rhs):
    """Restart the acceleration from equilibrium at (u1, v1), with every element force; a stuck
    Coulomb slab is tested: it keeps sticking (f = p, ü_b = 0) while |p| <= μ_s N, else it breaks
    away towards sign(p) against μ_d N. Returns True when a slab broke away."""
    u1 = tr.u1
    v1 = tr.v1
    n = u1.size
    broke = False
    for i in range(n):
        rhs[i] = -md.Mi[i] * g1
    _band_matvec_add(md.Cb, md.bw, v1, -1.0, rhs)
    _band_matvec_add(md.Kb, md.bw, u1, -1.0, rhs)
    add_forces(rhs, -1.0, gaps, tr.f1, el, True)
    if fr is None:
        band_solve(md.Lm, md.Dm, md.bw, rhs, tr.a1)
        return broke
    add_friction(rhs, -1.0, fr, FS_F1, True)
    st = fr.state
    for k in range(fr.dof.size):
        b = fr.dof[k]
        if fr.kind[k] == FRICTION_COULOMB and st[k, FS_STUCK] != 0.0:
            p = rhs[b]
            if abs(p) <= fr.params[k, 0] * fr.normal[k]:
                st[k, FS_F1] = p
                rhs[b] = 0.0
                continue
            st[k, FS_STUCK] = 0.0
            st[k, FS_DIR] = 1.0 if p > 0.0 else -1.0
            st[k, FS_F1] = st[k, FS_DIR] * fr.params[k, 1] * fr.normal[k]
            broke = True
            rhs[b] -= st[k, FS_F1]
    band_solve(md.Lm, md.Dm, md.bw, rhs, tr.a1)
    for k in range(fr.dof.size):
        if st[k, FS_STUCK] != 0.0:
            tr.a1[fr.dof[k]] = 0.0
            v1[fr.dof[k]] = 0.0
    return broke


@jit_setup
def refactor(h, md, sch, fac, Jb):
    """Factor the tangent without contacts of a step of length h into ``fac`` (in place: arrays
    reassigned inside the loop would cost reference-count traffic on every step; ``Jb`` scratch).

    The dense inverse and the whole condensation (Z, S) only where ``fac.J_inv`` is allocated
    (small systems, Coulomb slabs); otherwise the condensed step solves the columns of the gaps
    that act under this factor when they first do (:func:`condensed_column`): a row of buildings
    changes its contact step at every impact, and the O(n² + n C + C²) condensation of every gap
    was most of its cost at 400 dofs."""
    tangent_band_into(h, md.Mb, md.Cb, md.Kb, sch, Jb)
    band_ldl_into(Jb, md.bw, fac.L, fac.D)
    fac.h[0] = h
    n_el = fac.Z.shape[0]
    eager = fac.J_inv.shape[0] == fac.D.size
    if eager:
        _band_inverse(fac.L, fac.D, md.bw, fac.J_inv)
        condense_map(fac.J_inv, md.x_dof[:n_el], md.x_sign[:n_el], fac.Z, fac.S, fac.have)
    if not eager:
        for c in range(n_el):
            fac.have[c, 0] = 0
