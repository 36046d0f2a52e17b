"""The compiled Newmark/HHT time loop: choose a step, take it, locate its events, account for it,
accept it. The parts live beside it by concern: the argument groups and layouts (``_layout``), the
coefficients (``_coefficients``), the element families (``_families``), the step kinds
(``_steps``), the ledger and the impact log (``_ledger``), the law dispatch (``_dispatch``), the
event helpers (``_events``) and the linear algebra (``_linalg``)."""

from __future__ import annotations

import signal

import numpy as np

from pounding._numba import jit, jit_inline, jit_internal, jit_kernel  # noqa: F401  (re-exported: the kernels' decorators)

# The kernels' parts, by concern; names re-exported here for the integrators and the tests.
from pounding.integrators._coefficients import Coef, newmark_coefficients  # noqa: F401
from pounding.integrators._dispatch import (  # noqa: F401
    BILINEAR_ID,
    FAMILY_STORY,
    bilinear_rate,
    bouc_wen_rate,
    bouc_wen_slide,
    bouc_wen_story_rate,
    contact_eval,
    contact_stored_energy,
    element_eval,
    element_stored,
    friction_eval,
    friction_hysteretic_eval,
    has_straight,
)
from pounding.integrators._events import first_drop, ground_at, hermite_root  # noqa: F401
from pounding.integrators._families import eval_gaps, gap_openings
from pounding.integrators._layout import *  # noqa: F403  (re-exported: the layouts)
from pounding.integrators._layout import (
    CNT_FRICTION,
    CNT_HALVINGS,
    CNT_LOCATED,
    CNT_NEWTON,
    CNT_STATUS,
    CNT_SUBSTEPS,
    CT_GRADE,
    CT_GSTART,
    CT_HALVINGS,
    CT_HCONTACT,
    CT_HSEP,
    CT_SCALE,
    DENSE_MAP_RATIO,
    FRICTION_FORCE_TOL,
    FRICTION_SPEED_TOL,
    FS_DIR,
    FS_F0,
    FS_F1,
    FS_STUCK,
    GRADED_STEPS,
    N_CT,
    N_EN,
    SHORT_STEP,
    SLIVER,
    STATUS_COLLAPSE,
    STATUS_NO_CONVERGENCE,
    Factor,
    LoopState,
    Model,
    Trial,
    Work,
)
from pounding.integrators._ledger import (  # noqa: F401
    accept,
    account_algorithmic,
    account_energy,
    log_impacts,
    path_add,
    path_start,
    store,
)
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
    band_blocks,
    band_ldl,
    band_solve,
    bandwidth,
    to_band,
)
from pounding.integrators._steps import (  # noqa: F401
    condense_map,
    contact_step,
    dense_map,
    dense_step,
    equilibrium,
    linear_step,
    linear_step_coulomb,
    newton,
    refactor,
    residual,
    settle_elements,
    slopes_prepare,
    stick_force,
    straight_step,
)
from pounding.system import FRICTION_COULOMB


