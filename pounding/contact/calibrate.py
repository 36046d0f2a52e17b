r"""Contact-law parameters from (k, n, e), effective restitution, and exact calibration.

:func:`contact_parameters` turns the user's parameters into a law's kernel parameter array.
:func:`effective_restitution` simulates one free impact of a mass against a rigid wall with a tight
``solve_ivp`` integration and measures what the law really does: rebound/approach speed ratio, maximum
penetration, peak force, the time the force acts (the contact duration) and the time the bodies
overlap. With ``calibration="exact"`` the law's damping parameter is
solved (Brent's method on that simulation) so that the *clamped* law's effective restitution equals the
requested e; with ``calibration="nominal"`` the literature relation e -> damping is used as published.
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np

from pounding.contact.laws import (
    N_KERNEL_PARAMS,
    ContactLaw,
    bilinear_rate,
    bilinear_stiffnesses,
    get_contact_law,
)
from pounding.errors import PoundingInputError

CALIBRATIONS = ("nominal", "exact")


@dataclasses.dataclass(frozen=True)
class ImpactResult:
    """Outcome of one free impact against a rigid wall.

    Two durations differ for laws whose clamped force ends while the bodies still overlap (``kelvin``,
    ``hertz_kelvin``): once k δ + c δ̇ would turn tensile the force is zero, the mass flies free at
    constant speed, and the overlap δ > 0 closes a little later. The contact duration is the time the
    force acts; the impact log of a simulation (``impact_start`` to ``impact_end``) spans the overlap.

    Attributes
    ----------
    e_effective : float
        Rebound speed / approach speed [-]: the speed when the force ends, which is also the speed at
        separation (no force acts between the two).
    max_penetration : float
        Largest δ [m].
    peak_force : float
        Largest contact force [N].
    force_duration : float
        Time from first touch to the end of the contact force (last instant with F > 0) [s].
    overlap_duration : float
        Time from first touch to separation, δ back to 0 [s]; >= ``force_duration``.
    """

    e_effective: float
    max_penetration: float
    peak_force: float
    force_duration: float
    overlap_duration: float = math.nan

    @property
    def contact_duration(self) -> float:
        """Contact duration [s]: the time the force acts (= ``force_duration``)."""
        return self.force_duration

    def as_dict(self) -> dict[str, float]:
        """Fields plus ``contact_duration`` (= ``force_duration``), the ``--json`` keys."""
        out = dataclasses.asdict(self)
        out["contact_duration"] = self.contact_duration
        return out


def _positive(value: float | None, field: str, law: str, allowed: str = "> 0") -> float:
    if value is None:
        raise PoundingInputError(f"law {law!r} needs {field} ({allowed})")
    value = float(value)
    if not (math.isfinite(value) and value > 0.0):
        raise PoundingInputError(f"law {law!r}: {field} = {value}; allowed: {allowed}")
    return value


def _pack(
    law: ContactLaw,
    k: float,
    n: float,
    value: float,
    mass: float | None,
    a: float,
    delta_m: float | None,
) -> np.ndarray:
    """Kernel parameters of ``law`` with its damping parameter set to ``value`` (natural form)."""
    p = np.zeros(N_KERNEL_PARAMS)
    if law.is_bilinear:
        p[:3] = bilinear_stiffnesses(k=k, n=n, e=1.0, a=a, delta_m=delta_m, dissipation=value)
        return p
    p[0], p[1] = k, n
    if law.damping == "xi" and law.name not in ("jankowski", "filler"):
        p[2] = 2.0 * value * math.sqrt(k * mass)
    elif law.has_damping:
        p[2] = value
    p[3] = 0.0 if mass is None else mass
    return p


def _validate(
    law: ContactLaw,
    *,
    k: float,
    e: float | None,
    n: float | None,
    mass: float | None,
    a: float,
    delta_m: float | None,
    calibration: str,
) -> tuple[float, float, float | None, float | None]:
    name = law.name
    k = _positive(k, "k", name, "> 0 [N/m^n]")
    if calibration not in CALIBRATIONS:
        raise PoundingInputError(
            f"calibration = {calibration!r}; allowed: {', '.join(CALIBRATIONS)}"
        )
    if n is None:
        n = law.default_n
    elif not law.has_exponent and float(n) != 1.0:
        raise PoundingInputError(
            f"law {name!r} is linear in δ and takes no exponent n (got n = {n})"
        )
    n = float(n)
    if not (math.isfinite(n) and 1.0 <= n <= 3.0):
        raise PoundingInputError(f"law {name!r}: n = {n}; allowed: 1 <= n <= 3 (3/2 for Hertz)")
    if law.has_damping:
        e = _positive(e, "e", name, "0 < e <= 1")
        if e > 1.0:
            raise PoundingInputError(f"law {name!r}: e = {e}; allowed: 0 < e <= 1")
    if law.damping in ("xi", "zeta") or (calibration == "exact" and law.has_damping):
        mass = _positive(mass, "mass (effective mass m̄ of the impact)", name, "> 0 [kg]")
    if law.is_bilinear:
        if not (0.0 < float(a) < 1.0):
            raise PoundingInputError(f"law {name!r}: a = {a}; allowed: 0 < a < 1 (about 0.1)")
        delta_m = _positive(delta_m, "delta_m (expected maximum penetration)", name, "> 0 [m]")
    return k, n, e, mass, delta_m


def contact_parameters(
    law: str | ContactLaw,
    *,
    k: float,
    e: float | None = None,
    n: float | None = None,
    mass: float | None = None,
    a: float = 0.1,
    delta_m: float | None = None,
    calibration: str = "nominal",
    v0: float | None = None,
    bumper: tuple[float, float, float, float] | None = None,
    filler: tuple[float, float, float] | None = None,
) -> np.ndarray:
    """Kernel parameter array of a contact law.

    Parameters
    ----------
    law : str or ContactLaw
        Registry name (see :data:`pounding.contact.laws.CONTACT_LAWS`).
    k : float
        Contact stiffness [N/m^n] (k_h for the Hertz family, [N/m] for the linear family).
    e : float, optional
        Nominal coefficient of restitution, 0 < e <= 1; required by laws with damping.
    n : float, optional
        Exponent of δ; default 3/2 for the Hertz family, fixed at 1 for the linear family.
    mass : float, optional
        Effective mass m̄ = m1 m2/(m1 + m2) [kg] (m for a wall); required by ``kelvin``,
        ``kelvin_approach``, ``jankowski``, ``hertz_kelvin`` and by every exact calibration.
    a : float
        Bilinear yield fraction δ_y/δ_m (about 0.1).
    delta_m : float, optional
        Bilinear expected maximum penetration [m].
    calibration : {"nominal", "exact"}
        ``exact`` solves the damping so the clamped law's effective restitution equals e.
    v0 : float, optional
        Impact speed [m/s] at which the bilinear loop is calibrated exactly; default: the speed at
        which an undamped k δ^n contact reaches δ_m. (The other laws are self-similar in v0.)
    bumper : (thickness [m], k_rubber [N/m^n], e_rubber, crush), optional
        The rubber layer of ``bumper`` (required by it, refused by the others): the crushed contact
        (k, e) starts at the compression crush × thickness.
    filler : (k_filler [N/m], c_filler [N s/m], d_thr [m]), optional
        The viscoelastic filler of ``filler`` (required by it, refused by the others): the crushed
        contact (k, e, Jankowski's) starts at the compression d_thr.
    """
    law = get_contact_law(law)
    k, n, e, mass, delta_m = _validate(
        law, k=k, e=e, n=n, mass=mass, a=a, delta_m=delta_m, calibration=calibration
    )
    if law.is_bumper:
        if bumper is None:
            raise PoundingInputError(
                "law 'bumper' needs thickness [m], k_rubber [N/m^n] and e_rubber (0 < e <= 1)"
            )
        if calibration == "exact":
            raise PoundingInputError(
                "law 'bumper': calibration = 'exact' is not available (two restitutions); "
                "allowed: nominal"
            )
        thickness, k_r, e_r, crush = bumper
        thickness = _positive(thickness, "thickness", law.name, "> 0 [m]")
        k_r = _positive(k_r, "k_rubber", law.name, "> 0 [N/m^n]")
        e_r = _positive(e_r, "e_rubber", law.name, "0 < e <= 1")
        if e_r > 1.0:
            raise PoundingInputError(f"law 'bumper': e_rubber = {e_r}; allowed: 0 < e <= 1")
        crush = _positive(crush, "crush", law.name, "0 < crush <= 1")
        if crush > 1.0:
            raise PoundingInputError(f"law 'bumper': crush = {crush}; allowed: 0 < crush <= 1")
        p = _pack(law, k, n, law.damping_from_e(e), mass, a, delta_m)  # type: ignore[misc]
        p[4], p[5], p[6] = k_r, law.damping_from_e(e_r), crush * thickness  # type: ignore[misc]
        return p
    if law.is_filler:
        if filler is None:
            raise PoundingInputError(
                "law 'filler' needs k_filler [N/m], c_filler [N s/m] and the gap it fills"
            )
        if calibration == "exact":
            raise PoundingInputError(
                "law 'filler': calibration = 'exact' is not available (the filler sets the "
                "rebound); allowed: nominal"
            )
        k_f, c_f, d_thr = (float(v) for v in filler)
        k_f = _positive(k_f, "k_filler", law.name, "> 0 [N/m]")
        if not (math.isfinite(c_f) and c_f >= 0.0):
            raise PoundingInputError(f"law 'filler': c_filler = {c_f}; allowed: >= 0 [N s/m]")
        d_thr = _positive(d_thr, "the filled gap", law.name, "> 0 [m]")
        p = _pack(law, k, n, law.damping_from_e(e), mass, a, delta_m)  # type: ignore[misc]
        p[4], p[5], p[6], p[7] = k_f, c_f, d_thr, 1.0
        return p
    if filler is not None:
        raise PoundingInputError(
            f"law {law.name!r} takes no filler (k_filler, c_filler): use law = 'filler'"
        )
    if bumper is not None:
        raise PoundingInputError(
            f"law {law.name!r} takes no bumper (thickness, k_rubber, e_rubber, crush): use "
            "law = 'bumper'"
        )
    if not law.has_damping:
        return _pack(law, k, n, 0.0, mass, a, delta_m)
    if calibration == "exact" or law.damping_from_e is None:
        value = calibrated_damping(law, k=k, e=e, n=n, mass=mass, a=a, delta_m=delta_m, v0=v0)
    else:
        value = law.damping_from_e(e)
    return _pack(law, k, n, value, mass, a, delta_m)


def _hertz_speed_for(delta_m: float, *, k: float, n: float, mass: float) -> float:
    """Impact speed [m/s] at which an undamped k δ^n contact reaches δ_m (energy balance)."""
    return math.sqrt(2.0 * k * delta_m ** (n + 1.0) / ((n + 1.0) * mass))


def hertz_max_penetration(*, k: float, n: float, mass: float, v0: float) -> float:
    """δ_max [m] of an undamped k δ^n impact at v0: m v0²/2 = k δ^(n+1)/(n+1)."""
    return ((n + 1.0) * mass * v0 * v0 / (2.0 * k)) ** (1.0 / (n + 1.0))


def calibrated_damping(
    law: str | ContactLaw,
    *,
    k: float,
    e: float,
    n: float,
    mass: float,
    a: float = 0.1,
    delta_m: float | None = None,
    v0: float | None = None,
) -> float:
    """The law's damping parameter (natural form) whose clamped free impact returns exactly e.

    Except for the bilinear loop, every law here is self-similar: in units of δ* = (m̄ v0²/k)^(1/(n+1))
    and δ*/v0 the impact depends on the damping parameter alone, so the solution is computed once on a
    unit problem and cached. The bilinear loop is calibrated at ``v0`` [m/s], by default the speed at
    which an undamped contact reaches δ_m.
    """
    law = get_contact_law(law)
    if not law.has_damping or e >= 1.0:
        return 0.0
    if law.is_bilinear:
        if v0 is None:
            v0 = _hertz_speed_for(delta_m, k=k, n=n, mass=mass)
        return _solve_damping(law.name, e, n, k, mass, v0, a, delta_m)
    return _solve_damping(law.name, e, n, 1.0, 1.0, 1.0, a, None)


@functools.lru_cache(maxsize=512)
def _solve_damping(
    name: str, e: float, n: float, k: float, mass: float, v0: float, a: float, delta_m: float | None
) -> float:
    law = get_contact_law(name)

    def residual(value: float) -> float:
        p = _pack(law, k, n, value, mass, a, delta_m)
        return _impact(law, p, mass, v0, k, n).e_effective - e

    hi = law.damping_from_e(e) if law.damping_from_e is not None else 1.0
    hi = max(hi, 1e-3)
    # the bilinear loop keeps K2 > 0 only while its dissipation parameter is below (n + 1)(1 − a)
    cap = (n + 1.0) * (1.0 - a) * (1.0 - 1e-9) if law.is_bilinear else math.inf
    hi = min(hi, cap)
    for _ in range(60):
        if residual(hi) < 0.0:
            break
        hi = min(hi * 2.0, 0.5 * (hi + cap))
    else:
        raise PoundingInputError(
            f"law {name!r}: no damping gives an effective restitution as low as e = {e}"
        )
    from scipy.optimize import brentq  # here, not at import: scipy loads slowly

    return brentq(residual, 0.0, hi, xtol=1e-12, rtol=1e-10)


def _impact(
    law: ContactLaw, p: np.ndarray, mass: float, v0: float, k: float, n: float
) -> ImpactResult:
    """One free impact at speed v0 of ``mass`` against a rigid wall, integrated with DOP853."""
    kernel = law.kernel
    scale_k = p[0] if law.is_bilinear else k
    scale_n = 1.0 if law.is_bilinear else n
    d_star = (mass * v0 * v0 / scale_k) ** (1.0 / (scale_n + 1.0))
    t_star = d_star / v0
    bilinear = law.is_bilinear

    def force(y):
        if bilinear:
            return y[2] if y[0] > 0.0 else 0.0
        return kernel(y[0], y[1], v0, 0.0, 0.0, p)[0]

    def rhs(t, y):
        f = force(y)
        dy = [y[1], -f / mass]
        if bilinear:
            dy.append(bilinear_rate(y[0], y[1], y[2], p))
        return dy

    def separation(t, y):
        return y[0]

    separation.terminal = True
    separation.direction = -1.0

    y0 = [0.0, v0, 0.0] if bilinear else [0.0, v0]
    # start just inside the contact so the separation event does not fire at t = 0
    t_start = 1e-9 * t_star
    y0[0] = v0 * t_start
    from scipy.integrate import solve_ivp  # here, not at import: scipy.integrate loads slowly

    sol = solve_ivp(
        rhs,
        (t_start, 200.0 * t_star),
        y0,
        method="DOP853",
        events=separation,
        dense_output=True,
        rtol=1e-11,
        atol=[1e-13 * d_star, 1e-13 * v0, 1e-13 * scale_k * d_star**scale_n][: len(y0)],
        max_step=0.01 * t_star,
    )
    if not sol.t_events[0].size:
        raise PoundingInputError(
            f"law {law.name!r}: the mass did not separate from the wall within 200 t*"
        )
    t_end = float(sol.t_events[0][0])
    v_end = float(sol.y_events[0][0][1])
    ts = np.linspace(t_start, t_end, 4001)
    ys = sol.sol(ts)
    forces = np.array([force(ys[:, i]) for i in range(ts.size)])
    return ImpactResult(
        e_effective=-v_end / v0,
        max_penetration=float(ys[0].max()),
        peak_force=float(forces.max()),
        force_duration=_force_end(sol.sol, force, ts, forces, t_end),
        overlap_duration=t_end,
    )


def _force_end(dense, force, ts: np.ndarray, forces: np.ndarray, t_end: float) -> float:
    """Last instant [s] with F > 0 before separation at ``t_end``, by bisection on the dense output.

    A clamped force touches zero without changing sign, so it cannot be an event function; once it is
    zero the mass moves freely away from the wall and the force stays zero (δ falls while δ̇ < 0), so
    the instant is where the samples switch from F > 0 to F = 0 for good.
    """
    positive = np.flatnonzero(forces > 0.0)
    if positive.size == 0:
        return float(ts[0])
    i = int(positive[-1])
    if i == ts.size - 1:
        return t_end
    lo, hi = float(ts[i]), float(ts[i + 1])
    while hi - lo > 4.0 * np.spacing(hi):
        mid = 0.5 * (lo + hi)
        if force(dense(mid)) > 0.0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def effective_restitution(
    law: str | ContactLaw,
    *,
    k: float,
    mass: float,
    v0: float,
    e: float | None = None,
    n: float | None = None,
    a: float = 0.1,
    delta_m: float | None = None,
    calibration: str = "nominal",
    bumper: tuple[float, float, float, float] | None = None,
    filler: tuple[float, float, float] | None = None,
) -> ImpactResult:
    """Simulate one free impact of ``mass`` [kg] at ``v0`` [m/s] against a rigid wall.

    Returns the effective restitution (rebound/approach speed), the maximum penetration [m], the peak
    force [N], the time the force acts and the time the bodies overlap [s] of the law at these
    parameters, clamping included (:class:`ImpactResult`; its ``contact_duration`` is the time the
    force acts).
    For two bodies, pass the effective mass m̄ = m1 m2 / (m1 + m2) and the relative approach speed.
    The bilinear loop's δ_m defaults to the undamped Hertz δ_max at this speed, and its exact
    calibration is made at this speed. ``bumper``: the rubber layer of law ``bumper`` (thickness,
    k_rubber, e_rubber, crush; δ is then the layer's compression).
    """
    law = get_contact_law(law)
    v0 = _positive(v0, "v0", law.name, "> 0 [m/s]")
    mass = _positive(mass, "mass", law.name, "> 0 [kg]")
    n_used = law.default_n if n is None else float(n)
    if law.is_bilinear and delta_m is None:
        delta_m = hertz_max_penetration(k=_positive(k, "k", law.name), n=n_used, mass=mass, v0=v0)
    p = contact_parameters(
        law,
        k=k,
        e=e,
        n=n,
        mass=mass,
        a=a,
        delta_m=delta_m,
        calibration=calibration,
        v0=v0,
        bumper=bumper,
        filler=filler,
    )
    # the bumper's rubber sets the impact's scales (its stiff crushed contact comes later, if at all)
    return _impact(law, p, mass, v0, float(p[4] if law.is_bumper else k), n_used)
