"""The nonlinear element families of the compiled core: gather, kernel and scatter.

A family is a set of elements, each acting through a pair of dofs with signs (δ = s_a u_a + s_b u_b,
the force F pushes the pair apart: r_i += s_i F), with a kind, a law id, parameters and state. Three
families ride in every step:

- **gaps** (contact laws, :mod:`pounding.contact.laws`), with onset/separation events;
- **friction** (one dof per bearing, :mod:`pounding.friction`), with stick-slip events for Coulomb;
- **elements**: every further family (coupling links, ...) as rows of one struct, the law chosen
  by (kind, law id) in :func:`pounding.integrators._dispatch.element_eval`. They are always
  active, carry committed and trial state, and need no events: a new family adds a kernel and a
  dispatch entry, and the time loop, Newton, the Woodbury update, equilibrium restarts and the
  energy ledger take it as it is.

For each the core needs the force and the tangents ∂F/∂δ, ∂F/∂δ̇ at a trial state (``eval_*``), the
forces added into a residual (:func:`add_forces`) and the row stiffnesses of the Woodbury update
(:func:`row_stiffness`).
"""

from __future__ import annotations

import math

import numpy as np

from pounding._numba import jit_inline, jit_internal
from pounding.integrators._dispatch import (
    STRAIGHT_COLUMNS,
    bouc_wen_slide,
    bouc_wen_story_near,
    contact_eval,
    element_eval_other,
    element_eval_row,
    element_failed,
    element_stored,
    friction_eval,
    friction_hysteretic_eval,
    has_near,
    has_straight,
    story_straight,
    written_columns,
)
from pounding.integrators._layout import FS_DIR, FS_F1, FS_KF, FS_STUCK, FS_Z0, FS_Z1
from pounding.system import FRICTION_BOUC_WEN, FRICTION_COULOMB


@jit_inline
def gather(dof, sign, c, u, v):
    """s_a u_a + s_b u_b and its rate for row c of (dof, sign); a dof of −1 is fixed ground."""
    d = 0.0
    dd = 0.0
    for s in range(dof.shape[1]):
        i = dof[c, s]
        if i >= 0:
            d += sign[c, s] * u[i]
            dd += sign[c, s] * v[i]
    return d, dd


@jit_internal
def eval_gaps(u1, v1, gaps, off, tr):
    """δ, δ̇, force and tangents of every gap at (u1, v1) into ``tr``; True when any acts.

    Gaps flagged in ``off`` are held open: the step ends at their closure, and a law whose force
    jumps at δ = 0⁺ (c v0 of the Kelvin family) must not act before it."""
    active = False
    for c in range(gaps.gap.size):
        dc, vc = gather(gaps.dof, gaps.sign, c, u1, v1)
        dc -= gaps.gap[c]
        tr.d1[c] = dc
        tr.dd1[c] = vc
        if off[c]:
            tr.f1[c] = 0.0
            tr.kd1[c] = 0.0
            tr.cd1[c] = 0.0
            continue
        fc, kc, cc = gap_force(gaps, c, dc, vc)
        tr.f1[c] = fc
        tr.kd1[c] = kc
        tr.cd1[c] = cc
        if fc != 0.0 or kc != 0.0:
            active = True
    return active


@jit_inline
def gap_force(gaps, c, d, dd):
    """Force and tangents of gap c at (δ, δ̇); before the onset is registered, the approach speed
    itself stands in for v0."""
    if d <= 0.0:
        # every law is zero while the gap is open (tests/test_contact_laws.py); most of a row's
        # gaps are, and the dispatch cost ~30 ns a gap per Newton iteration
        return 0.0, 0.0, 0.0
    v0 = gaps.v0[c] if gaps.inside[c] else max(dd, 0.0)
    p = gaps.params
    # a tuple, not a row view: no array per call (p[4:8]: a bumper's or filler's layer)
    pc = (p[c, 0], p[c, 1], p[c, 2], p[c, 3], p[c, 4], p[c, 5], p[c, 6], p[c, 7])
    return contact_eval(gaps.law[c], d, dd, v0, gaps.hd[c], gaps.hf[c], pc)


@jit_inline
def gap_openings(u1, v1, gaps, d, dd):
    """δ and δ̇ of every gap; True when any gap is closed."""
    return gap_openings_of(u1, v1, gaps.dof, gaps.sign, gaps.gap, d, dd)


@jit_internal
def gap_openings_of(u1, v1, dof, sign, gap, d, dd):
    """:func:`gap_openings` on the gaps' dofs, signs and gaps [m] alone (a call copies every word
    of the groups it is given)."""
    closed = False
    for c in range(gap.size):
        dc, vc = gather(dof, sign, c, u1, v1)
        dc -= gap[c]
        d[c] = dc
        dd[c] = vc
        if dc > 0.0:
            closed = True
    return closed