@jit
def _prepare(sy, sch, gaps, fr, el, h):
    """The model (band forms, M ι, M's factors), the factors of the base step and of the contact step
    (a copy until a contact needs another step), the trial arrays, the scratch space and the loop
    state."""
    n = sy.M.shape[0]
    n_el = gaps.gap.size
    n_x = sy.x_dof.shape[0]
    Mi = np.zeros(n)
    _dense_matvec_add(sy.M, sy.iota, 1.0, Mi)
    # band storage: a row of shear buildings has tridiagonal M, C (Rayleigh), K, so every per-step
    # product and solve is O(n); dense damping or an isolation slab widens the band, never beyond n
    bw = bandwidth(sy.M, sy.C, sy.K)
    Mb = to_band(sy.M, bw)
    Cb = to_band(sy.C, bw)
    Kb = to_band(sy.K, bw)
    L_m, D_m = band_ldl(Mb, bw)
    dense = n * (2 * bw + 1) * 3 >= DENSE_MAP_RATIO * n * n
    # the diagonal blocks (separate buildings) of the band tangent, and of the tangent with the
    # family rows that Newton takes into the band
    pattern = np.abs(Mb) + np.abs(Cb) + np.abs(Kb)
    blk = band_blocks(pattern, bw)
    if el is not None:
        for e in range(el.kind.size):
            for s in range(el.dof.shape[1]):
                for r in range(el.dof.shape[1]):
                    i = el.dof[e, s]
                    j = el.dof[e, r]
                    if i >= 0 and j >= 0 and abs(i - j) <= bw:
                        pattern[i, j - i + bw] = 1.0
    # diagonal-major copies for the quadratic forms of the energy ledger
    md = Model(sy.M, sy.C, sy.K, Mi, L_m, D_m, Mb, Cb, Kb, _transpose(Mb), _transpose(Cb),
               _transpose(Kb), bw, dense, sy.iota, sy.below, sy.tilt, sy.tilt_h, sy.ag, sy.ag_dt,
               sy.x_dof, sy.x_sign, band_blocks(pattern, bw))  # fmt: skip
    if dense:
        Q, pg = dense_map(h, sy.M, sy.C, sy.K, Mi, sch)
    else:
        Q = np.zeros((0, 0))
        pg = np.zeros(0)
    tr = Trial(np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n_el), np.zeros(n_el),
               np.zeros(n_el), np.zeros(n_el), np.zeros(n_el))  # fmt: skip
    m = max(n_x, 1)
    lin = (np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n))
    wk = Work(np.zeros(n), np.zeros((n, n)), np.zeros((4, max(n, n_x))), np.zeros((n, m)),
              np.zeros((m, m + 1)), lin, np.zeros((4, n_el)), np.zeros(n_el, dtype=np.int64),
              np.zeros(n_el, dtype=np.int64), np.zeros(n_el),
              np.zeros((max(n_el, 1), max(n_el, 1) + 1)), np.zeros(n_el),
              np.zeros(n_el, dtype=np.bool_), np.zeros(n_el, dtype=np.bool_),
              np.zeros((n, 2 * bw + 1)), np.zeros((n, bw + 1)), np.zeros(n), np.zeros(n),
              np.zeros(n_x, dtype=np.bool_), np.zeros(n_el, dtype=np.int64))  # fmt: skip
    # the dense inverse where the dense map is used or Coulomb slabs read its columns
    n_inv = n if dense or (fr is not None and fr.dof.size > 0) else 0
    n_have = 1 + 2 * md.x_dof.shape[1]  # solved, then a row range per dof of a gap
    fac_h = Factor(np.zeros(1), np.zeros((n, bw + 1)), np.zeros(n), np.empty((n_inv, n_inv)),
                   np.zeros((n_el, n)), np.zeros((n_el, n_el)), Q, pg,
                   np.zeros((n_el, n_have), dtype=np.int64), blk)  # fmt: skip
    refactor(h, md, sch, fac_h, wk.Jb)
    fac_c = Factor(fac_h.h.copy(), fac_h.L.copy(), fac_h.D.copy(), fac_h.J_inv.copy(),
                   fac_h.Z.copy(), fac_h.S.copy(), np.zeros((0, 0)), np.zeros(0),
                   fac_h.have.copy(), blk)  # fmt: skip
    # the factor of any other step length (graded, before a separation, located events) for the
    # condensed step of a large system of gaps alone; unused (empty) otherwise
    k = n_el if _condensed_any(md, fr, el) else 0
    fac_g = Factor(np.zeros(1), np.zeros((n, bw + 1)), np.zeros(n), np.empty((0, 0)),
                   np.zeros((k, n)), np.zeros((k, k)), np.zeros((0, 0)), np.zeros(0),
                   np.zeros((k, n_have), dtype=np.int64), blk)  # fmt: skip
    ls = LoopState(np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(N_CT), np.zeros(N_EN),
                   np.zeros(n), np.zeros(n), np.zeros(n_el, dtype=np.bool_),
                   np.zeros(n_el, dtype=np.bool_))  # fmt: skip
    # the stories condensed on the base step's tangent: a step in which every story goes straight
    # on is then one product (straight_step)
    straight = False
    if el is not None:
        straight = dense and (fr is None or fr.dof.size == 0) and el.kind.size > 0
        for e in range(el.kind.size):
            straight = straight and has_straight(el.kind[e], el.law[e])
    sl = slopes_prepare(fac_h.J_inv, fac_h.Q, fac_h.pg, el, straight)
    return md, fac_h, fac_c, fac_g, tr, wk, ls, sl


