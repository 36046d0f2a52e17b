r"""Newmark-family integrators with Newton-Raphson on the contact forces.

An integrator is its coefficients (γ, β, α): :class:`Newmark` (average acceleration, unconditionally
stable, no numerical damping), :class:`LinearAcceleration` and :class:`HHT` (Hilber-Hughes-Taylor α,
numerical damping of high frequencies). The time loop is :func:`pounding.integrators._kernels.newmark_run`,
compiled with numba; it

- solves each step by Newton-Raphson with the consistent tangent of the contact laws
  (∂F/∂δ + γ/(βh) ∂F/∂δ̇ on the gap elements),
- shortens a step that closes a gap so the step ends at the closure (cubic Hermite root of δ), which puts
  the impact time and v0 right,
- halves the step when Newton does not converge (up to ``max_halvings`` times),
- tracks peaks at every step and logs every impact,
- carries the friction of isolated buildings' bearings: regularised laws and Bouc-Wen hysteresis
  in the Newton iteration (tangent γ/(βh) ∂f/∂v, plus ∂f/∂z ∂z/∂u_b), and exact Coulomb stick-slip
  for the ``coulomb`` law: a stuck slab is a constraint (its friction the reaction, a linear step),
  a sliding one carries ±μ_d N (a linear step too); the step ends where a sliding slab comes to
  rest (then the stick test |p| <= μ_s N decides) or where the force holding a stuck one reaches
  μ_s N (break-away), both located to round-off by regula falsi.

The energy ledger is the scheme's own energy identity [3]_. With Δu = u₁ − u₀, averages
x̄ = (x₀ + x₁)/2 and r = M a + C v + K u + Bᵀf + f_friction − p (what a state fails the equation of
motion by: zero for Newmark, the α-weighted lag of HHT), every step satisfies exactly

.. math:: \Delta\big(\tfrac12 v^TMv + \tfrac12 u^TKu\big) = \Delta u^T\bar p - \Delta u^T C\bar v
          - \bar f^T\Delta\delta - \bar f_{fr}^T\Delta u_b - \Delta E_{alg},
          \qquad \Delta E_{alg} = -\Delta u^T\bar r + h^2(\beta - \tfrac{\gamma}{2})\,\Delta a^TM\bar a
          - h(\gamma - \tfrac12)\,\bar v^TM\Delta a

so input, damping, contact and friction work are summed in this work form and ``algorithmic`` is
ΔE_alg (identically zero for average acceleration, γ = ½, β = ¼). The ledger then closes to the
Newton tolerance for every scheme; what remains in ``energy_balance_error`` is a real error.

References
----------
.. [1] Newmark, N.M. (1959). A method of computation for structural dynamics. J. Eng. Mech. Div. 85(3),
   67-94.
.. [2] Hilber, H.M., Hughes, T.J.R., Taylor, R.L. (1977). Improved numerical dissipation for time
   integration algorithms in structural dynamics. Earthquake Eng. Struct. Dyn. 5(3), 283-292.
   doi:10.1002/eqe.4290050306
.. [3] Krenk, S. (2006). Energy conservation in Newmark based time integration algorithms. Comput.
   Methods Appl. Mech. Eng. 195(44-47), 6110-6124. doi:10.1016/j.cma.2005.12.001
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pounding.contact.laws import LAWS_BY_ID
from pounding.errors import PoundingInputError
from pounding.ground_motion import GroundMotion
from pounding.integrators import _kernels as kn
from pounding.integrators.base import (
    ENERGY_TERMS,
    IMPACT_FIELDS,
    PATH_POINTS,
    ConvergenceError,
    RawResult,
    compiled_core,
    response_scales,
    v0_floor,
)
from pounding.links import FAMILY_LINK, N_LINK_PARAMS, N_LINK_STATE
from pounding.stories import (
    FAMILY_STORY,
    N_STORY_PARAMS,
    N_STORY_STATE,
    SS_DIR,
    SS_FAILED,
    SS_W,
    STORY_MODELS,
    imk_failure_ahead,
    story_energy,
)
from pounding.system import PoundingSystem

#: Newton iterations per step and step halvings allowed by default.
MAX_ITER = 25
MAX_HALVINGS = 12


class Newmark:
    """Average (constant) acceleration: γ = 1/2, β = 1/4, α = 0."""

    name = "newmark"
    gamma = 0.5
    beta = 0.25
    alpha = 0.0


class LinearAcceleration(Newmark):
    """Linear acceleration: γ = 1/2, β = 1/6 (stable for h < 0.551 T_min)."""

    name = "linear_acceleration"
    beta = 1.0 / 6.0


class HHT(Newmark):
    """Hilber-Hughes-Taylor α-method: α in [−1/3, 0], γ = (1 − 2α)/2, β = (1 − α)²/4 [2]."""

    name = "hht"

    def __init__(self, alpha: float = -0.05) -> None:
        if not (-1.0 / 3.0 <= alpha <= 0.0):
            raise PoundingInputError(f"hht alpha = {alpha}; allowed: -1/3 <= alpha <= 0")
        self.alpha = float(alpha)
        self.gamma = 0.5 - self.alpha
        self.beta = 0.25 * (1.0 - self.alpha) ** 2


#: Newmark-family schemes by name.
SCHEMES: dict[str, type[Newmark]] = {
    "average_acceleration": Newmark,
    "newmark": Newmark,
    "linear_acceleration": LinearAcceleration,
    "hht": HHT,
}


def get_scheme(scheme: str | Newmark | type[Newmark], **options: float) -> Newmark:
    """A scheme instance from a name, class or instance; unknown names list the valid ones."""
    if isinstance(scheme, Newmark):
        return scheme
    if isinstance(scheme, type) and issubclass(scheme, Newmark):
        return scheme(**options)
    try:
        cls = SCHEMES[str(scheme)]
    except KeyError:
        raise PoundingInputError(
            f"unknown Newmark scheme {scheme!r}; allowed: {', '.join(SCHEMES)}"
        ) from None
    return cls(**options)


def _beta_fn(x: float, y: float) -> float:
    """Euler's beta function B(x, y) = Γ(x) Γ(y) / Γ(x + y) (x, y > 0; no scipy.special import)."""
    return math.exp(math.lgamma(x) + math.lgamma(y) - math.lgamma(x + y))


