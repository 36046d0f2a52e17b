r"""Reference integration with :func:`scipy.integrate.solve_ivp`, events at gap closure and separation.

The equations of motion of :mod:`pounding.system`,

.. math:: M\ddot u + C\dot u + K u + B^T F(\delta, \dot\delta) = -M\iota\, a_g(t),
          \qquad \delta = B u - g,

are integrated in first-order form with the state

.. math:: y = [u,\ \dot u,\ F_{bl},\ J,\ z,\ E_{in},\ E_D,\ W_c,\ W_f]

where F_bl is the force of each ``bilinear`` element (its loop is hysteretic, so the force is carried
as a state with rate :func:`pounding.contact.laws.bilinear_rate`), J the cumulative impulse ∫F dt of
each element, z the Bouc-Wen variable of each hysteretic friction element
(:func:`pounding.friction.bouc_wen_rate`) and the last four the energy integrals (relative-energy
form of Uang & Bertero [3]; W_f only when there are friction elements)

.. math:: E_{in} = -\int \dot u^T M\iota\, a_g\,dt, \qquad E_D = \int \dot u^T C\dot u\,dt, \qquad
          W_c = \int F^T\dot\delta\,dt, \qquad W_f = \int f^T \dot u_b\,dt

so that E_in = E_K + E_S + E_D + W_c + W_f holds exactly, with the kinetic and strain energies
E_K = ½u̇ᵀMu̇, E_S = ½uᵀKu. The contact work splits into the energy still stored in the contacts and the
energy dissipated, W_c = E_stored + E_dissipated; W_f is the work of the bearings' friction forces f on
the base velocities u̇_b of isolated buildings.

How the integration is cut into pieces:

* **Ground-motion samples.** a_g is linear between samples, so its slope jumps at every sample. The
  integration restarts at each sample so that the right-hand side is smooth inside every solver call
  (a high-order method stepping over a kink would otherwise shrink its step at every sample).
* **Contact events.** Every gap element has a terminal event δ_c = 0, upward (closure) while the element
  is open, downward (separation) while it is closed. At closure the impact velocity v0 = δ̇ is stored
  (the history variable of the Hunt-Crossley family and ``hertz_kelvin``) and the bilinear force state
  reset to 0; the integration restarts there, so each contact phase starts cleanly. The event direction
  follows the element's state, so an event does not fire again at the restart point. Force kinks inside
  a phase (a Kelvin force clamped at zero while δ > 0) are not events. A closure fires at δ = ε_δ, ten
  displacement tolerances of the solver: a penetration below that is round-off and carries no force
  worth an impact (identical buildings at zero gap). A separation and re-closure, or a grazing touch,
  can fall inside one solver step with no sign change of δ at the step ends; so every extremum of δ is
  a (non-terminal) event too, and a minimum below −ε_δ while closed (maximum above ε_δ while open)
  sends the integration back to the crossing before it, located on the dense output.
* **Coulomb stick-slip** (isolated buildings with the ``coulomb`` law). A sliding slab carries
  f = ±μ_d N and has a terminal event u̇_b = 0 (direction against its motion): there the velocity is set
  to exactly 0 and the stick test decides, |p| <= μ_s N with p the force that holds the slab at rest
  (m_b ü_b = p − f); it sticks, or slides on towards sign(p). A stuck slab has u̇_b ≡ 0, ü_b ≡ 0,
  f = p, and a terminal event μ_s N − |p| = 0 (break-away) after which it slides towards sign(p).
  A jump of a contact force at a restart (Kelvin onset) is checked too. The other friction laws are
  smooth functions of u̇_b (and z) in the right-hand side.
* **Yielding stories.** Bouc–Wen stories carry ζ and ε as states. A piecewise-linear story
  (``bilinear``, ``takeda``, ``imk``) has a terminal event at each reversal of its drift (δ̇ = 0
  against its motion); its kernel state is committed at every restart, so between reversals its
  force is the kernel's exact answer for the monotone drift since then, kinks (yield, zero-force
  crossing, reloading onto the backbone) included, and its work ∫F dδ is a state. An IMK story
  whose capacity its next reversal or zero-force crossing spends has that point as a terminal
  event: there its building has collapsed and the analysis ends (``info["stopped_at"]``), as the
  Newmark integrators end in the step that holds it.

Peaks are taken from the dense output at :data:`SAMPLES_PER_STEP` points inside every accepted solver
step, plus the step ends and the event points, not only on the output grid; the contact force and
penetration peaks are then refined by a bounded search on the dense output around the largest sample.

References
----------
.. [1] Virtanen, P. et al. (2020). SciPy 1.0: fundamental algorithms for scientific computing in Python.
   Nature Methods 17, 261-272. doi:10.1038/s41592-019-0686-2
.. [2] Hairer, E., Nørsett, S.P., Wanner, G. (1993). Solving Ordinary Differential Equations I, 2nd ed.
   Springer. Sec. II.5 (DOP853), II.6 (dense output), II.4 (step-size control).
.. [3] Uang, C.-M., Bertero, V.V. (1990). Evaluation of seismic energy in structures. Earthquake Eng.
   Struct. Dyn. 19(1), 77-90. doi:10.1002/eqe.4290190108
"""

from __future__ import annotations

import math

import numpy as np

from pounding.errors import IntegrationError, PoundingInputError
from pounding.ground_motion import GroundMotion
from pounding.integrators._families import gather
from pounding.integrators._kernels import (
    BILINEAR_ID,
    FAMILY_STORY,
    bilinear_rate,
    bouc_wen_rate,
    bouc_wen_story_rate,
    contact_eval,
    contact_stored_energy,
    element_eval,
    element_stored,
    friction_eval,
    friction_hysteretic_eval,
    jit,
)
from pounding.integrators.base import (
    ENERGY_TERMS,
    IMPACT_FIELDS,
    RawResult,
    path_table,
    response_scales,
    v0_floor,
)
from pounding.stories import N_STORY_STATE, SS_FAILED, STORY_MODELS, imk_failure_ahead
from pounding.system import FRICTION_BOUC_WEN, FRICTION_COULOMB, PoundingSystem

#: Kernel id of the Bouc–Wen story model (its ζ and ε are ODE states here).
BOUC_WEN_STORY = STORY_MODELS["bouc_wen"].kernel_id

#: solve_ivp methods this path accepts.
IVP_METHODS = ("RK45", "DOP853", "Radau", "BDF", "LSODA")

#: Points per accepted solver step at which the dense output is sampled for the peaks.
SAMPLES_PER_STEP = 16

_EPS = np.finfo(float).eps


# --------------------------------------------------------------------------------------------------
# Compiled contact evaluation over elements (plain arrays)
# --------------------------------------------------------------------------------------------------


#: contact_eval's Python source (it calls the compiled laws), for the few calls made from Python.
_contact_eval_py = getattr(contact_eval, "py_func", contact_eval)


@jit
def _element_forces(law, params, d, dd, v0, fstate, force, rate):
    """Force [N] of every element, and dF/dt [N/s] of the bilinear force states (0 elsewhere)."""
    for c in range(law.size):
        if law[c] == BILINEAR_ID:
            force[c] = max(fstate[c], 0.0) if d[c] > 0.0 else 0.0
            rate[c] = bilinear_rate(d[c], dd[c], fstate[c], params[c])
        else:
            # the law's parameters as a tuple, as the Newmark loop passes them (gap_force): an
            # array row would compile every law a second time
            p = params
            pc = (p[c, 0], p[c, 1], p[c, 2], p[c, 3], p[c, 4], p[c, 5], p[c, 6], p[c, 7])
            force[c] = contact_eval(law[c], d[c], dd[c], v0[c], 0.0, 0.0, pc)[0]
            rate[c] = 0.0