@jit_inline
def _condensed_any(md, fr, el):
    """True when a step of any length is taken condensed onto the gaps: gaps alone (no friction,
    no element family) in a system large enough for the band form. Newton over all n dofs would
    cost O(n) per iteration and a Woodbury row per closed gap; the condensed step solves the
    closed gaps' columns once per step and iterates on the gap openings."""
    return (fr is None or fr.dof.size == 0) and (el is None or el.kind.size == 0) and not md.dense


@jit_inline
def _step_any(hs, t, x0, md, sch, gaps, off, fr, el, fac, fac_g, opts, tr, wk):
    """A step of length hs by Newton with the factors ``fac`` where they are hs's (or the system
    needs Newton), else condensed onto the gaps with ``fac_g`` factored for hs."""
    if _condensed_any(md, fr, el) and abs(hs - fac.h[0]) > 1e-8 * fac.h[0]:
        if fac_g.h[0] != hs:
            refactor(hs, md, sch, fac_g, wk.Jb)
        cf = newmark_coefficients(hs, sch)
        g_eff = cf.w * ground_at(md.ag, md.ag_dt, t + hs) - cf.alpha * ground_at(md.ag, md.ag_dt, t)
        linear_step(md, fac_g, g_eff, cf, x0, tr, wk.lin)
        return contact_step(fac_g, cf, x0[0], gaps, off, opts, tr, wk)
    return newton(hs, t, x0, md, sch, gaps, off, fr, el, fac, opts, tr, wk)


@jit_inline
def _retry_smaller(ctl, counters, max_halvings):
    """A step failed: halve it and retry, unless the halvings are used up (then False: stop)."""
    ctl[CT_HALVINGS] += 1.0
    counters[CNT_HALVINGS] += 1
    if ctl[CT_HALVINGS] > max_halvings:
        counters[CNT_STATUS] = STATUS_NO_CONVERGENCE
        return False
    ctl[CT_SCALE] *= 0.5
    return True


@jit_inline
def _choose_step(t, t_next, gaps, ctl, opts, open_off):
    """Length of the next step from t: the base step while every gap is open, the contact step
    (graded after an onset, shortened before a separation) inside one, scaled by the halvings and
    stretched to end on the base step rather than leave a sliver. Sets ``open_off``: with onset
    location, trial steps hold every open gap open, so a closure is located on the contact-free
    motion, not on a trial that already bounced off the contact. Returns (hs, in contact)."""
    h = opts.h
    in_contact = False
    for c in range(gaps.gap.size):
        in_contact = in_contact or gaps.inside[c]
        open_off[c] = opts.locate_onset and not gaps.inside[c]
    if in_contact:
        hs = min(ctl[CT_HCONTACT] * 0.5 ** ctl[CT_GRADE], ctl[CT_HSEP]) * ctl[CT_SCALE]
    else:
        hs = h * ctl[CT_SCALE]
    if t_next - t - hs < SLIVER * hs:
        # a step of 1e-9 h turns the round-off of u into an acceleration error c0 ε u = 4 ε u / hs²
        hs = t_next - t
    if abs(hs - h) <= 1e-8 * h:
        hs = h  # a full base step: (k + 1) h − k h is not bit-equal to h
    return hs, in_contact