#: False runs every system on the whole core (:func:`pounding.integrators.base.compiled_core`);
#: the tests compare the two compilations with it.
LEAN_CORE = True


def stiffness_exponent(system: PoundingSystem, c: int) -> float:
    """The exponent n of gap element c's elastic force k δ^n: its law's ``n``, or 1 for the
    bilinear loop (its elastic slope K1, in N/m)."""
    law = LAWS_BY_ID[system.elements.el_law[c]]
    return 1.0 if law.is_bilinear else float(system.elements.el_params[c, 1])


def contact_duration_coefficients(system: PoundingSystem) -> tuple[np.ndarray, np.ndarray]:
    r"""(A, b) per gap element with t_c(v0) = A v0^b, the undamped contact duration [s] at speed v0 [m/s].

    For F = k δ^n and effective mass m̄: δ_max = ((n+1) m̄ v0²/(2k))^(1/(n+1)) and
    t_c = 2 B(1/(n+1), 1/2)/(n+1) · δ_max / v0 (π √(m̄/k) for n = 1; 2.943 δ_max/v0 for n = 3/2).
    The bilinear loop uses its elastic slope K1 (n = 1).
    """
    el = system.elements
    coef = np.empty(len(el))
    expo = np.empty(len(el))
    # a spring soft enough to overflow (k ~ 1e-310) never ends an impact: t_c = inf, no step limit
    with np.errstate(over="ignore", divide="ignore"):
        for c in range(len(el)):
            k = el.el_params[c, 0]
            n = stiffness_exponent(system, c)
            factor = 2.0 * _beta_fn(1.0 / (n + 1.0), 0.5) / (n + 1.0)
            coef[c] = factor * ((n + 1.0) * el.el_mass[c] / (2.0 * k)) ** (1.0 / (n + 1.0))
            expo[c] = 2.0 / (n + 1.0) - 1.0
    return coef, expo