@jit
def _friction_forces(v, z, fr_dof, fr_kind, fr_law, fr_params, fr_bw, fr_normal, fr_stuck, fr_dir,
                     fr_bwi, force, zdot):  # fmt: skip
    """Friction force [N] of every element that is not stuck, and ż of the Bouc-Wen variables."""
    for k in range(fr_dof.size):
        vb = v[fr_dof[k]]
        if fr_kind[k] == FRICTION_COULOMB:
            force[k] = 0.0 if fr_stuck[k] else fr_dir[k] * fr_params[k, 1] * fr_normal[k]
        elif fr_kind[k] == FRICTION_BOUC_WEN:
            j = fr_bwi[k]
            force[k] = friction_hysteretic_eval(fr_law[k], vb, fr_normal[k], z[j], fr_params[k])[0]
            zdot[j] = bouc_wen_rate(z[j], vb, fr_bw[k])[0]
        else:
            force[k] = friction_eval(fr_law[k], vb, fr_normal[k], fr_params[k])[0]


@jit
def _rhs_kernel(t, y, dy, b, gap, law, params, v0, bil, a_k, a_c, a_b, iota, m_iota, cmat, ag, ws,
                fr_dof, fr_kind, fr_law, fr_params, fr_bw, fr_normal, fr_minv, fr_stuck, fr_dir,
                fr_bwi, fr_ws):  # fmt: skip
    """dy/dt of the first-order form (layout of :class:`_Model`); ``ag`` = (a0, slope, t0) of a_g.

    ``fr_ws[0]`` receives each friction element's force (the holding force p of a stuck slab)."""
    n = iota.size
    ne = gap.size
    nb = bil.size
    d, dd, fstate, force, rate = ws[0], ws[1], ws[2], ws[3], ws[4]
    for c in range(ne):
        s = 0.0
        sd = 0.0
        for j in range(n):
            s += b[c, j] * y[j]
            sd += b[c, j] * y[n + j]
        d[c] = s - gap[c]
        dd[c] = sd
    for k in range(nb):
        fstate[bil[k]] = y[2 * n + k]
    _element_forces(law, params, d, dd, v0, fstate, force, rate)
    a_g = ag[0] + ag[1] * (t - ag[2])
    e_in = 0.0
    e_damp = 0.0
    for i in range(n):
        dy[i] = y[n + i]
        acc = -iota[i] * a_g
        cv = 0.0
        for j in range(n):
            acc -= a_k[i, j] * y[j] + a_c[i, j] * y[n + j]
            cv += cmat[i, j] * y[n + j]
        for c in range(ne):
            acc -= a_b[i, c] * force[c]
        dy[n + i] = acc
        e_in -= y[n + i] * m_iota[i] * a_g
        e_damp += y[n + i] * cv
    work = 0.0
    for k in range(nb):
        dy[2 * n + k] = rate[bil[k]]
    for c in range(ne):
        dy[2 * n + nb + c] = force[c]
        work += force[c] * dd[c]
    nz = 0
    work_f = 0.0
    if fr_dof.size:
        iz = 2 * n + nb + ne
        nz = fr_ws.shape[1] - fr_dof.size
        fforce = fr_ws[0, : fr_dof.size]
        zdot = fr_ws[0, fr_dof.size :]
        _friction_forces(y[n : 2 * n], y[iz : iz + nz], fr_dof, fr_kind, fr_law, fr_params, fr_bw,
                         fr_normal, fr_stuck, fr_dir, fr_bwi, fforce, zdot)  # fmt: skip
        for k in range(fr_dof.size):
            i = fr_dof[k]
            if fr_stuck[k]:
                # held at rest: the friction is the force p = m_b ü_b(free) that keeps it there
                fforce[k] = dy[n + i] / fr_minv[k]
                dy[n + i] = 0.0
                dy[i] = 0.0
            else:
                dy[n + i] -= fr_minv[k] * fforce[k]
                work_f += fforce[k] * y[n + i]
        for j in range(nz):
            dy[iz + j] = zdot[j]
    base = 2 * n + nb + ne + nz
    dy[base] = e_in
    dy[base + 1] = e_damp
    dy[base + 2] = work
    if fr_dof.size:
        dy[base + 3] = work_f


@jit
def _sampled_forces(law, params, d, dd, v0, fstate):
    """Forces [N] and stored energies [J], shape (samples, elements), at many states of one phase."""
    ns, ne = d.shape
    force = np.zeros((ns, ne))
    stored = np.zeros((ns, ne))
    rate = np.zeros(ne)
    for i in range(ns):
        _element_forces(law, params, d[i], dd[i], v0, fstate[i], force[i], rate)
        for c in range(ne):
            stored[i, c] = contact_stored_energy(law[c], d[i, c], force[i, c], params[c])
    return force, stored


# --------------------------------------------------------------------------------------------------
# Options
# --------------------------------------------------------------------------------------------------


def _validate(
    method: str, rtol: float, atol: float | None, max_step: float | None, output_times
) -> tuple[str, float, float | None, float, np.ndarray]:
    if not isinstance(method, str) or method.upper() not in {m.upper() for m in IVP_METHODS}:
        raise PoundingInputError(f"ivp method = {method!r}; allowed: {', '.join(IVP_METHODS)}")
    method = next(m for m in IVP_METHODS if m.upper() == method.upper())
    rtol = float(rtol)
    if not (math.isfinite(rtol) and 100.0 * _EPS <= rtol < 1.0):
        raise PoundingInputError(
            f"rtol = {rtol}; allowed: a relative tolerance in [{100 * _EPS:.3g}, 1)"
        )
    if atol is not None:
        atol = float(atol)
        if not (math.isfinite(atol) and atol > 0.0):
            raise PoundingInputError(
                f"atol = {atol}; allowed: a positive absolute tolerance [m] or None"
            )
    if max_step is None:
        max_step = math.inf
    else:
        max_step = float(max_step)
        if not (max_step > 0.0) or math.isnan(max_step):
            raise PoundingInputError(f"max_step = {max_step}; allowed: a positive step [s] or None")
    times = np.asarray(output_times, dtype=float)
    if times.ndim != 1 or times.size == 0:
        raise PoundingInputError(
            f"output_times has shape {times.shape}; allowed: a non-empty 1-D array of times [s]"
        )
    if not np.all(np.isfinite(times)) or times[0] < 0.0:
        raise PoundingInputError(
            f"output_times starts at {times[0]} s; allowed: finite times >= 0 [s] (t = 0 is rest)"
        )
    if times.size > 1 and not np.all(np.diff(times) > 0.0):
        i = int(np.flatnonzero(np.diff(times) <= 0.0)[0])
        raise PoundingInputError(
            f"output_times[{i + 1}] = {times[i + 1]} s after {times[i]} s; allowed: strictly "
            "increasing times"
        )
    return method, rtol, atol, max_step, times


# --------------------------------------------------------------------------------------------------
# The first-order model
# --------------------------------------------------------------------------------------------------