@jit_inline
def _take_step(hs, t, in_contact, h_contact, x0, md, sch, gaps, fr, el, facs, opts, tr, wk, off):
    """Take the step [t, t + hs] by the cheapest exact route: the linear step while nothing acts,
    then, if a gap closes, the step condensed onto the gaps (no friction, no element families) or
    Newton over every family. ``facs`` = the factors of the base step, of the contact step and of
    any other length (:func:`_step_any`), and the stories' condensation on the first
    (:func:`straight_step`); ``off`` = (no gap held open, open gaps held open). Returns (ok, Newton
    iterations, hs: the length taken)."""
    fac_h, fac_c, fac_g, sl = facs
    none_off, open_off = off
    h = opts.h
    n_fr = 0 if fr is None else fr.dof.size
    n_fam = 0 if el is None else el.kind.size
    linear = n_fam == 0
    if fr is not None:
        for k in range(n_fr):
            linear = linear and fr.kind[k] == FRICTION_COULOMB
    # element families without friction: the linear step, their forces settled on its factors
    settle = n_fam > 0 and n_fr == 0
    condensable = n_fr == 0 and n_fam == 0
    g_start = ground_at(md.ag, md.ag_dt, t)
    if not in_contact and hs == h and (linear or settle):
        # open gaps, Coulomb slabs stuck or sliding, element families: the exact linear step
        cf = newmark_coefficients(hs, sch)
        g_eff = cf.w * ground_at(md.ag, md.ag_dt, t + hs) - cf.alpha * g_start
        straight = False
        if fr is not None and n_fr > 0:
            linear_step_coulomb(md, fac_h, g_eff, cf, x0, fr, tr, wk)
        else:
            straight = settle and straight_step(sl, g_eff, cf, x0, el, tr)
            if not straight:
                linear_step(md, fac_h, g_eff, cf, x0, tr, wk.lin)
        # (the element forces settled by passes of this step's solve are not Newton iterations)
        if (straight or not settle
                or settle_elements(md.bw, fac_h.J_inv, fac_h.L, fac_h.D, cf, hs, el, tr, wk.lin,
                                   wk.vec[3], opts.tol, opts.max_iter)):  # fmt: skip
            closed = gap_openings(tr.u1, tr.v1, gaps, tr.d1, tr.dd1)
            for c in range(gaps.gap.size):
                tr.f1[c] = 0.0
            if closed and not opts.locate_onset and condensable:
                ok, its = contact_step(fac_h, cf, x0[0], gaps, none_off, opts, tr, wk)
                return ok, its, hs
            if closed and not opts.locate_onset:
                ok, its = newton(hs, t, x0, md, sch, gaps, none_off, fr, el, fac_h, opts, tr, wk)
                return ok, its, hs
            return True, 0, hs
    if in_contact and abs(hs - h_contact) <= 1e-8 * h_contact and fac_c.h[0] != h_contact:
        # a new contact step size: its tangent inverse serves every step of the impact
        refactor(hs, md, sch, fac_c, wk.Jb)
    use_c = abs(hs - fac_c.h[0]) <= 1e-8 * fac_c.h[0]
    if use_c:
        hs = fac_c.h[0]  # the step whose stored tangent serves it, exactly
    if condensable and (hs == h or use_c):
        # the linear step, then Newton on the gaps alone
        fac = fac_h if hs == h else fac_c
        cf = newmark_coefficients(hs, sch)
        g_eff = cf.w * ground_at(md.ag, md.ag_dt, t + hs) - cf.alpha * g_start
        linear_step(md, fac, g_eff, cf, x0, tr, wk.lin)
        ok, its = contact_step(fac, cf, x0[0], gaps, open_off, opts, tr, wk)
        return ok, its, hs
    fac = fac_c if use_c else fac_h
    ok, its = _step_any(hs, t, x0, md, sch, gaps, open_off, fr, el, fac, fac_g, opts, tr, wk)
    return ok, its, hs


@jit_inline
def _locate_gap_event(sense, hs, t, x0, md, sch, gaps, fr, el, facs, opts, tr, wk, off, counters):
    """Shorten the step to end at the earliest gap closure (``sense`` +1) or separation (−1) inside
    it, refining until the event's gaps are within d_tol of δ = 0. A penetration below d_tol is
    round-off, never an onset (identical neighbours at zero gap stay apart); a step carried past a
    separation would let the contact force do work the contact never stored. Flags the event's gaps
    in ``wk.closing`` or ``wk.separating``. Returns (ok, hs)."""
    d_tol = opts.d_tol
    d0 = gaps.d0
    dd0 = gaps.dd0
    d1 = tr.d1
    flags = wk.closing if sense > 0 else wk.separating
    th_min = 1.0
    for c in range(gaps.gap.size):
        if sense > 0:
            crossing = not gaps.inside[c] and d0[c] <= d_tol < d1[c]
        else:
            crossing = gaps.inside[c] and d0[c] > 0.0 and d1[c] < -d_tol
        wk.theta[c] = 2.0
        if crossing:
            th, _ = hermite_root(d0[c], dd0[c], d1[c], tr.dd1[c], hs)
            wk.theta[c] = th
            th_min = min(th_min, th)
    if th_min >= 1.0:
        return True, hs
    for c in range(gaps.gap.size):
        flags[c] = wk.theta[c] <= th_min * (1.0 + 1e-9)
    counters[CNT_LOCATED] += 1
    ok = True
    for _ in range(8):
        hs = max(th_min * hs, 1e-12 * opts.h)
        ok, its = _step_any(hs, t, x0, md, sch, gaps, off, fr, el, facs[0], facs[2], opts, tr, wk)
        counters[CNT_NEWTON] += its
        if not ok:
            return False, hs
        worst = -1.0
        th_min = 1.0
        for c in range(gaps.gap.size):
            if flags[c]:
                past = sense * d1[c]  # how far the gap went past δ = 0
                worst = max(worst, past)
                if past > d_tol:
                    th, _ = hermite_root(d0[c], dd0[c], d1[c], tr.dd1[c], hs)
                    th_min = min(th_min, th)
        if worst <= d_tol:
            break
    for c in range(gaps.gap.size):
        # a gap that stopped short of the event reaches it in a later step
        if wk.separating[c] and d1[c] > d_tol:
            wk.separating[c] = False
        if wk.closing[c] and d1[c] < -d_tol:
            wk.closing[c] = False
    return ok, hs