@jit_internal
def eval_friction(u, u1, v1, c1, fr):
    """Trial force f1 and tangent ∂f1/∂u1 = c1 ∂f/∂v (+ ∂f/∂z ∂z1/∂u1) of every friction element.

    A stuck Coulomb slab is a constraint (tangent inf, force a reaction found after the step); a
    sliding one carries μ_d N against its direction. Returns True when a law is nonlinear."""
    if fr is None:
        return False
    nonlinear = False
    st = fr.state
    for k in range(fr.dof.size):
        b = fr.dof[k]
        kind = fr.kind[k]
        if kind == FRICTION_COULOMB:
            if st[k, FS_STUCK] != 0.0:
                st[k, FS_KF] = np.inf
            else:
                st[k, FS_F1] = st[k, FS_DIR] * fr.params[k, 1] * fr.normal[k]
                st[k, FS_KF] = 0.0
        elif kind == FRICTION_BOUC_WEN:
            z1, dz = bouc_wen_slide(st[k, FS_Z0], u1[b] - u[b], fr.bw[k])
            f, dfdv, dfdz = friction_hysteretic_eval(
                fr.law[k], v1[b], fr.normal[k], z1, fr.params[k]
            )
            st[k, FS_Z1] = z1
            st[k, FS_F1] = f
            st[k, FS_KF] = c1 * dfdv + dfdz * dz
            nonlinear = True
        else:
            f, dfdv = friction_eval(fr.law[k], v1[b], fr.normal[k], fr.params[k])
            st[k, FS_F1] = f
            st[k, FS_KF] = c1 * dfdv
            nonlinear = True
    return nonlinear


@jit_internal
def eval_elements(u1, v1, h, el):
    """Force and tangents of every family element at (u1, v1) at the end of a step of length h [s]
    (trial state from the committed one); True when there is any."""
    return eval_elements_here(u1, v1, h, el)


@jit_internal
def eval_element(el, e, d, dd, h):
    """Element e's kernel at drift d [m] and rate dd [m/s] over a step of h [s], from its committed
    state into its trial row (written); returns (F − k δ, its tangent kd). Called, not inlined:
    a straight step calls it where a story turned, rarely (a story model with straight
    branches: not Bouc–Wen, :func:`has_straight`)."""
    f, kd, _ = element_eval_other(
        el.kind[e], el.law[e], d, dd, h, el.state[e], el.trial[e], el.params[e]
    )
    el.written[e] = True
    return f, kd


@jit_inline
def eval_elements_here(u1, v1, h, el):
    """:func:`eval_elements` inlined into its caller: the fixed-point passes of every base step
    call it, and a call boundary passing the element group costs them ~8 %. A story increment
    that goes straight on (:func:`pounding.stories.story_straight`) skips its model's kernel, and
    so does a Bouc–Wen story re-evaluated a round-off from its trial
    (:func:`pounding.stories.make_bouc_wen_story_near`)."""
    if el is None:
        return False
    for e in range(el.kind.size):
        d, dd = gather(el.dof, el.sign, e, u1, v1)
        done = False
        f = kd = cd = 0.0
        if has_straight(el.kind[e], el.law[e]):
            done, f, kd = story_straight(d, el.state, el.trial, el.params, e)
            if done and el.written[e]:
                # the rest of the trial row is a kernel's from an earlier pass: the committed one
                for j in range(el.state.shape[1]):
                    el.trial[e, j] = el.state[e, j]
                story_straight(d, el.state, el.trial, el.params, e)
                el.written[e] = False
        elif el.written[e] and has_near(el.kind[e], el.law[e]):
            done, f, kd = bouc_wen_story_near(d, el.state, el.trial, el.params, e)
        if not done:
            f, kd, cd = element_eval_row(
                el.kind[e], el.law[e], d, dd, h, el.state, el.trial, el.params, e
            )
            el.written[e] = True
        el.d1[e] = d
        el.dd1[e] = dd
        el.f1[e] = f
        el.kd[e] = kd
        el.cd[e] = cd
    return el.kind.size > 0


@jit_inline
def add_forces(r, scale, gaps, f_gaps, el, trial):
    """r += scale (Bᵀ F) of the gaps' forces ``f_gaps`` and the elements' forces (their trial
    ``f1`` when ``trial``, else the committed ``f0``). Inlined: ``trial`` is a constant at every
    call, which would compile one specialisation each."""
    for c in range(f_gaps.size):
        fc = f_gaps[c]
        if fc != 0.0:
            for s in range(gaps.dof.shape[1]):
                i = gaps.dof[c, s]
                if i >= 0:
                    r[i] += scale * gaps.sign[c, s] * fc
    if el is None:
        return
    f_el = el.f1 if trial else el.f0
    for e in range(f_el.size):
        for s in range(el.dof.shape[1]):
            i = el.dof[e, s]
            if i >= 0:
                r[i] += scale * el.sign[e, s] * f_el[e]