@jit
def _story_rhs(y, dy, n, i0, dof, sign, law, params, committed, trial, minv):
    """Yielding stories (pounding.stories; states from index i0: ζ_e then ε_e of each story):
    dy[n:2n] −= M⁻¹ Bᵀ (F − k δ) (K holds k δ). Bouc–Wen: ζ̇ = δ̇/δ_y g with the kernel's own
    rate g, ε̇ = (1 − α) δ̇ ζ/δ_y. A piecewise-linear model (bilinear, takeda, imk): F from its kernel
    for the monotone drift increment since its committed state (the last reversal, an event), and
    ε̇ = F δ̇/(F_y δ_y), its work normalised (ζ stays 0)."""
    ns = dof.shape[0]
    for e in range(ns):
        d, dd = gather(dof, sign, e, y[:n], y[n : 2 * n])
        k, fy = params[e, 0], params[e, 1]
        dy_ = fy / k
        if law[e] == BOUC_WEN_STORY:
            al = params[e, 2]
            z = y[i0 + e]
            corr = al * k * d + (1.0 - al) * fy * z - k * d
            g = bouc_wen_story_rate(z, y[i0 + ns + e], 1.0 if dd >= 0.0 else -1.0, params, e)
            dy[i0 + e] = dd / dy_ * g
            dy[i0 + ns + e] = (1.0 - al) * dd * z / dy_
        else:
            corr = element_eval(
                FAMILY_STORY, law[e], d, dd, 0.0, committed[e], trial[e], params[e]
            )[0]
            dy[i0 + e] = 0.0
            dy[i0 + ns + e] = (corr + k * d) * dd / (fy * dy_)
        for s in range(dof.shape[1]):
            i = dof[e, s]
            if i >= 0:
                dy[n + i] -= minv[i] * sign[e, s] * corr


@jit
def _story_samples(d, law, params, committed, trial, f, extra):
    """Force F [N] and recoverable energy beyond k δ²/2 [J] of the piecewise-linear stories at drifts
    d (samples × stories) from their committed states (Bouc–Wen columns are left alone)."""
    for i in range(d.shape[0]):
        for e in range(d.shape[1]):
            if law[e] != BOUC_WEN_STORY:
                corr = element_eval(
                    FAMILY_STORY, law[e], d[i, e], 0.0, 0.0, committed[e], trial[e], params[e]
                )[0]
                f[i, e] = corr + params[e, 0] * d[i, e]
                extra[i, e] = element_stored(
                    FAMILY_STORY, law[e], d[i, e], f[i, e], trial[e], params[e]
                )


def _story_values(u: np.ndarray, ys: np.ndarray, model: _Model) -> tuple[np.ndarray, ...]:
    """(F, F − k δ, recoverable energy beyond k δ²/2, hysteretic energy) of every yielding story at
    displacements u (samples × n) and story states ys (samples × 2 ns)."""
    st = model.stories
    ns = len(st)
    p = st.params
    k, fy, al = p[:, 0], p[:, 1], p[:, 2]
    d = np.zeros((u.shape[0], ns))
    for s in range(st.sign.shape[1]):
        dof = st.dof[:, s]
        hit = dof >= 0
        d[:, hit] += st.sign[hit, s] * u[:, dof[hit]]
    z, eps = ys[:, :ns], ys[:, ns:]
    dy_ = fy / k
    f = al * k * d + (1.0 - al) * fy * z
    stored = 0.5 * al * k * d * d + 0.5 * (1.0 - al) * fy * dy_ * z * z
    e_h = eps * fy * dy_ - 0.5 * (1.0 - al) * fy * dy_ * z * z
    extra = stored - 0.5 * k * d * d
    if model.st_pl.size:
        trial = np.zeros_like(model.st_committed)
        _story_samples(
            np.ascontiguousarray(d), model.st_law, p, model.st_committed, trial, f, extra
        )
        pl = model.st_pl
        # ε of a piecewise-linear story is its work over F_y δ_y: E_h = W − recoverable
        e_h[:, pl] = eps[:, pl] * (fy * dy_)[pl] - (extra + 0.5 * k * d * d)[:, pl]
    return f, f - k * d, extra, e_h