def penetration_tolerance(system: PoundingSystem, ground: GroundMotion, tol: float) -> float:
    """Smallest penetration [m] that counts as contact: 100 Newton tolerances of the response's
    displacement scale u_c = v_c/ω1 (v_c = min(PGV, PGA/ω1), ω1 the lowest natural frequency).

    Newton leaves displacements uncertain by ~tol·u_c, so a penetration below this is round-off, not
    an impact (two identical buildings at zero gap stay at |δ| ~ 1e-11 m); it scales with the
    problem's lengths, so a model scaled in length behaves the same. Closures and separations are
    located to within it.
    """
    v_c, omega1 = response_scales(system, ground)
    u_c = v_c / omega1
    return 100.0 * tol * u_c if u_c > 0.0 else 1e-12


def _contacts_at_failure(
    system: PoundingSystem,
    imp_el: np.ndarray,
    imp_val: np.ndarray,
    counters: np.ndarray,
    d_out: np.ndarray,
    t: float,
    output_step: float,
) -> str:
    """Name the gap elements in contact when Newton failed: impacts still open in the log, else the
    gap that was closest to closing at the last stored output."""
    el = system.elements
    n_imp = min(int(counters[kn.CNT_IMPACTS]), imp_el.size)
    open_ = sorted({int(imp_el[i]) for i in range(n_imp) if np.isnan(imp_val[i, kn.IMP_END])})
    label = "contact"
    if not open_ and len(el):
        row = min(int(t / output_step), d_out.shape[0] - 1)
        open_ = [int(np.argmax(d_out[row]))]
        label = "closing contact"
    names = [
        f"{c} ({el.left[c]}:{int(el.left_floor[c])}-{el.right[c]}:{int(el.right_floor[c])}, "
        f"{el.law[c]})"
        for c in open_
    ]
    return f"{label}{'s' if len(names) > 1 else ''} {', '.join(names)}" if names else "no contact"


def _remedies(
    max_iter: int, max_halvings: int, locate_onset: bool, adaptive: bool, contacts: bool = True
) -> str:
    """What a user can still change after a Newton failure: the options below their defaults (in
    the [analysis] table), then a smaller dt or, with contacts, a softer contact."""
    steps = []
    if max_halvings < MAX_HALVINGS:
        steps.append(f"max_halvings = {MAX_HALVINGS}")
    if max_iter < MAX_ITER:
        steps.append(f"max_iter = {MAX_ITER}")
    if not locate_onset:
        steps.append("locate_onset = true")
    if not adaptive:
        steps.append("adaptive = true")
    options = f"[analysis] {', '.join(steps)}, " if steps else ""
    return f"{options}a smaller dt" + (", or a softer contact k" if contacts else "")


def _f64(x: np.ndarray) -> np.ndarray:
    """C-contiguous, writable float64: one compiled specialisation of the kernels serves every run
    (a read-only array is another numba type, and inside a group it would recompile every kernel
    that takes the group)."""
    return np.require(x, np.float64, ["C", "W"])


def _i64(x: np.ndarray) -> np.ndarray:
    return np.require(x, np.int64, ["C", "W"])


@dataclass(frozen=True)
class ElementFamilyRows:
    """The element-family rows of a system (links, ...): family kind and law id per element, its
    two dofs and signs, parameters; state rows of ``n_state`` columns start at zero."""

    kind: np.ndarray
    law: np.ndarray
    dof: np.ndarray
    sign: np.ndarray
    params: np.ndarray
    n_state: int

    def fresh(self) -> kn.Elements:
        """The compiled core's group, with zeroed committed and trial state."""
        m = len(self.kind)
        z = np.zeros(m)
        return kn.Elements(_i64(self.kind), _i64(self.law), _i64(self.dof), _f64(self.sign),
                           _f64(self.params), np.zeros((m, self.n_state)),
                           np.zeros((m, self.n_state)), z, z.copy(), z.copy(), z.copy(),
                           z.copy(), z.copy(), z.copy(), np.ones(m, dtype=np.bool_))  # fmt: skip