@jit_inline
def add_friction(r, scale, fr, col, skip_stuck):
    """r += scale f of the friction column ``col`` of the state; stuck slabs skipped when
    ``skip_stuck`` (their row is a constraint). Inlined: its int and bool arguments are constants
    at every call, which would compile one specialisation each."""
    if fr is None:
        return
    for k in range(fr.dof.size):
        if not (skip_stuck and fr.state[k, FS_STUCK] != 0.0):
            r[fr.dof[k]] += scale * fr.state[k, col]


@jit_internal
def row_stiffness(cf, tr, fr, el, kc):
    """Stiffness w (∂F/∂δ + c1 ∂F/∂δ̇) of every Woodbury row: gaps, friction (inf: stuck), elements."""
    n_el = tr.f1.size
    n_fr = 0 if fr is None else fr.dof.size
    for c in range(n_el):
        kc[c] = cf.w * (tr.kd1[c] + cf.c1 * tr.cd1[c])
    if fr is not None:
        for k in range(n_fr):
            kc[n_el + k] = cf.w * fr.state[k, FS_KF]
    if el is not None:
        for e in range(el.kind.size):
            kc[n_el + n_fr + e] = cf.w * (el.kd[e] + cf.c1 * el.cd[e])


@jit_internal
def in_band(el, bw):
    """True when an element family row lies within the band of K (both dofs at most bw apart,
    or one at the ground): a yielding story, whose tangent is cheaper in the band factor than as
    a Woodbury row."""
    if el is None:
        return False
    for e in range(el.kind.size):
        a = el.dof[e, 0]
        b = el.dof[e, 1]
        if a < 0 or b < 0 or abs(a - b) <= bw:
            return True
    return False


@jit_internal
def band_rows_into(el, first, kc, bw, Jb):
    """Move the stiffness kc of the family rows within the band (rows ``first``…) into the band
    tangent Jb and zero it among the Woodbury rows."""
    if el is None:
        return
    for e in range(el.kind.size):
        c = first + e
        k = kc[c]
        a = el.dof[e, 0]
        b = el.dof[e, 1]
        if k == 0.0 or (a >= 0 and b >= 0 and abs(a - b) > bw):
            continue
        for s in range(el.dof.shape[1]):
            i = el.dof[e, s]
            if i < 0:
                continue
            for r in range(el.dof.shape[1]):
                j = el.dof[e, r]
                if j >= 0:
                    Jb[i, j - i + bw] += k * el.sign[e, s] * el.sign[e, r]
        kc[c] = 0.0


@jit_internal
def add_row_tangent(x_dof, x_sign, kc, J):
    """J += Σ kc_c b_c b_cᵀ over the finite rows (a stuck slab's infinite row is a constraint)."""
    for c in range(kc.size):
        if kc[c] != 0.0 and not math.isinf(kc[c]):
            for s in range(x_dof.shape[1]):
                i = x_dof[c, s]
                if i < 0:
                    continue
                for r in range(x_dof.shape[1]):
                    j = x_dof[c, r]
                    if j >= 0:
                        J[i, j] += kc[c] * x_sign[c, s] * x_sign[c, r]


@jit_inline
def commit_elements(el):
    """Accept the trial state of every family element as the start of the next step. Returns
    (failed, written): an element has spent its capacity (:func:`element_failed`); a kernel wrote
    a row (not only straight story increments)."""
    failed = written = False
    if el is None:
        return failed, written
    for e in range(el.kind.size):
        el.d0[e] = el.d1[e]
        el.f0[e] = el.f1[e]
        if el.written[e]:
            written = True
            for j in range(written_columns(el.kind[e], el.law[e], el.state.shape[1])):
                el.state[e, j] = el.trial[e, j]
            el.written[e] = False
            # (a straight increment leaves a story as it was: failure is a kernel's)
            if element_failed(el.kind[e], el.law[e], el.state[e]):
                failed = True
        else:  # a straight story increment
            for j in STRAIGHT_COLUMNS:
                el.state[e, j] = el.trial[e, j]
    return failed, written


@jit_internal
def elements_stored(el, kind):
    """Recoverable energy [J] held by the elements of family ``kind`` at their committed state."""
    total = 0.0
    if el is None:
        return total
    for e in range(el.kind.size):
        if el.kind[e] != kind:
            continue
        total += element_stored(
            el.kind[e], el.law[e], el.d0[e], el.f0[e], el.state[e], el.params[e]
        )
    return total