class _Model:
    """State layout, right-hand side and derived quantities of a system (one object per run)."""

    def __init__(self, system: PoundingSystem):
        el = system.elements
        n = system.n_dof
        ne = len(el)
        self.n, self.ne = n, ne
        # B from the system's own penetration map (δ of unit displacements), so the sign convention
        # stays in system.py: δ(e_j) = B[:, j] − g.
        unit_delta, _ = system.penetration(np.eye(n), np.zeros((n, n)))
        self.B = np.ascontiguousarray((unit_delta + el.el_gap).T).reshape(ne, n)
        self.gap = np.asarray(el.el_gap, dtype=float)
        self.law = np.ascontiguousarray(el.el_law, dtype=np.int64)
        self.params = np.ascontiguousarray(el.el_params, dtype=float)
        self.bil = np.flatnonzero(self.law == BILINEAR_ID)
        nb = self.bil.size
        self.mass = np.asarray(system.mass, dtype=float)
        self.stiffness = np.asarray(system.stiffness, dtype=float)
        self.damping = np.asarray(system.damping, dtype=float)
        self.iota = np.asarray(system.influence, dtype=float)
        self.drift = system.drift
        self.m_iota = self.mass @ self.iota
        minv = np.linalg.inv(self.mass)
        self.a_k = np.ascontiguousarray(minv @ self.stiffness)
        self.a_c = np.ascontiguousarray(minv @ self.damping)
        self.a_b = np.ascontiguousarray(minv @ self.B.T)
        # friction elements (isolated buildings' bearings); M is diagonal (lumped masses), so a
        # friction force acts on its base dof's equation alone
        fr = system.friction
        self.nf = nf = len(fr)
        if nf and np.count_nonzero(self.mass - np.diag(np.diag(self.mass))):
            raise PoundingInputError(
                "the ivp path with isolation bearings needs a diagonal mass matrix"
            )
        self.fr_dof = np.ascontiguousarray(fr.fr_dof, dtype=np.int64)
        self.fr_kind = np.ascontiguousarray(fr.fr_kind, dtype=np.int64)
        self.fr_law = np.ascontiguousarray(fr.fr_law, dtype=np.int64)
        self.fr_params = np.ascontiguousarray(fr.fr_params, dtype=float)
        self.fr_bw = np.ascontiguousarray(fr.fr_bouc_wen, dtype=float)
        self.fr_normal = np.ascontiguousarray(fr.fr_normal, dtype=float)
        self.fr_minv = 1.0 / np.diag(self.mass)[self.fr_dof]
        self.fr_limit = self.fr_params[:, 0] * self.fr_normal  # μ_s N of the Coulomb elements
        self.coulomb = np.flatnonzero(self.fr_kind == FRICTION_COULOMB)
        hyst = np.flatnonzero(self.fr_kind == FRICTION_BOUC_WEN)
        self.fr_bwi = np.full(nf, -1, dtype=np.int64)
        self.fr_bwi[hyst] = np.arange(hyst.size)
        nz = hyst.size
        # state of each Coulomb slab (per phase): stuck, and the sliding direction
        self.fr_stuck = np.zeros(nf, dtype=np.bool_)
        self.fr_dir = np.ones(nf)
        # state layout
        self.iu = slice(0, n)
        self.iv = slice(n, 2 * n)
        self.ifb = slice(2 * n, 2 * n + nb)
        self.ij = slice(2 * n + nb, 2 * n + nb + ne)
        self.iz = slice(2 * n + nb + ne, 2 * n + nb + ne + nz)
        # W_f only with friction elements (a state more changes the error norm of every run)
        self.i_in, self.i_damp, self.i_work, self.i_fric = 2 * n + nb + ne + nz + np.arange(4)
        self.size = 2 * n + nb + ne + nz + (4 if nf else 3)
        # yielding stories: ζ and ε of each, after everything else (a piecewise-linear model's ε is
        # its normalised work; its kernel state is committed at each reversal of its drift, an event)
        self.stories = st = system.stories
        self.ns = ns = len(st)
        self.ist = slice(self.size, self.size + 2 * ns)
        self.size += 2 * ns
        self.st_minv = 1.0 / np.diag(self.mass)
        self.st_law = np.ascontiguousarray(st.law_id, dtype=np.int64)
        self.st_pl = np.flatnonzero(self.st_law != BOUC_WEN_STORY)
        self.st_committed = np.zeros((ns, N_STORY_STATE))
        self.st_trial = np.zeros((ns, N_STORY_STATE))
        self.st_dir = np.zeros(ns)  # drift direction since the last commit (0: at rest so far)
        # history variables (per contact phase)
        self.v0 = np.zeros(ne)
        self.d_tol = 0.0  # [m], set by tolerances()
        self.v0_floor = 0.0  # [m/s], set by tolerances()
        # a_g(t) = ag[0] + ag[1] (t − ag[2]) on the current ground-motion segment
        self.ag = np.zeros(3)
        self._ws = np.zeros((5, ne))  # workspace of the compiled right-hand side
        self._fr_ws = np.zeros((1, nf + nz))

    def set_ground(self, ground: GroundMotion, ta: float, tb: float) -> None:
        """The linear piece of ``ground.at`` on the open interval (ta, tb) (no sample inside)."""
        h = tb - ta
        t1, t2 = ta + h / 3.0, ta + 2.0 * h / 3.0
        a1, a2 = (float(x) for x in ground.at(np.array([t1, t2])))
        slope = (a2 - a1) / (t2 - t1)
        self.ag[:] = (a1 - slope * (t1 - ta), slope, ta)

    def ground_at(self, t):
        return self.ag[0] + self.ag[1] * (t - self.ag[2])

    def rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        dy = np.empty(self.size)
        _rhs_kernel(
            t, y, dy, self.B, self.gap, self.law, self.params, self.v0, self.bil, self.a_k,
            self.a_c, self.a_b, self.iota, self.m_iota, self.damping, self.ag, self._ws,
            self.fr_dof, self.fr_kind, self.fr_law, self.fr_params, self.fr_bw, self.fr_normal,
            self.fr_minv, self.fr_stuck, self.fr_dir, self.fr_bwi, self._fr_ws,
        )  # fmt: skip
        if self.ns:
            st = self.stories
            _story_rhs(
                y, dy, self.n, self.ist.start, st.dof, st.sign, self.st_law, st.params,
                self.st_committed, self.st_trial, self.st_minv,
            )  # fmt: skip
        return dy

    def friction_now(self, t: float, y: np.ndarray) -> np.ndarray:
        """Friction force [N] of every element at (t, y); the holding force p of a stuck slab."""
        self.rhs(t, y)
        return self._fr_ws[0, : self.nf].copy()

    def holding_force(self, t: float, y: np.ndarray, k: int) -> float:
        """Force p [N] that holds slab k at rest at (t, y) (m_b ü_b = p − f), whatever its state."""
        stuck = bool(self.fr_stuck[k])
        self.fr_stuck[k] = True
        try:
            return float(self.friction_now(t, y)[k])
        finally:
            self.fr_stuck[k] = stuck

    def story_drifts(self, x: np.ndarray) -> np.ndarray:
        """Story drifts [m] (or drift rates) of the yielding stories from floor values x."""
        st = self.stories
        out = np.zeros(self.ns)
        for s in range(st.sign.shape[1]):
            hit = st.dof[:, s] >= 0
            out[hit] += st.sign[hit, s] * x[st.dof[hit, s]]
        return out

    def commit_stories(self, y: np.ndarray) -> None:
        """Commit the piecewise-linear stories' kernel states at y (the start of a solver call: after
        a reversal, or any other restart) and give a direction to those that start moving."""
        if not self.st_pl.size:
            return
        d = self.story_drifts(y[self.iu])
        dd = self.story_drifts(y[self.iv])
        p = self.stories.params
        for e in self.st_pl:
            element_eval(
                FAMILY_STORY, self.st_law[e], d[e], dd[e], 0.0, self.st_committed[e],
                self.st_trial[e], p[e],
            )  # fmt: skip
            self.st_committed[e] = self.st_trial[e]
            if self.st_dir[e] == 0.0 and dd[e] != 0.0:
                self.st_dir[e] = math.copysign(1.0, dd[e])

    def story_failures(self) -> tuple[list[int], list[tuple[int, float, float]]]:
        """IMK stories at their committed state: the rows failed, or failing at the start of their
        next increment (a reversal that spends the unloading stiffness: the force drops to zero
        there); and (row, drift z [m], direction) of those whose next zero-force crossing, at z,
        spends a capacity (a terminal event)."""
        imk = STORY_MODELS["imk"].kernel_id
        now, ahead = [], []
        for e in self.st_pl[self.st_law[self.st_pl] == imk]:
            m = self.st_dir[e]
            if m == 0.0 and not self.st_committed[e, SS_FAILED]:
                continue
            spent, z = imk_failure_ahead(self.st_committed[e], self.stories.params[e], m)
            if spent:
                now.append(int(e))
            elif math.isfinite(z):
                ahead.append((int(e), z, float(m)))
        return now, ahead

    def failure_events(self, ahead: list[tuple[int, float, float]]) -> list:
        """Terminal events: a story's drift reaching the zero-force drift z where it fails."""
        events = []
        for e, z, m in ahead:

            def event(t, y, e=e, z=z):
                return float(self.story_drifts(y[self.iu])[e]) - z

            event.terminal, event.direction = True, m
            events.append(event)
        return events

    def element_value(self, y: np.ndarray, c: int, key: str) -> float:
        """Penetration δ [m] (key "d") or contact force [N] (key "force") of element c at state y."""
        d = float(self.B[c] @ y[self.iu]) - self.gap[c]
        if key == "d" or d <= 0.0:
            return d if key == "d" else 0.0
        if self.law[c] == BILINEAR_ID:
            return max(float(y[self.ifb.start + int(np.searchsorted(self.bil, c))]), 0.0)
        dd = float(self.B[c] @ y[self.iv])
        # the laws as compiled for the loops (a tuple of parameters), dispatched in Python: no
        # compiled entry of contact_eval for this one call
        p = tuple(float(x) for x in self.params[c])
        return float(_contact_eval_py(int(self.law[c]), d, dd, float(self.v0[c]), 0.0, 0.0, p)[0])

    def derived(self, t: np.ndarray, y: np.ndarray) -> dict[str, np.ndarray]:
        """Physical quantities at states ``y`` (state, samples) of the current phase; rows = samples."""
        u = y[self.iu].T
        v = y[self.iv].T
        d = u @ self.B.T - self.gap
        dd = v @ self.B.T
        fstate = np.zeros((t.size, self.ne))
        fstate[:, self.bil] = y[self.ifb].T
        force, stored = _sampled_forces(
            self.law,
            self.params,
            np.ascontiguousarray(d),
            np.ascontiguousarray(dd),
            self.v0,
            fstate,
        )
        ag = self.ground_at(t)
        acc = -(u @ self.a_k.T) - (v @ self.a_c.T) - force @ self.a_b.T - np.outer(ag, self.iota)
        friction = np.zeros((t.size, self.nf))
        if self.nf:
            zdot = np.zeros(self.iz.stop - self.iz.start)
            z = y[self.iz].T
            row = np.zeros(self.nf)
            for i in range(t.size):
                _friction_forces(
                    v[i], z[i], self.fr_dof, self.fr_kind, self.fr_law, self.fr_params, self.fr_bw,
                    self.fr_normal, self.fr_stuck, self.fr_dir, self.fr_bwi, row, zdot,
                )  # fmt: skip
                friction[i] = row
            for k, b in enumerate(self.fr_dof):
                if self.fr_stuck[k]:
                    friction[:, k] = acc[:, b] / self.fr_minv[k]
                    acc[:, b] = 0.0
                else:
                    acc[:, b] -= self.fr_minv[k] * friction[:, k]
        story_force = np.zeros((t.size, self.ns))
        strain_extra = np.zeros(t.size)
        hysteretic = np.zeros(t.size)
        if self.ns:
            st = self.stories
            story_force, corr, extra, e_h = _story_values(u, y[self.ist].T, self)
            for s in range(st.dof.shape[1]):
                dof = st.dof[:, s]
                hit = dof >= 0
                np.add.at(
                    acc.T, dof[hit], -(st.sign[hit, s] * corr[:, hit] * self.st_minv[dof[hit]]).T
                )
            strain_extra = extra.sum(axis=1)
            hysteretic = e_h.sum(axis=1)
        stored_sum = stored.sum(axis=1)
        energy = np.column_stack(
            (
                y[self.i_in],
                0.5 * np.einsum("ti,ij,tj->t", v, self.mass, v),
                0.5 * np.einsum("ti,ij,tj->t", u, self.stiffness, u) + strain_extra,
                y[self.i_damp],
                y[self.i_work] - stored_sum,
                stored_sum,
                y[self.i_fric] if self.nf else np.zeros(t.size),
                np.zeros(t.size),  # algorithmic: none, the integration error is controlled instead
                np.zeros(t.size),  # link_dissipated, link_stored: no links on this path
                np.zeros(t.size),
                hysteretic,
            )
        )
        return dict(
            u=u,
            v=v,
            acc=acc,
            abs_acc=acc + np.outer(ag, self.iota),
            drift=self.drift(u),
            d=d,
            dd=dd,
            force=force,
            energy=energy,
            ag=ag,
            friction=friction,
            stick=np.broadcast_to(self.fr_stuck.astype(float), (t.size, self.nf)),
            story_force=story_force,
            story_hysteretic=hysteretic,
        )

    def tolerances(self, system: PoundingSystem, ground: GroundMotion, rtol, atol):
        """Absolute tolerance per state component, and the displacement tolerance [m] it implies.

        Characteristic sizes: velocity v_c = min(PGV, PGA/ω1) (ω1 the lowest natural frequency of any
        building, an isolated one's √(g/R) or, on flat sliders, PGA/PGV included), displacement u_c = min(v_c/ω1, δ*) with δ* = (m̄ v_c²/k)^(1/(n+1)) the smallest
        impact penetration scale of any element (so penetrations, not just floor displacements,
        are resolved), v_c √(m̄ k) for bilinear forces, m̄ v_c for impulses, (Σm) v_c² for energies.
        Each component gets ``rtol`` times its size; a user ``atol`` [m] replaces rtol·u_c and
        scales the others alike.
        """
        v_c, omega1 = response_scales(system, ground)
        if not v_c > 0.0:  # no excitation: any positive scale will do
            v_c = 1e-3 * omega1
        m_el = np.asarray(system.elements.el_mass, dtype=float)
        k_el = self.params[:, 0]
        n_el = np.where(self.law == BILINEAR_ID, 1.0, self.params[:, 1])
        d_star = (m_el * v_c**2 / k_el) ** (1.0 / (n_el + 1.0))
        u_c = float(min(v_c / omega1, d_star.min(initial=math.inf)))
        e_c = float(np.trace(self.mass)) * v_c**2
        scale = np.empty(self.size)
        scale[self.iu] = u_c
        scale[self.iv] = v_c
        scale[self.ifb] = v_c * np.sqrt(m_el[self.bil] * k_el[self.bil])
        scale[self.ij] = m_el * v_c
        scale[self.iz] = 1.0
        scale[self.ist] = 1.0  # ζ (≤ 1 at the yield force) and ε (hysteretic work / F_y δ_y)
        scale[[self.i_in, self.i_damp, self.i_work]] = e_c
        if self.nf:
            scale[self.i_fric] = e_c
        factor = rtol if atol is None else atol / u_c
        # penetrations below ten displacement tolerances are round-off, not contact (see _events)
        self.d_tol = 10.0 * factor * u_c
        self.v0_floor = v0_floor(system, ground)
        return factor * scale, factor * u_c


