"""Bookkeeping of the compiled Newmark/HHT core: the energy ledger, the impact log with its
force-penetration paths, the running peaks and the output rows."""

from __future__ import annotations

import numpy as np

from pounding._numba import jit_inline, jit_internal, jit_kernel
from pounding.integrators._dispatch import FAMILY_LINK, FAMILY_STORY, contact_stored_energy
from pounding.integrators._events import ground_at, hermite_root
from pounding.integrators._families import commit_elements, elements_stored
from pounding.integrators._layout import (
    CNT_IMPACTS,
    CNT_STATUS,
    EN_ALG,
    EN_CONTACT,
    EN_DAMP,
    EN_ELEMENTS,
    EN_FRICTION,
    EN_INPUT,
    EVENT_FRACTION,
    FS_F0,
    FS_F1,
    FS_STUCK,
    FS_Z0,
    FS_Z1,
    IMP_DMAX,
    IMP_END,
    IMP_FMAX,
    IMP_IMPULSE,
    IMP_NPTS,
    IMP_PATH,
    IMP_SEEN,
    IMP_START,
    IMP_STRIDE,
    IMP_V0,
    IMP_VEND,
    STATUS_COLLAPSE,
    STATUS_IMPACT_LOG_FULL,
)
from pounding.integrators._linalg import _band_bilinear, _band_quadratic
from pounding.integrators.base import PATH_POINTS


@jit_kernel
def path_start(row):
    """Start the step path of an impact (its log row) at the closure: no penetration, no force."""
    row[IMP_NPTS] = 1.0
    row[IMP_STRIDE] = 1.0
    row[IMP_SEEN] = 0.0
    row[IMP_PATH] = 0.0
    row[IMP_PATH + 1] = 0.0


@jit_kernel
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


@jit_inline
def account_energy(md, hs, g0, g1, x0, tr, gaps, fr, el, en, wk):
    """Add the work of the step-averaged forces on the step's increment to the running sums ``en``
    (input, damping, contact, friction, families). The Newmark identity makes these exact for
    average acceleration; the algorithmic term of other schemes is :func:`account_algorithmic`."""
    u, v, a = x0
    # the scratch rows are max(n, Woodbury rows) long: only their first n entries are this step's
    du = wk.vec[0, : u.size]
    vs = wk.vec[1, : u.size]
    g_avg = 0.5 * (g0 + g1)
    work = 0.0  # summed apart: en may alias the arrays, so en[...] -= in the loop is a memory chain
    for i in range(u.size):
        du[i] = tr.u1[i] - u[i]
        vs[i] = v[i] + tr.v1[i]
        work += du[i] * md.Mi[i]
    en[EN_INPUT] -= work * g_avg
    en[EN_DAMP] += 0.5 * _band_bilinear(md.CbT, md.bw, du, vs)
    work = 0.0
    for c in range(gaps.gap.size):
        work += 0.5 * (gaps.f0[c] + tr.f1[c]) * (tr.d1[c] - gaps.d0[c])
    en[EN_CONTACT] += work
    if fr is not None:
        for k in range(fr.dof.size):
            b = fr.dof[k]
            en[EN_FRICTION] += 0.5 * (fr.state[k, FS_F0] + fr.state[k, FS_F1]) * (tr.u1[b] - u[b])
    if el is not None:
        links = stories = 0.0
        for e in range(el.kind.size):
            work = 0.5 * (el.f0[e] + el.f1[e]) * (el.d1[e] - el.d0[e])
            if el.kind[e] == FAMILY_STORY:
                stories += work
            else:
                links += work
        en[EN_ELEMENTS + FAMILY_LINK] += links
        en[EN_ELEMENTS + FAMILY_STORY] += stories


@jit_internal
def account_algorithmic(md, sch, hs, x0, tr, r0, r1, en, wk):
    """ΔE_alg = −Δuᵀ r̄ + h²(β − γ/2) Δaᵀ M ā − h(γ − ½) v̄ᵀ M Δa of a step whose end residual r1
    is known; r0 becomes r1 for the next step."""
    u, v, a = x0
    n = u.size
    du = wk.vec[0, :n]
    s = wk.vec[1, :n]
    step = 0.0
    for i in range(n):
        step -= 0.5 * (tr.u1[i] - u[i]) * (r0[i] + r1[i])
        du[i] = tr.a1[i] - a[i]
        s[i] = a[i] + tr.a1[i]
    step += 0.5 * hs * hs * (sch.beta - 0.5 * sch.gamma) * _band_bilinear(md.MbT, md.bw, du, s)
    for i in range(n):
        s[i] = v[i] + tr.v1[i]
    step -= 0.5 * hs * (sch.gamma - 0.5) * _band_bilinear(md.MbT, md.bw, s, du)
    en[EN_ALG] += step
    for i in range(n):
        r0[i] = r1[i]