@jit_internal
def _slab_gap(k, b, fr, v1, p1, sign):
    """Distance to the next stick-slip event of Coulomb element k (>= 0 before it): dir u̇_b while
    sliding; μ_s N − sign p while stuck (sign = the side the push is on)."""
    if fr.state[k, FS_STUCK] != 0.0:
        return fr.params[k, 0] * fr.normal[k] - sign * p1
    return fr.state[k, FS_DIR] * v1[b]


@jit_internal
def _first_slab_event(hs, g1, x0, md, gaps, fr, el, tr):
    """The Coulomb slab whose stick-slip event (a sliding slab turning back, a stuck one breaking
    away) comes first inside the step, and its fraction θ of the step; (−1, 2) when none."""
    u, v, a = x0
    ev = -1
    th_ev = 2.0
    st = fr.state
    for k in range(fr.dof.size):
        fr.event[k] = False
        if fr.kind[k] != FRICTION_COULOMB:
            continue
        b = fr.dof[k]
        if st[k, FS_STUCK] != 0.0:
            p1 = stick_force(b, g1, md, tr.u1, tr.v1, gaps, tr.f1, el)
            fr.p[k] = p1
            sg = 1.0 if p1 > 0.0 else -1.0
            g_end = _slab_gap(k, b, fr, tr.v1, p1, sg)
            if g_end < 0.0:
                g_start = fr.params[k, 0] * fr.normal[k] - sg * st[k, FS_F0]
                th = g_start / (g_start - g_end)
                if th < th_ev:
                    th_ev = th
                    ev = k
        else:
            dr = st[k, FS_DIR]
            g_end = dr * tr.v1[b]
            if g_end < 0.0:
                th = first_drop(max(dr * v[b], 0.0), dr * a[b], g_end, dr * tr.a1[b], hs)
                if th < th_ev:
                    th_ev = th
                    ev = k
    return ev, th_ev


@jit_inline
def _locate_slab_event(ev, th_ev, hs, t, x0, md, sch, gaps, fr, el, fac_h, opts, tr, wk, off):
    """End the step at slab ev's stick-slip event: regula falsi with the Illinois rule on the step
    length, to round-off. Returns (ok, hs, ground acceleration at the new end, Newton iterations)."""
    u, v, a = x0
    st = fr.state
    b = fr.dof[ev]
    h = opts.h
    sg = 1.0 if fr.p[ev] > 0.0 else -1.0
    if st[ev, FS_STUCK] != 0.0:
        g_lo = fr.params[ev, 0] * fr.normal[ev] - sg * st[ev, FS_F0]
        g_tol = FRICTION_FORCE_TOL * fr.params[ev, 0] * fr.normal[ev]
        g_hi = _slab_gap(ev, b, fr, tr.v1, fr.p[ev], sg)
    else:
        g_lo = max(st[ev, FS_DIR] * v[b], 0.0)
        g_tol = FRICTION_SPEED_TOL * (abs(v[b]) + abs(a[b]) * hs) + 1e-300
        g_hi = st[ev, FS_DIR] * tr.v1[b]
    lo = 0.0
    hi = hs
    x = min(max(th_ev, 1e-6), 1.0 - 1e-6) * hs
    side = 0
    g1 = 0.0
    n_its = 0
    for it_loc in range(61):
        if it_loc == 60:
            x = hi  # not converged: end just past the event (g <= 0 there)
        ok, its = newton(x, t, x0, md, sch, gaps, off, fr, el, fac_h, opts, tr, wk)
        n_its += its
        if not ok:
            return False, hs, g1, n_its
        g1 = ground_at(md.ag, md.ag_dt, t + x)
        p1 = stick_force(b, g1, md, tr.u1, tr.v1, gaps, tr.f1, el)
        fr.p[ev] = p1
        gx = _slab_gap(ev, b, fr, tr.v1, p1, sg)
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
    fr.event[ev] = True
    for c in range(gaps.gap.size):
        # a closure or separation the shortened step no longer reaches comes later
        if wk.closing[c] and tr.d1[c] < -opts.d_tol:
            wk.closing[c] = False
        if wk.separating[c] and tr.d1[c] > opts.d_tol:
            wk.separating[c] = False
    return True, x, g1, n_its