# --------------------------------------------------------------------------------------------------
# Recording: output grid, peaks, impact log
# --------------------------------------------------------------------------------------------------


class _Recorder:
    def __init__(self, model: _Model, times: np.ndarray, ground: GroundMotion):
        nt, n, ne = times.size, model.n, model.ne
        self.times = times
        self.next = 0  # index of the next output time to fill
        self.out = dict(
            u=np.zeros((nt, n)),
            v=np.zeros((nt, n)),
            acc=np.zeros((nt, n)),
            d=np.zeros((nt, ne)),
            force=np.zeros((nt, ne)),
            energy=np.zeros((nt, len(ENERGY_TERMS))),
            friction=np.zeros((nt, model.nf)),
            stick=np.zeros((nt, model.nf)),
            story_force=np.zeros((nt, model.ns)),
        )
        self.ground = np.asarray(ground.at(times), dtype=float)
        self.peak = dict(
            u=np.zeros(n),
            drift=np.zeros(n),
            abs_acc=np.zeros(n),
            force=np.zeros(ne),
            d=np.zeros(ne),
            story_force=np.zeros(model.ns),
        )
        self.impacts: list[dict[str, float]] = []
        self.open: dict[int, dict[str, float]] = {}

    def fill(self, model: _Model, sol, t_end: float) -> None:
        """Output-grid values for the times not yet filled up to t_end (the end of a solver call)."""
        times = self.times
        lo = self.next
        hi = int(np.searchsorted(times, t_end, side="right"))
        if hi <= lo:
            return
        t = times[lo:hi]
        q = model.derived(t, sol(t))
        for key, arr in self.out.items():
            arr[lo:hi] = q[key]
        self.next = hi

    def track(self, model: _Model, sol, ts: np.ndarray, in_contact: np.ndarray) -> None:
        """Peaks over the dense output sampled inside every step of one solver call."""
        h = np.diff(ts)
        frac = np.arange(SAMPLES_PER_STEP) / SAMPLES_PER_STEP
        t = np.append((ts[:-1, None] + h[:, None] * frac[None, :]).ravel(), ts[-1])
        q = model.derived(t, sol(t))
        pk = self.peak
        np.maximum(pk["u"], np.abs(q["u"]).max(axis=0), out=pk["u"])
        np.maximum(pk["drift"], np.abs(q["drift"]).max(axis=0), out=pk["drift"])
        np.maximum(pk["abs_acc"], np.abs(q["abs_acc"]).max(axis=0), out=pk["abs_acc"])
        if model.ns:
            peak = np.abs(q["story_force"]).max(axis=0)
            np.maximum(pk["story_force"], peak, out=pk["story_force"])
        if not model.ne:
            return
        np.maximum(pk["force"], q["force"].max(axis=0), out=pk["force"])
        np.maximum(pk["d"], q["d"].max(axis=0), out=pk["d"])
        last = t.size - 1
        for c in np.flatnonzero(in_contact):
            rec = self.open[int(c)]
            inside = q["d"][:, c] > 0.0
            rec["_path"].append((q["d"][inside, c], q["force"][inside, c]))
            for key, field, peak in (
                ("force", "peak_force", pk["force"]),
                ("d", "max_penetration", pk["d"]),
            ):
                values = q[key][:, c]
                i = int(np.argmax(values))
                best = float(values[i])
                # refine only a new running maximum that lies inside this call (one still rising at
                # the call's end peaks in the next call)
                if best > rec[field] and i < last:
                    lo, hi = t[max(i - 1, 0)], t[i + 1]
                    best = max(best, _refine_max(model, sol, lo, hi, int(c), key))
                rec[field] = max(rec[field], best)
                peak[c] = max(peak[c], best)

    def close_contact(self, c: int, t: float, dd: float, impulse: float) -> None:
        rec = self.open.pop(c)
        rec.update(end=t, v_end=dd, impulse=impulse - rec.pop("_j0"))
        self.impacts.append(rec)

    def open_contact(self, c: int, t: float, v0: float, impulse: float) -> None:
        self.open[c] = dict(
            element=c,
            start=t,
            end=math.nan,
            v0=v0,
            v_end=math.nan,
            peak_force=0.0,
            max_penetration=0.0,
            impulse=math.nan,
            _j0=impulse,
            _path=[(np.zeros(1), np.zeros(1))],  # (penetration, force) samples from the closure
        )

    def impact_log(self, impulse_now: np.ndarray) -> dict[str, np.ndarray]:
        rows = list(self.impacts)
        for c, rec in self.open.items():  # still in contact when the record ends
            rec = dict(rec)
            rec["impulse"] = float(impulse_now[c]) - rec.pop("_j0")
            rows.append(rec)
        rows.sort(key=lambda r: (r["start"], r["element"]))
        log = {f: np.array([r[f] for r in rows], dtype=float) for f in IMPACT_FIELDS}
        log["element"] = log["element"].astype(np.int64)
        paths = [
            tuple(np.concatenate(part) for part in zip(*r["_path"], strict=True)) for r in rows
        ]
        log["path_penetration"], log["path_force"] = path_table(paths)
        return log