@jit_internal
def open_impact(c, t_on, vc, v0_floor, gaps, log_el, log_val, counters):
    """Register the onset of an impact of gap c at t_on [s] with approach speed vc [m/s] (a
    v0-scaled law sees at least v0_floor). False when the impact log is full."""
    gaps.inside[c] = True
    gaps.v0[c] = max(vc, v0_floor)
    gaps.hd[c] = 0.0
    gaps.hf[c] = 0.0
    i_imp = counters[CNT_IMPACTS]
    if i_imp >= log_el.size:
        counters[CNT_STATUS] = STATUS_IMPACT_LOG_FULL
        return False
    counters[CNT_IMPACTS] += 1
    gaps.imp[c] = i_imp
    log_el[i_imp] = c
    row = log_val[i_imp]
    row[IMP_START] = t_on
    row[IMP_END] = np.nan
    row[IMP_V0] = max(vc, 0.0)
    row[IMP_VEND] = np.nan
    row[IMP_FMAX] = 0.0
    row[IMP_DMAX] = 0.0
    row[IMP_IMPULSE] = 0.0
    path_start(row)
    return True


@jit_inline
def log_impacts(t, hs, tr, gaps, wk, opts, out):
    """Onsets, running maxima and separations of every gap over the step [t, t + hs]. Returns
    (onset: an impact began, ok: the log had room)."""
    t1 = t + hs
    d1 = tr.d1
    dd1 = tr.dd1
    f1 = tr.f1
    d0 = gaps.d0
    dd0 = gaps.dd0
    onset = False
    for c in range(gaps.gap.size):
        # a gap that would close within EVENT_FRACTION of a step closes now: locating it would take a
        # step so short that its acceleration is lost to round-off
        soon = dd1[c] > 0.0 and opts.d_tol - d1[c] < EVENT_FRACTION * hs * dd1[c]
        if not gaps.inside[c] and (wk.closing[c] or d1[c] > opts.d_tol or soon):
            if wk.closing[c] or soon:
                # the step was shortened to end at this closure (or ends just before it)
                vc = dd1[c]
                t_on = t1 + max(-d1[c], 0.0) / vc
            else:
                th, vc = hermite_root(d0[c], dd0[c], d1[c], dd1[c], hs)
                t_on = t + th * hs
            onset = True
            if not open_impact(c, t_on, vc, opts.v0_floor, gaps, out.imp_el, out.imp_val,
                               out.counters):  # fmt: skip
                return onset, False
        if gaps.inside[c]:
            row = out.imp_val[gaps.imp[c]]
            row[IMP_FMAX] = max(row[IMP_FMAX], f1[c])
            row[IMP_DMAX] = max(row[IMP_DMAX], d1[c])
            row[IMP_IMPULSE] += 0.5 * hs * (gaps.f0[c] + f1[c])
            # separation (located: the step ends there); a grazing closure that never penetrated
            # ends once it recedes
            soon = dd1[c] < 0.0 and d1[c] < -EVENT_FRACTION * hs * dd1[c]
            ends = (
                wk.separating[c] or soon or (d1[c] <= 0.0 and (row[IMP_DMAX] > 0.0 or dd1[c] < 0.0))
            )
            path_add(row, max(d1[c], 0.0), f1[c], ends)
            if ends:
                if wk.separating[c] or (soon and d1[c] > 0.0):
                    vc = dd1[c]
                    row[IMP_END] = t1 + max(d1[c], 0.0) / -vc
                elif d0[c] > 0.0:
                    th, vc = hermite_root(d0[c], dd0[c], d1[c], dd1[c], hs)
                    row[IMP_END] = t + th * hs
                else:
                    vc = dd1[c]
                    row[IMP_END] = t1
                row[IMP_VEND] = vc
                gaps.inside[c] = False
                gaps.imp[c] = -1
                gaps.hd[c] = 0.0
                gaps.hf[c] = 0.0
            else:
                gaps.hd[c] = d1[c]
                gaps.hf[c] = f1[c]
    return onset, True