@jit_internal
def _slab_transitions(hs, g1, x0, md, gaps, fr, el, tr):
    """Stick-slip transitions at the step end: the located event and any other slab at its own
    (a stuck slab pushed beyond μ_s N breaks away; a sliding one that stopped sticks or turns, as
    the stick test of the equilibrium restart decides). True when the state changed."""
    u, v, a = x0
    st = fr.state
    restart = False
    for k in range(fr.dof.size):
        if fr.kind[k] != FRICTION_COULOMB:
            continue
        b = fr.dof[k]
        if st[k, FS_STUCK] != 0.0:
            p1 = stick_force(b, g1, md, tr.u1, tr.v1, gaps, tr.f1, el)
            st[k, FS_F1] = p1
            if fr.event[k] or abs(p1) > fr.params[k, 0] * fr.normal[k]:
                st[k, FS_STUCK] = 0.0
                st[k, FS_DIR] = 1.0 if p1 > 0.0 else -1.0
                st[k, FS_F1] = st[k, FS_DIR] * fr.params[k, 1] * fr.normal[k]
                restart = True
        else:
            dr = st[k, FS_DIR]
            tol_v = FRICTION_SPEED_TOL * (abs(v[b]) + abs(a[b]) * hs) + 1e-300
            if fr.event[k] or dr * tr.v1[b] < 0.0 or (dr * v[b] > 0.0 and dr * tr.v1[b] <= tol_v):
                tr.v1[b] = 0.0
                st[k, FS_STUCK] = 1.0
                restart = True
    return restart


@jit_inline
def _adapt(onset, hs, gaps, tr, ctl, opts):
    """The contact step after this step: t_c(v0)/steps_per_contact of the shortest contact inside,
    graded geometrically after an onset, and halving the time left before a separation."""
    if ctl[CT_GRADE] > 0.0:
        ctl[CT_GRADE] -= 1.0
    if not opts.adaptive:
        return
    if onset:
        # the force of some laws grows like a fractional power of time after the onset
        # (Jankowski: c ∝ δ^(1/4)); steps graded geometrically up to h_contact resolve it
        ctl[CT_GRADE] = GRADED_STEPS
    h_contact = opts.h
    for c in range(gaps.gap.size):
        if gaps.inside[c]:
            tc = gaps.tc_coef[c] * max(gaps.v0[c], 1e-3) ** gaps.tc_exp[c]
            h_contact = min(h_contact, tc / opts.steps_per_contact)
    ctl[CT_HCONTACT] = h_contact
    # the separation mirrors the onset: steps halve the time left to it (linear estimate) down to
    # the first graded step, so the trapezoidal work of a stiffening law errs alike going in and
    # coming out instead of only coming out
    h_sep = np.inf
    for c in range(gaps.gap.size):
        if gaps.inside[c] and tr.dd1[c] < 0.0 and tr.d1[c] > 0.0:
            t_sep = tr.d1[c] / -tr.dd1[c]
            if t_sep < 2.0 * h_contact:
                h_sep = min(h_sep, max(0.5 * t_sep, h_contact * 0.5**GRADED_STEPS))
    ctl[CT_HSEP] = h_sep