def _refine_max(model: _Model, sol, lo: float, hi: float, c: int, key: str) -> float:
    """Largest value of element c's force or penetration found by Brent's search in [lo, hi].

    Only values actually evaluated on the dense output are returned, so a kink (clamped force, law
    switching) cannot make it overshoot.
    """
    from scipy.optimize import minimize_scalar

    res = minimize_scalar(
        lambda tt: -model.element_value(sol(tt), c, key),
        bounds=(lo, hi),
        method="bounded",
        options=dict(xatol=1e-7 * (hi - lo)),
    )
    return -float(res.fun)


# --------------------------------------------------------------------------------------------------
# Driver
# --------------------------------------------------------------------------------------------------


def _breakpoints(ground: GroundMotion, t_end: float) -> np.ndarray:
    """0, every ground sample time inside (0, t_end), t_end: a_g is linear between two of them."""
    inner = ground.time[(ground.time > 0.0) & (ground.time < t_end)]
    return np.concatenate(([0.0], inner, [t_end]))


def _events(model: _Model, in_contact: np.ndarray) -> list:
    """Terminal events: δ_c = ε_δ upward (closure) for an open element, δ_c = 0 downward (separation)
    for a closed one, then the friction events. Then one non-terminal event per element at each
    extremum of δ_c (δ̇_c = 0: a minimum while closed, a maximum while open), which
    :func:`_missed_switch` checks for a separation or closure that fell inside one solver step.

    ε_δ (:attr:`_Model.d_tol`) is the solver's own displacement tolerance: a penetration below it
    carries no force worth an impact (two identical buildings at zero gap stay at δ ≈ 0 by round-off).
    """
    n = model.n
    events = []
    for c in range(model.ne):
        row = model.B[c]
        g = float(model.gap[c]) + (0.0 if in_contact[c] else model.d_tol)

        def event(t, y, row=row, g=g):
            return float(row @ y[:n]) - g

        event.terminal = True
        event.direction = -1.0 if in_contact[c] else 1.0
        events.append(event)
    events += _friction_events(model)
    events += _story_events(model)
    for c in range(model.ne):
        row = model.B[c]

        def extremum(t, y, row=row):
            return float(row @ y[n : 2 * n])

        extremum.terminal = False
        extremum.direction = 1.0 if in_contact[c] else -1.0
        events.append(extremum)
    return events


def _missed_switch(model: _Model, sol, t0: float, in_contact: np.ndarray) -> tuple[float, int]:
    """(time, element) of the earliest separation or closure that happened inside a solver step and
    so gave no sign change of δ at the step ends (a 2 ms dip below zero while in contact, a grazing
    touch while open); (inf, -1) if none.

    Every extremum of δ_c is an event (:func:`_events`); a minimum below −ε_δ while closed (a maximum
    above ε_δ while open) means δ crossed zero since the previous extremum of the same element (or
    the start t0 of this solver call), once. That crossing is located by Brent's method on the dense
    output.
    """
    from scipy.optimize import brentq

    first, which = math.inf, -1
    base = len(sol.t_events) - model.ne
    for c in range(model.ne):
        times, states = sol.t_events[base + c], sol.y_events[base + c]
        lo = t0
        for te, ye in zip(times, states, strict=True):
            d = float(model.B[c] @ ye[: model.n]) - model.gap[c]
            wrong = d < -model.d_tol if in_contact[c] else d > model.d_tol
            if wrong:
                if te < first:
                    sign = 1.0 if in_contact[c] else -1.0
                    level = model.gap[c] + (0.0 if in_contact[c] else model.d_tol)

                    def f(tt, c=c, level=level, sign=sign):
                        return sign * (float(model.B[c] @ sol.sol(tt)[: model.n]) - level)

                    if f(lo) >= 0.0 > f(te):
                        first, which = brentq(f, lo, te, xtol=1e-14 * max(1.0, te)), c
                break
            lo = te
    return first, which


def _story_events(model: _Model) -> list:
    """One terminal event per piecewise-linear story: its drift rate crossing zero against its
    motion (a reversal, where its kernel state is committed); none yet for a story still at rest."""
    n = model.n
    st = model.stories
    events = []
    for e in model.st_pl:
        rows = [
            (n + int(st.dof[e, s]), float(st.sign[e, s])) for s in range(2) if st.dof[e, s] >= 0
        ]

        def reversal(t, y, rows=rows):
            return sum(sg * y[i] for i, sg in rows)

        def at_rest(t, y):
            return 1.0

        event = reversal if model.st_dir[e] != 0.0 else at_rest
        event.terminal = True
        event.direction = -float(model.st_dir[e])
        events.append(event)
    return events