def element_families(system: PoundingSystem) -> ElementFamilyRows:
    """The rows of every element family of ``system`` beyond gaps and friction: the links, then
    the yielding stories; parameters and state as wide as the widest family."""
    families = ((FAMILY_LINK, system.links), (FAMILY_STORY, system.stories))
    width = max(N_LINK_PARAMS, N_STORY_PARAMS)
    dofs = max(f.dof.shape[1] for _, f in families)  # a story on a rocking base has three
    params = np.zeros((sum(len(f) for _, f in families), width))
    row = 0
    for _, f in families:
        params[row : row + len(f), : f.params.shape[1]] = f.params
        row += len(f)
    return ElementFamilyRows(
        kind=np.concatenate([np.full(len(f), kind, dtype=np.int64) for kind, f in families]),
        law=np.concatenate([f.law_id for _, f in families]).astype(np.int64),
        dof=np.vstack([pad_rows(f.dof, dofs, -1) for _, f in families]).astype(np.int64),
        sign=np.vstack([pad_rows(f.sign, dofs, 0.0) for _, f in families]),
        params=params,
        n_state=max(N_LINK_STATE, N_STORY_STATE),
    )


def pad_rows(rows: np.ndarray, width: int, fill: float) -> np.ndarray:
    """Element rows (dofs or signs) widened to ``width`` columns with ``fill`` (−1: no dof, 0)."""
    out = np.full((rows.shape[0], width), fill, dtype=rows.dtype)
    out[:, : rows.shape[1]] = rows
    return out


def collapse_drifts(system: PoundingSystem, limit: float) -> np.ndarray:
    """The drift [m] of each dof's story taken as collapse: ``limit`` × height in the buildings
    that can collapse (yielding stories or P-Δ), inf elsewhere (an elastic story has no strength
    to lose; its drift beyond the ``drift_limit`` is a warning) and at a base slab."""
    h = system.story_height
    can = np.zeros(h.size, dtype=bool)
    for i, b in enumerate(system.buildings):
        can[system.building_dofs(i)] = b.can_collapse
    return np.where(can & (h > 0.0), limit * h, np.inf)


def _collapsed(system: PoundingSystem, peak_drift: np.ndarray, limit: float) -> bool:
    """True when a story that can collapse has a peak drift beyond ``limit`` × its height."""
    return bool(np.any(peak_drift > collapse_drifts(system, limit)))


def _failed_buildings(
    system: PoundingSystem, state: np.ndarray, reversal: bool = False
) -> list[int]:
    """Buildings with an IMK story whose energy capacity is spent in ``state`` (the story rows of
    the committed element state): it carries no force any more, its building has collapsed. With
    ``reversal``, also a story whose next reversal spends it (its unloading stiffness gone: the
    force drops from the peak to zero there, which no step of Newton gets past)."""
    st = system.stories
    spent = (st.law_id == STORY_MODELS["imk"].kernel_id) & (state[:, SS_FAILED] > 0.0)
    if reversal:
        for r in np.flatnonzero((st.law_id == STORY_MODELS["imk"].kernel_id) & ~spent):
            back = -np.sign(state[r, SS_DIR])
            spent[r] = back != 0.0 and imk_failure_ahead(state[r], st.params[r], back)[0]
    return sorted({int(b) for b in st.building[spent]})


def _blank_after(out: kn.Output, output_dt: float, t_end: float) -> None:
    """NaN in the output rows after ``t_end``, which the analysis did not reach."""
    rows = np.arange(out.u.shape[0]) * output_dt > t_end + 1e-9 * output_dt
    for arr in (out.u, out.v, out.a, out.d, out.f, out.e, out.ff, out.st, out.lf):
        arr[rows] = np.nan


def _hysteretic(state: np.ndarray, law: np.ndarray, params: np.ndarray) -> np.ndarray:
    """Hysteretic energy [J] of each story at its committed state: W less the recoverable E."""
    energy = [story_energy(law[r], state[r], params[r]) for r in range(len(state))]
    return state[:, SS_W] - np.array(energy, dtype=float)