_HELD = (signal.SIGINT, signal.SIGTERM)


def _hold_signals():
    """Block SIGINT and SIGTERM in this thread (they stay pending); the previous mask, or None
    where the platform has no ``pthread_sigmask``."""
    if not hasattr(signal, "pthread_sigmask"):
        return None
    return signal.pthread_sigmask(signal.SIG_BLOCK, _HELD)


def _release_signals(previous) -> None:
    if previous is not None:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def newmark_run(sy, sch, gaps, fr, el, opts, n_steps, out_every, out):
    """Integrate from rest over n_steps base steps of opts.h; outputs every out_every steps (row 0 =
    t 0) into ``out``. Returns the final time reached; ``out.counters[CNT_STATUS]`` tells success or
    the failure kind.

    While every gap is open, no element family acts and every slab is stuck or sliding under Coulomb
    friction, a step is the precomputed linear map (no Newton). A step in which a gap closes is
    shortened to end at the closure; one in which a Coulomb slab turns back or breaks away, to end
    there. With ``opts.adaptive``, steps inside a contact are t_c(v0)/steps_per_contact; otherwise
    every step is h. The arrays are allocated by :func:`_prepare`; the loop (:func:`_integrate`)
    allocates none. A Python function joins the two compiled ones: compiled, it would link and
    optimise the whole core once more (12 s of a cold compilation).
    """
    # SIGINT/SIGTERM held while numba boxes _prepare's groups: boxing calls each namedtuple's
    # Python __new__, where a handler that raises (Ctrl-C, a study's stop) crashed the process
    # (a segfault in about 1 of 10 SIGTERMs sent to a serial study at that moment)
    held = _hold_signals()
    try:
        md, fac_h, fac_c, fac_g, tr, wk, ls, sl = _prepare(sy, sch, gaps, fr, el, opts.h)
    finally:
        _release_signals(held)
    return _integrate(md, sch, gaps, fr, el, opts, (fac_h, fac_c, fac_g, sl), tr, wk, ls, n_steps,
                      out_every, out)  # fmt: skip


@jit_internal
def _start(md, sch, gaps, fr, el, tr, wk, ls, out):
    """The state at rest at t = 0: a = −ι a_g(0), gaps at their initial openings, Coulomb slabs
    stuck unless the first push already exceeds μ_s N; row 0 of the output."""
    u = ls.u
    a = ls.a
    g = ground_at(md.ag, md.ag_dt, 0.0)
    for i in range(u.size):
        a[i] = -md.iota[i] * g
    for c in range(gaps.gap.size):
        gaps.d0[c] = -gaps.gap[c]  # a contact may start closed when a gap is 0
    if fr is not None and fr.dof.size > 0:
        for k in range(fr.dof.size):
            fr.state[k, FS_DIR] = 1.0
            if fr.kind[k] == FRICTION_COULOMB:
                fr.state[k, FS_STUCK] = 1.0
        tr_0 = Trial(u, ls.v, a, tr.d1, tr.dd1, gaps.f0, tr.kd1, tr.cd1)
        equilibrium(g, md, tr_0, gaps, fr, el, wk.R)
        for k in range(fr.dof.size):
            fr.state[k, FS_F0] = fr.state[k, FS_F1]
    ls.ctl[CT_HSEP] = np.inf
    ls.ctl[CT_GSTART] = g
    if _algorithmic(sch):
        residual(md, g, u, ls.v, a, gaps, gaps.f0, fr, el, ls.r0)
    store(np.int64(0), 0.0, md, (u, ls.v, a), gaps, fr, el, ls.en, out)


@jit_inline
def _algorithmic(sch):
    """The ledger is the scheme's own energy identity (work form, module docstring of newmark.py):
    exact for average acceleration; other schemes add their algorithmic term."""
    return sch.alpha != 0.0 or sch.gamma != 0.5 or sch.beta != 0.25