def _friction_events(model: _Model) -> list:
    """One event per Coulomb slab: u̇_b = 0 against the motion while sliding, μ_s N − |p| = 0 while
    stuck (p the holding force)."""
    events = []
    for k in model.coulomb:
        k = int(k)
        if model.fr_stuck[k]:
            limit = float(model.fr_limit[k])

            def event(t, y, k=k, limit=limit):
                return limit - abs(float(model.friction_now(t, y)[k]))

            event.direction = -1.0
        else:
            i = model.n + int(model.fr_dof[k])

            def event(t, y, i=i):
                return float(y[i])

            event.direction = -float(model.fr_dir[k])
        event.terminal = True
        events.append(event)
    return events


def _stick_slip(model: _Model, y: np.ndarray, t: float, fired: list[int]) -> int:
    """Switch the Coulomb slabs whose event fired at t (indices into ``model.coulomb``), and any other
    slab at its own switching point; returns the number switched.

    A sliding slab that stops gets u̇_b = 0 exactly, then the stick test: it sticks while its holding
    force |p| <= μ_s N, else slides on towards sign(p). A stuck slab whose |p| reaches μ_s N (or jumps
    past it, e.g. at a contact onset) breaks away towards sign(p)."""
    switched = 0
    for j, k in enumerate(model.coulomb):
        k = int(k)
        i = model.n + int(model.fr_dof[k])
        if model.fr_stuck[k]:
            p = model.holding_force(t, y, k)
            if j in fired or abs(p) > model.fr_limit[k]:
                model.fr_stuck[k] = False
                model.fr_dir[k] = 1.0 if p > 0.0 else -1.0
                switched += 1
        elif j in fired or model.fr_dir[k] * y[i] < 0.0:
            y[i] = 0.0
            p = model.holding_force(t, y, k)
            if abs(p) <= model.fr_limit[k]:
                model.fr_stuck[k] = True
            else:
                model.fr_dir[k] = 1.0 if p > 0.0 else -1.0
            switched += 1
    return switched


class SolveIVP:
    """The reference integrator: :func:`scipy.integrate.solve_ivp` with contact events
    (:func:`integrate_ivp`), with its ``method``, ``rtol`` and ``atol``."""

    name = "ivp"

    def __init__(self, method: str = "DOP853", rtol: float = 1e-8, atol: float | None = None):
        if method not in IVP_METHODS:
            raise PoundingInputError(
                f"analysis.ivp_method = {method!r}; allowed: {', '.join(IVP_METHODS)}"
            )
        self.method, self.rtol, self.atol = method, float(rtol), atol

    def integrate(
        self, system: PoundingSystem, ground: GroundMotion, *, output_times: np.ndarray
    ) -> RawResult:
        """:func:`integrate_ivp` with this integrator's options."""
        return integrate_ivp(
            system, ground, output_times=output_times, method=self.method, rtol=self.rtol,
            atol=self.atol,
        )  # fmt: skip


def integrate_ivp(
    system: PoundingSystem,
    ground: GroundMotion,
    *,
    output_times: np.ndarray,
    method: str = "DOP853",
    rtol: float = 1e-8,
    atol: float | None = None,
    max_step: float | None = None,
) -> RawResult:
    r"""Integrate a pounding system from rest with :func:`scipy.integrate.solve_ivp` and contact events.

    Solves :math:`M\ddot u + C\dot u + K u + B^T F(\delta,\dot\delta) = -M\iota\,a_g(t)` (the system
    equation of :mod:`pounding.system`) from u = u̇ = 0 at t = 0 to ``output_times[-1]``, restarting
    the solver at every ground-motion sample and at every gap closure and separation (see the module
    docstring). This is the reference path: accurate and simple rather than fast.

    Parameters
    ----------
    system : PoundingSystem
        Buildings and gap elements (:func:`pounding.system.assemble`).
    ground : GroundMotion
        Ground acceleration, ``ground.at(t)`` [m/s²] (linear between samples, 0 after the record).
    output_times : array_like
        Strictly increasing times [s], >= 0, at which the response is stored.
    method : {"RK45", "DOP853", "Radau", "BDF", "LSODA"}
        solve_ivp method. DOP853 (explicit, order 8) is the default; Radau and BDF are slow here
        because they restart at every sample with a finite-difference Jacobian.
    rtol : float
        Relative tolerance, in [100 ε, 1).
    atol : float, optional
        Absolute tolerance on displacements [m]; the other states get it scaled by their
        characteristic size (:meth:`_Model.tolerances`). Default: ``rtol`` times the smaller of a
        response displacement scale and the impact penetration scale of the stiffest contact.
    max_step : float, optional
        Largest solver step [s]; default unlimited (steps never cross a ground-motion sample).

    Returns
    -------
    RawResult
        On ``output_times``: displacement, velocity and relative acceleration (from the equation of
        motion) per dof, ``ground.at(t)``, the signed penetration δ (negative while open) and the
        contact force per element, and the energy terms (:data:`ENERGY_TERMS`, cumulative).
        Peaks over the dense output of every solver step: |u|, |u_i − u_below|, |ü + a_g| per dof;
        contact force and penetration per element (0 for an element that never closes).
        Impact log (:data:`IMPACT_FIELDS`), one row per impact sorted by start time; ``impulse`` is
        ∫F dt over the impact (up to the end of the run for an impact still open, whose ``end`` and
        ``v_end`` are NaN). ``info``: integrator="ivp", method, rtol, atol (the displacement
        tolerance used [m]), max_step, n_rhs (right-hand-side evaluations), n_events (closures +
        separations), n_steps (accepted steps), n_calls (solve_ivp calls), samples_per_step.

    References
    ----------
    .. [1] Virtanen, P. et al. (2020). SciPy 1.0. Nature Methods 17, 261-272.
       doi:10.1038/s41592-019-0686-2
    .. [2] Hairer, E., Nørsett, S.P., Wanner, G. (1993). Solving Ordinary Differential Equations I,
       2nd ed. Springer.
    """
    _check_ivp_system(system, ground)
    method, rtol, atol, max_step, times = _validate(method, rtol, atol, max_step, output_times)
    model = _Model(system)
    atol_vec, atol_u = model.tolerances(system, ground, rtol, atol)
    rec = _Recorder(model, times, ground)
    t_end = float(times[-1])
    y = np.zeros(model.size)
    in_contact = np.zeros(model.ne, dtype=bool)
    if model.nf:
        # Coulomb slabs start stuck unless the first push already exceeds μ_s N
        model.set_ground(ground, 0.0, float(ground.time[1]) if ground.npts > 1 else 1.0)
        model.fr_stuck[model.coulomb] = True
        _stick_slip(model, y, 0.0, [])
    n_rhs = n_steps = n_calls = n_events = 0
    stalls = 0
    t = 0.0
    first_step: float | None = None

    from scipy.integrate import solve_ivp  # here, not at import: scipy.integrate loads slowly

    # t_end = 0: nothing to integrate, the structure is at rest (the zero-initialised outputs)
    bps = _breakpoints(ground, t_end) if t_end > 0.0 else np.zeros(1)
    stopped, failed = math.nan, []
    for ta, tb in zip(bps[:-1], bps[1:], strict=True):
        model.set_ground(ground, ta, tb)
        while t < tb:
            model.commit_stories(y)
            n_pl = model.st_pl.size
            now, ahead = model.story_failures()
            if now:  # a story failed: its building has collapsed, the analysis ends here
                stopped, failed = t, now
                break
            events = _events(model, in_contact) if model.ne or model.coulomb.size or n_pl else []
            n_base = len(events)
            events += model.failure_events(ahead)
            sol = solve_ivp(
                model.rhs,
                (t, tb),
                y,
                method=method,
                rtol=rtol,
                atol=atol_vec,
                max_step=max_step,
                first_step=None if first_step is None else min(first_step, tb - t),
                events=events or None,
                dense_output=True,
            )
            n_calls += 1
            n_rhs += int(sol.nfev)
            if sol.status < 0:
                raise IntegrationError(
                    f"solve_ivp ({method}) failed at t = {sol.t[-1]:.6g} s: {sol.message}"
                )
            t_new = float(sol.t[-1])
            ts = sol.sol.ts
            t_miss, c_miss = (
                _missed_switch(model, sol, t, in_contact) if model.ne else (math.inf, -1)
            )
            if c_miss >= 0:
                # the state after the missed crossing is wrong: keep the call up to it, restart there
                t_new = t_miss
                ts = np.append(ts[ts < t_miss], t_miss)
            if ts.size > 1 and ts[-1] > ts[0]:
                n_steps += ts.size - 1
                rec.track(model, sol.sol, ts, in_contact)
                rec.fill(model, sol.sol, t_new)
                # carry the last full step into the next segment (no step-size search at each sample)
                first_step = float(np.max(np.diff(ts)))
                stalls = 0
            else:
                stalls += 1
                if stalls > 3 * (model.ne + model.coulomb.size + n_pl) + 3:
                    raise IntegrationError(
                        f"solve_ivp restarts made no progress at t = {t:.9g} s (contact events "
                        "firing at the restart point)"
                    )
            if c_miss >= 0:
                y = np.asarray(sol.sol(t_new), dtype=float).copy()
                t = t_new
                n_events += _switch(model, rec, y, t, in_contact, [c_miss])
                first_step = None
                continue
            y = sol.y[:, -1].copy()
            t = t_new
            hit = (
                [ahead[j][0] for j, te in enumerate(sol.t_events[n_base:]) if te.size]
                if ahead
                else []
            )
            if sol.status == 1 and hit:
                stopped, failed = t, hit
                break
            if sol.status == 1:
                n_fr = model.ne + model.coulomb.size
                n_term = n_fr + n_pl  # the terminal events come first
                fired = [c for c, te in enumerate(sol.t_events[:n_term]) if te.size]
                n_events += _switch(
                    model, rec, y, t, in_contact, [c for c in fired if c < model.ne]
                )
                n_events += _stick_slip(
                    model, y, t, [c - model.ne for c in fired if model.ne <= c < n_fr]
                )
                for c in fired:
                    if c >= n_fr:  # a story's drift reverses: committed at the restart
                        model.st_dir[model.st_pl[c - n_fr]] *= -1.0
                        n_events += 1
                first_step = None  # a new contact phase: let the solver choose its first step
        if failed:
            break

    info = dict(
        integrator="ivp",
        method=method,
        rtol=rtol,
        atol=atol_u,
        max_step=None if math.isinf(max_step) else max_step,
        n_rhs=n_rhs,
        n_events=n_events,
        n_steps=n_steps,
        n_calls=n_calls,
        samples_per_step=SAMPLES_PER_STEP,
        v0_floor=model.v0_floor,
        stopped_at=stopped,
        failed_stories=sorted({int(model.stories.building[e]) for e in failed}),
    )
    return _raw_result(model, rec, times, y, bool(failed), info)