def impact_paths(imp_val: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(impact, point) penetration [m] and force [N] of the kernel's step paths, NaN-padded."""
    n = imp_val[:, kn.IMP_NPTS].astype(np.int64)
    pts = imp_val[:, kn.IMP_PATH :].reshape(len(imp_val), PATH_POINTS, 2)
    kept = np.arange(PATH_POINTS)[None, :] < n[:, None]
    return np.where(kept, pts[:, :, 0], np.nan), np.where(kept, pts[:, :, 1], np.nan)


def integrate_newmark(
    system: PoundingSystem,
    ground: GroundMotion,
    *,
    dt: float,
    output_every: int,
    n_steps: int,
    scheme: str | Newmark = "newmark",
    tol: float = 1e-10,
    max_iter: int = MAX_ITER,
    max_halvings: int = MAX_HALVINGS,
    locate_onset: bool = True,
    adaptive: bool = False,
    steps_per_contact: int = 20,
    impact_capacity: int = 4096,
    collapse_drift: float = math.inf,
    core: str | None = None,
) -> RawResult:
    """Integrate ``system`` under ``ground`` from rest with base step ``dt`` [s] for ``n_steps`` steps.

    Output every ``output_every`` base steps. With ``adaptive``, steps inside a contact are shortened to
    resolve each impact by ``steps_per_contact`` steps of its own undamped contact duration at its v0
    (see :func:`contact_duration_coefficients`); base steps are taken while every gap is open.
    The analysis ends when a story's drift ratio passes ``collapse_drift`` or an IMK story spends
    its energy capacity (``info["stopped_at"]``; ``info["failed_stories"]`` the buildings of such
    stories; the output rows after it NaN). Raises :class:`ConvergenceError` when Newton fails even
    after ``max_halvings`` halvings of the step, unless a story is already past ``collapse_drift``
    or has failed. ``core="families"`` runs a system of gaps alone on the whole compiled core
    (:func:`pounding.integrators.base.compiled_core`): an auxiliary run of an analysis with
    families then compiles nothing more.
    """
    sch = get_scheme(scheme)
    n_links = len(system.links)
    if not (dt > 0 and math.isfinite(dt)):
        raise PoundingInputError(f"dt = {dt}; allowed: a positive number [s]")
    el = system.elements
    fr = system.friction
    n, n_el, n_fr = system.n_dof, len(el), len(fr)
    n_out = n_steps // output_every + 1
    floor = v0_floor(system, ground)
    collapse = math.nan
    collapse_at = collapse_drifts(system, collapse_drift)
    families = element_families(system)
    # the rows of the Woodbury update: gaps, then one per friction element (its base dof, sign +1),
    # then the element families
    w = families.dof.shape[1]
    x_dof = np.vstack((pad_rows(el.el_dof, w, -1),
                       pad_rows(np.column_stack((fr.fr_dof, -np.ones(n_fr, dtype=np.int64))), w, -1),
                       families.dof))  # fmt: skip
    x_sign = np.vstack((pad_rows(el.el_sign, w, 0.0),
                        pad_rows(np.column_stack((np.ones(n_fr), np.zeros(n_fr))), w, 0.0),
                        families.sign))  # fmt: skip
    sy = kn.System(_f64(system.mass), _f64(system.damping), _f64(system.stiffness),
                   _f64(system.influence), _i64(system.below), _i64(system.tilt),
                   _f64(system.tilt_height), _f64(ground.acceleration), float(ground.dt),
                   _i64(x_dof), _f64(x_sign))  # fmt: skip
    opts = kn.Options(float(tol), int(max_iter), int(max_halvings), bool(locate_onset),
                      penetration_tolerance(system, ground, tol), float(floor), bool(adaptive),
                      float(steps_per_contact), float(dt))  # fmt: skip
    tc_coef, tc_exp = contact_duration_coefficients(system)
    while True:
        gaps = kn.Gaps(_i64(el.el_dof), _f64(el.el_sign), _f64(el.el_gap), _i64(el.el_law),
                       _f64(el.el_params), tc_coef, tc_exp, np.zeros(n_el, dtype=np.bool_),
                       np.zeros(n_el), np.zeros(n_el), np.zeros(n_el),
                       -np.ones(n_el, dtype=np.int64), np.zeros(n_el), np.zeros(n_el),
                       np.zeros(n_el))  # fmt: skip
        friction = kn.Friction(_i64(fr.fr_dof), _i64(fr.fr_kind), _i64(fr.fr_law),
                               _f64(fr.fr_params), _f64(fr.fr_bouc_wen), _f64(fr.fr_normal),
                               np.zeros((n_fr, kn.N_FS)), np.zeros(n_fr),
                               np.zeros(n_fr, dtype=np.bool_))  # fmt: skip
        m = len(families.kind)
        out = kn.Output(
            np.zeros((n_out, n)), np.zeros((n_out, n)), np.zeros((n_out, n)), np.zeros(n_out),
            np.zeros((n_out, n_el)), np.zeros((n_out, n_el)),
            np.zeros((n_out, len(ENERGY_TERMS))), np.zeros((n_out, n_fr)),
            np.zeros((n_out, n_fr)), np.zeros((n_out, m)), np.zeros(n), np.zeros(n), np.zeros(n),
            np.zeros(n_el), np.zeros(n_el), np.zeros(m), np.zeros(impact_capacity, dtype=np.int64),
            np.zeros((impact_capacity, kn.IMP_COLUMNS)), np.zeros(kn.N_COUNTERS, dtype=np.int64),
            collapse_at,
        )  # fmt: skip
        elements = families.fresh()
        # gaps alone: the core compiled without the friction and element-family code
        lean = compiled_core(system, LEAN_CORE) == "gaps" and core != "families"
        t_reached = kn.newmark_run(sy, kn.Scheme(sch.gamma, sch.beta, sch.alpha), gaps,
                                   None if lean else friction, None if lean else elements, opts,
                                   int(n_steps), int(output_every), out)  # fmt: skip
        imp_el, imp_val, counters = out.imp_el, out.imp_val, out.counters
        status = counters[kn.CNT_STATUS]
        if status == kn.STATUS_IMPACT_LOG_FULL:
            impact_capacity *= 4
            continue
        failed = _failed_buildings(
            system, elements.state[n_links:], reversal=status == kn.STATUS_NO_CONVERGENCE
        )
        if (
            status == kn.STATUS_COLLAPSE
            or failed
            or (
                status == kn.STATUS_NO_CONVERGENCE
                and _collapsed(system, out.peak_drift, collapse_drift)
            )
        ):
            # a building past its collapse drift or with a failed story: the analysis ends
            # there, its result stands
            _blank_after(out, dt * output_every, t_reached)
            collapse = t_reached
        elif status == kn.STATUS_NO_CONVERGENCE:
            where = _contacts_at_failure(
                system, imp_el, imp_val, counters, out.d, t_reached, dt * output_every
            )
            raise ConvergenceError(
                f"Newton-Raphson did not converge at t = {t_reached:.6g} s, {where}, with dt = "
                f"{dt:.3g} s, max_iter = {max_iter} and the step halved up to {max_halvings} times; "
                f"try {_remedies(max_iter, max_halvings, locate_onset, adaptive, n_el > 0)}"
            )
        break
    n_imp = int(counters[kn.CNT_IMPACTS])
    impacts = {"element": imp_el[:n_imp].copy()}
    for j, name in enumerate(IMPACT_FIELDS[1:]):
        impacts[name] = imp_val[:n_imp, j].copy()
    impacts["path_penetration"], impacts["path_force"] = impact_paths(imp_val[:n_imp])
    return RawResult(
        time=dt * output_every * np.arange(n_out),
        displacement=out.u,
        velocity=out.v,
        acceleration=out.a,
        ground_acceleration=out.ag,
        penetration=out.d,
        contact_force=out.f,
        energy=out.e,
        peak_displacement=out.peak_u,
        peak_drift=out.peak_drift,
        peak_absolute_acceleration=out.peak_aabs,
        peak_contact_force=out.peak_f,
        peak_penetration=out.peak_d,
        impacts=impacts,
        friction_force=out.ff,
        stick=out.st,
        link_force=out.lf[:, :n_links],
        peak_link_force=out.peak_lf[:n_links],
        story_force=out.lf[:, n_links:],
        peak_story_force=out.peak_lf[n_links:],
        story_hysteretic=_hysteretic(
            elements.state[n_links:], elements.law[n_links:], elements.params[n_links:]
        ),
        info={
            "integrator": sch.name,
            "gamma": sch.gamma,
            "beta": sch.beta,
            "alpha": sch.alpha,
            "dt": float(dt),
            "n_steps": int(n_steps),
            "n_substeps": int(counters[kn.CNT_SUBSTEPS]),
            "n_newton_iterations": int(counters[kn.CNT_NEWTON]),
            "n_located_onsets": int(counters[kn.CNT_LOCATED]),
            "n_halvings": int(counters[kn.CNT_HALVINGS]),
            "n_friction_events": int(counters[kn.CNT_FRICTION]),
            "adaptive": int(bool(adaptive)),
            "v0_floor": floor,
            "stopped_at": collapse,
            "failed_stories": failed,
        },
    )