@jit_kernel
def _integrate(md, sch, gaps, fr, el, opts, facs, tr, wk, ls, n_steps, out_every, out):
    """The time loop: per base step, substeps chosen, taken, their events located, accounted for
    and accepted until the base step's end; output at every out_every-th base step."""
    h = opts.h
    counters = out.counters
    fac_h = facs[0]
    sl = facs[3]
    ctl = ls.ctl
    en = ls.en
    x0 = (ls.u, ls.v, ls.a)
    none_off = ls.none_off
    open_off = ls.open_off
    n_el = gaps.gap.size
    ctl[CT_HCONTACT] = h
    _start(md, sch, gaps, fr, el, tr, wk, ls, out)
    algorithmic = _algorithmic(sch)
    offs = (none_off, open_off)
    for k in range(n_steps):
        t = k * h
        t_next = (k + 1) * h
        ctl[CT_SCALE] = 1.0
        ctl[CT_HALVINGS] = 0.0
        while t < t_next - 1e-9 * h:
            # choose
            hs, in_contact = _choose_step(t, t_next, gaps, ctl, opts, open_off)
            # take
            ok, its, hs = _take_step(hs, t, in_contact, ctl[CT_HCONTACT], x0, md, sch, gaps, fr,
                                     el, facs, opts, tr, wk, offs)  # fmt: skip
            counters[CNT_NEWTON] += its
            if not ok:
                if _retry_smaller(ctl, counters, opts.max_halvings):
                    continue
                return t
            # locate: gap closure and separation, then stick-slip
            for c in range(n_el):
                wk.closing[c] = False
                wk.separating[c] = False
            if opts.locate_onset:
                for sense in (1.0, -1.0):
                    if ok:
                        ok, hs = _locate_gap_event(sense, hs, t, x0, md, sch, gaps, fr, el, facs,
                                                   opts, tr, wk, open_off, counters)  # fmt: skip
                if not ok:
                    if _retry_smaller(ctl, counters, opts.max_halvings):
                        continue
                    return t
            g1 = ground_at(md.ag, md.ag_dt, t + hs)
            if fr is not None and fr.dof.size > 0:
                ev, th_ev = _first_slab_event(hs, g1, x0, md, gaps, fr, el, tr)
                if ev >= 0:
                    counters[CNT_FRICTION] += 1
                    ok, hs, g1, its = _locate_slab_event(ev, th_ev, hs, t, x0, md, sch, gaps, fr,
                                                         el, fac_h, opts, tr, wk, open_off)  # fmt: skip
                    counters[CNT_NEWTON] += its
                    if not ok:
                        if _retry_smaller(ctl, counters, opts.max_halvings):
                            continue
                        return t
                if _slab_transitions(hs, g1, x0, md, gaps, fr, el, tr):
                    equilibrium(g1, md, tr, gaps, fr, el, wk.R)
            counters[CNT_SUBSTEPS] += 1
            # account
            account_energy(md, hs, ctl[CT_GSTART], g1, x0, tr, gaps, fr, el, en, wk)
            if algorithmic:
                residual(md, g1, tr.u1, tr.v1, tr.a1, gaps, tr.f1, fr, el, ls.r1)
                account_algorithmic(md, sch, hs, x0, tr, ls.r0, ls.r1, en, wk)
            onset, logged = log_impacts(t, hs, tr, gaps, wk, opts, out)
            if not logged:
                return t
            _adapt(onset, hs, gaps, tr, ctl, opts)
            if onset or hs < SHORT_STEP * h:
                if onset:
                    # a law whose force jumps at δ = 0⁺ (c v0) changes the acceleration at the
                    # onset: restart the next step from equilibrium with that force
                    eval_gaps(tr.u1, tr.v1, gaps, none_off, tr)
                # after a short step (a located event) too: a1 = c0 (u1 − u) − … turns the
                # round-off of u1 into an error 4 ε |u| / hs² that the next step would integrate;
                # a stuck slab hit by a jumping contact force may break away at once
                equilibrium(g1, md, tr, gaps, fr, el, wk.R)
                if algorithmic:
                    residual(md, g1, tr.u1, tr.v1, tr.a1, gaps, tr.f1, fr, el, ls.r0)
            # accept
            if accept(g1, md, x0, tr, gaps, fr, el, out):
                sl.count[1] = 1  # a kernel committed: the straight map is brought up to date
            t = t + hs
            ctl[CT_GSTART] = g1
            if counters[CNT_STATUS] == STATUS_COLLAPSE:
                return t
        if (k + 1) % out_every == 0:
            store((k + 1) // out_every, t_next, md, x0, gaps, fr, el, en, out)
    return t