def _check_ivp_system(system: PoundingSystem, ground: GroundMotion) -> None:
    """Refuse what the ivp path does not integrate, naming the methods that do."""
    if not isinstance(system, PoundingSystem):
        raise PoundingInputError(f"system = {type(system).__name__}; allowed: a PoundingSystem")
    if not isinstance(ground, GroundMotion):
        raise PoundingInputError(f"ground = {type(ground).__name__}; allowed: a GroundMotion")
    if len(system.links):
        raise PoundingInputError(
            f"the system has {len(system.links)} coupling link(s); analysis.method = 'ivp' does "
            "not integrate links; allowed with links: newmark, linear_acceleration, hht"
        )
    if len(system.stories) and len(system.friction):
        raise PoundingInputError(
            "analysis.method = 'ivp' does not combine yielding stories with isolation bearings; "
            "allowed: newmark, linear_acceleration, hht"
        )


def _raw_result(
    model: _Model, rec: _Recorder, times: np.ndarray, y: np.ndarray, failed: bool, info: dict
) -> RawResult:
    """The recorder's outputs, peaks and impact log at the final state y (NaN after a collapse)."""
    out = rec.out
    if failed:
        for arr in out.values():
            arr[rec.next :] = np.nan
    return RawResult(
        time=times.copy(),
        displacement=out["u"],
        velocity=out["v"],
        acceleration=out["acc"],
        ground_acceleration=rec.ground,
        penetration=out["d"],
        contact_force=out["force"],
        energy=out["energy"],
        peak_displacement=rec.peak["u"],
        peak_drift=rec.peak["drift"],
        peak_absolute_acceleration=rec.peak["abs_acc"],
        peak_contact_force=rec.peak["force"],
        peak_penetration=rec.peak["d"],
        impacts=rec.impact_log(y[model.ij]),
        friction_force=out["friction"],
        stick=out["stick"],
        story_force=out["story_force"],
        peak_story_force=rec.peak["story_force"],
        story_hysteretic=(_story_values(y[model.iu][None, :], y[model.ist][None, :], model)[3][0]),
        info=info,
    )


def _switch(
    model: _Model,
    rec: _Recorder,
    y: np.ndarray,
    t: float,
    in_contact: np.ndarray,
    fired: list[int],
) -> int:
    """Open or close the contact of the elements whose event fired at t; returns the number switched.

    Other elements are checked too: an open element with δ > 0 and δ̇ > 0 (or a closed one with
    δ < 0 and δ̇ < 0) had its event at the same instant as the one that stopped the solver (ties are
    reported one at a time) and is switched now.
    """
    d = model.B @ y[model.iu] - model.gap
    dd = model.B @ y[model.iv]
    switch = set(fired)
    for c in range(model.ne):
        if (not in_contact[c] and d[c] > 0.0 and dd[c] > 0.0) or (
            in_contact[c] and d[c] < 0.0 and dd[c] < 0.0
        ):
            switch.add(c)
    impulse = y[model.ij]
    for c in sorted(switch):
        if in_contact[c]:
            rec.close_contact(c, t, float(dd[c]), float(impulse[c]))
            in_contact[c] = False
        else:
            model.v0[c] = max(dd[c], model.v0_floor)
            k = np.searchsorted(model.bil, c)
            if k < model.bil.size and model.bil[k] == c:
                y[model.ifb.start + k] = 0.0
            rec.open_contact(c, t, float(dd[c]), float(impulse[c]))
            in_contact[c] = True
    return len(switch)