@jit_inline
def accept(g1, md, x0, tr, gaps, fr, el, out):
    """The trial end becomes the step start (the element families commit their trial state);
    peaks are updated. True when a kernel wrote an element's committed state
    (:func:`commit_elements`)."""
    u, v, a = x0
    for i in range(u.size):
        u[i] = tr.u1[i]
        v[i] = tr.v1[i]
        a[i] = tr.a1[i]
        au = abs(u[i])
        if au > out.peak_u[i]:
            out.peak_u[i] = au
        below = md.below[i]
        tilt = md.tilt[i]
        dr = abs(
            u[i]
            - (u[below] if below >= 0 else 0.0)
            - (md.tilt_h[i] * u[tilt] if tilt >= 0 else 0.0)
        )
        if dr > out.peak_drift[i]:
            out.peak_drift[i] = dr
            if dr > out.collapse[i]:
                out.counters[CNT_STATUS] = STATUS_COLLAPSE
        aa = abs(a[i] + md.iota[i] * g1)
        if aa > out.peak_aabs[i]:
            out.peak_aabs[i] = aa
    for c in range(gaps.gap.size):
        gaps.d0[c] = tr.d1[c]
        gaps.dd0[c] = tr.dd1[c]
        gaps.f0[c] = tr.f1[c]
        if tr.f1[c] > out.peak_f[c]:
            out.peak_f[c] = tr.f1[c]
        if tr.d1[c] > out.peak_d[c]:
            out.peak_d[c] = tr.d1[c]
    if fr is not None:
        for k in range(fr.dof.size):
            fr.state[k, FS_F0] = fr.state[k, FS_F1]
            fr.state[k, FS_Z0] = fr.state[k, FS_Z1]
    if el is None:
        return False
    for j in range(el.kind.size):
        # column 0 of a family's state is the force it reports (a story: its spring force)
        if abs(el.trial[j, 0]) > out.peak_lf[j]:
            out.peak_lf[j] = abs(el.trial[j, 0])
    failed, written = commit_elements(el)
    if failed:  # a story failed: its building has collapsed
        out.counters[CNT_STATUS] = STATUS_COLLAPSE
    return written


@jit_internal
def store(row, t, md, x0, gaps, fr, el, en, out):
    """Output row ``row`` at time t: state, gap δ and force, friction, cumulative energies."""
    if row >= out.u.shape[0]:
        return
    u, v, a = x0
    # element loops, not row slices: a slice assignment compiles numba's broadcasting checks
    for i in range(u.size):
        out.u[row, i] = u[i]
        out.v[row, i] = v[i]
        out.a[row, i] = a[i]
    out.ag[row] = ground_at(md.ag, md.ag_dt, t)
    stored = 0.0
    for c in range(gaps.gap.size):
        out.d[row, c] = gaps.d0[c]
        out.f[row, c] = gaps.f0[c]
        stored += contact_stored_energy(gaps.law[c], gaps.d0[c], gaps.f0[c], gaps.params[c])
    if fr is not None:
        for k in range(fr.dof.size):
            out.ff[row, k] = fr.state[k, FS_F0]
            out.st[row, k] = fr.state[k, FS_STUCK]
    if el is not None:
        for j in range(el.kind.size):
            out.lf[row, j] = el.state[j, 0]
    e = out.e
    e[row, 0] = en[EN_INPUT]
    e[row, 1] = 0.5 * _band_quadratic(md.MbT, md.bw, v)
    # the family as an int64, not its literal: one compiled elements_stored for both families
    story_stored = elements_stored(el, np.int64(FAMILY_STORY))
    # a yielding story's recoverable energy is F²/(2k): K's k δ²/2 plus its element's part
    e[row, 2] = 0.5 * _band_quadratic(md.KbT, md.bw, u) + story_stored
    e[row, 3] = en[EN_DAMP]
    e[row, 4] = en[EN_CONTACT] - stored
    e[row, 5] = stored
    e[row, 6] = en[EN_FRICTION]
    e[row, 7] = en[EN_ALG]
    link_stored = elements_stored(el, np.int64(FAMILY_LINK))
    e[row, 8] = en[EN_ELEMENTS + FAMILY_LINK] - link_stored
    e[row, 9] = link_stored
    e[row, 10] = en[EN_ELEMENTS + FAMILY_STORY] - story_stored
