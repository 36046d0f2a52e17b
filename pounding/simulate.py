"""``simulate(...) -> xr.Dataset``: one pounding analysis, from a case or from objects built in Python.

Options are validated before anything is integrated. The default integration step resolves both the
structure and the impacts: at least ``steps_per_period`` steps per shortest natural period and
``steps_per_contact`` steps per estimated contact duration (the undamped duration of each gap element's
law at an approach speed of twice the record's peak ground velocity, at least 0.1 m/s), never more than
the record's own sampling interval. The output step is separate; peaks are tracked at every step.
"""

from __future__ import annotations

import dataclasses
import datetime
import math
from typing import Any

import numpy as np
import xarray as xr
from scipy.special import beta as beta_fn

from pounding._version import __version__
from pounding.contact.laws import LAWS_BY_ID
from pounding.ground_motion import GroundMotion
from pounding.integrators.base import RawResult
from pounding.integrators.ivp import IVP_METHODS, integrate_ivp
from pounding.integrators.newmark import SCHEMES, get_scheme, integrate_newmark
from pounding.results import build_dataset
from pounding.system import PoundingSystem

#: Integration methods by name: the Newmark family (compiled loop) and ``ivp`` (scipy solve_ivp).
METHODS = (*SCHEMES, "ivp")


@dataclasses.dataclass(frozen=True)
class AnalysisOptions:
    """Options of one analysis (the ``[analysis]`` table of a case file).

    Attributes
    ----------
    method : str
        ``newmark`` (average acceleration, default), ``linear_acceleration``, ``hht`` or ``ivp``.
    dt : float or None
        Integration step [s]; None picks one from the periods and contact durations.
    output_dt : float or None
        Output step [s]; default 0.005 s (never smaller than dt).
    duration : float or None
        Analysed time [s]; default the record's duration.
    alpha : float
        HHT α in [−1/3, 0].
    ivp_method : str
        ``solve_ivp`` method for ``method = "ivp"``: RK45, DOP853, Radau, BDF, LSODA.
    rtol, atol : float
        ``solve_ivp`` tolerances.
    tol : float
        Newton tolerance on the displacement increment, relative to max(|u|, 1 mm).
    max_iter, max_halvings : int
        Newton iterations per step; step halvings allowed when Newton fails.
    locate_onset : bool
        Shorten a step that closes a gap so it ends at the closure.
    steps_per_contact, steps_per_period : int
        Resolution used for the default dt.
    """

    method: str = "newmark"
    dt: float | None = None
    output_dt: float | None = None
    duration: float | None = None
    alpha: float = -0.05
    ivp_method: str = "DOP853"
    rtol: float = 1e-8
    atol: float | None = None
    tol: float = 1e-10
    max_iter: int = 25
    max_halvings: int = 12
    locate_onset: bool = True
    steps_per_contact: int = 20
    steps_per_period: int = 20

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise ValueError(f"analysis.method = {self.method!r}; allowed: {', '.join(METHODS)}")
        if self.ivp_method not in IVP_METHODS:
            raise ValueError(
                f"analysis.ivp_method = {self.ivp_method!r}; allowed: {', '.join(IVP_METHODS)}"
            )
        for name in ("dt", "output_dt", "duration", "atol"):
            value = getattr(self, name)
            if value is not None and not (math.isfinite(value) and value > 0):
                raise ValueError(f"analysis.{name} = {value}; allowed: a positive number")
        for name in ("rtol", "tol"):
            value = getattr(self, name)
            if not (math.isfinite(value) and 0 < value < 1):
                raise ValueError(f"analysis.{name} = {value}; allowed: 0 < {name} < 1")
        for name in ("max_iter", "steps_per_contact", "steps_per_period"):
            if int(getattr(self, name)) < 1:
                raise ValueError(f"analysis.{name} = {getattr(self, name)}; allowed: >= 1")
        if int(self.max_halvings) < 0:
            raise ValueError(f"analysis.max_halvings = {self.max_halvings}; allowed: >= 0")
        if self.method == "hht":
            get_scheme("hht", alpha=self.alpha)

    @classmethod
    def from_mapping(cls, options: dict[str, Any]) -> AnalysisOptions:
        """Build from a mapping, naming unknown keys and the allowed ones."""
        allowed = [f.name for f in dataclasses.fields(cls)]
        unknown = sorted(set(options) - set(allowed))
        if unknown:
            raise ValueError(
                f"unknown analysis option(s) {', '.join(unknown)}; allowed: {', '.join(allowed)}"
            )
        return cls(**options)


def _contact_duration_factor(n: float) -> float:
    """t_c v0 / δ_max of an undamped k δ^n impact: 2 ∫₀¹ (1 − x^(n+1))^(-1/2) dx = 2 B(1/(n+1), 1/2)/(n+1)."""
    return 2.0 * beta_fn(1.0 / (n + 1.0), 0.5) / (n + 1.0)


def estimated_contact_durations(system: PoundingSystem, v_approach: float) -> np.ndarray:
    """Undamped contact duration [s] of each gap element at approach speed ``v_approach`` [m/s].

    Linear family: π √(m̄/k); Hertz family: (2 B(1/(n+1), 1/2)/(n+1)) δ_max / v0 with
    δ_max = ((n+1) m̄ v0² / (2k))^(1/(n+1)) (2.943 δ_max/v0 for n = 3/2); bilinear: π √(m̄/K1).
    """
    el = system.elements
    out = np.empty(len(el))
    for c in range(len(el)):
        law = LAWS_BY_ID[el.el_law[c]]
        p = el.el_params[c]
        m = el.el_mass[c]
        n = 1.0 if law.is_bilinear else p[1]
        k = p[0]
        if n == 1.0:
            out[c] = math.pi * math.sqrt(m / k)
        else:
            d_max = ((n + 1.0) * m * v_approach**2 / (2.0 * k)) ** (1.0 / (n + 1.0))
            out[c] = _contact_duration_factor(n) * d_max / v_approach
    return out


def default_time_step(
    system: PoundingSystem,
    ground: GroundMotion,
    *,
    steps_per_contact: int = 20,
    steps_per_period: int = 20,
) -> float:
    """Default integration step [s] (see the module docstring)."""
    pgv = float(np.max(np.abs(np.cumsum(ground.acceleration) * ground.dt)))
    v_approach = max(2.0 * pgv, 0.1)
    candidates = [system.shortest_period() / steps_per_period, ground.dt]
    if len(system.elements):
        candidates.append(
            float(estimated_contact_durations(system, v_approach).min()) / steps_per_contact
        )
    return min(candidates)


def _resolve(case_or_system: Any, ground: GroundMotion | None, options: dict[str, Any]):
    """(system, ground, options, title) from a case object or from a system and a ground motion."""
    if isinstance(case_or_system, PoundingSystem):
        if ground is None:
            raise ValueError("simulate(system, ground): a GroundMotion is required with a system")
        return case_or_system, ground, AnalysisOptions.from_mapping(options), ""
    for attr in ("system", "ground_motion", "analysis"):
        if not hasattr(case_or_system, attr):
            raise TypeError(
                "simulate() takes a case (pounding.load_case) or a PoundingSystem and a GroundMotion"
            )
    analysis = (
        dataclasses.replace(case_or_system.analysis, **options)
        if options
        else case_or_system.analysis
    )
    return (
        case_or_system.system,
        ground if ground is not None else case_or_system.ground_motion,
        analysis,
        getattr(case_or_system, "title", ""),
    )


def simulate(
    case_or_system: Any,
    ground: GroundMotion | None = None,
    **options: Any,
) -> xr.Dataset:
    """Run one pounding analysis and return the results Dataset.

    Parameters
    ----------
    case_or_system : Case or PoundingSystem
        A case from :func:`pounding.load_case`, or a system from :func:`pounding.system.assemble`.
    ground : GroundMotion, optional
        Ground motion (required with a system; overrides the case's record when given).
    **options
        Any field of :class:`AnalysisOptions` (``method``, ``dt``, ``output_dt``, ``duration``, ...).
    """
    system, ground, opts, title = _resolve(case_or_system, ground, options)
    raw, info = run(system, ground, opts)
    provenance = {
        "title": title,
        "pounding_version": __version__,
        "created": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "laws": sorted(set(system.elements.law)),
        "method": opts.method,
        **info,
    }
    return build_dataset(system, ground.starting_from_rest(), raw, provenance=provenance)


def run(
    system: PoundingSystem, ground: GroundMotion, opts: AnalysisOptions
) -> tuple[RawResult, dict]:
    """Integrate with validated options; returns the raw result and the provenance of the step choice."""
    ground = ground.starting_from_rest()
    duration = ground.duration if opts.duration is None else float(opts.duration)
    dt = opts.dt or default_time_step(
        system,
        ground,
        steps_per_contact=opts.steps_per_contact,
        steps_per_period=opts.steps_per_period,
    )
    output_dt = max(opts.output_dt or 0.005, dt)
    every = max(1, math.ceil(output_dt / dt - 1e-9))
    dt = output_dt / every
    n_out = max(1, math.ceil(duration / output_dt - 1e-9))
    info = {
        "dt": dt,
        "output_dt": output_dt,
        "duration": n_out * output_dt,
        "dt_chosen": int(opts.dt is None),
    }
    if opts.method == "ivp":
        raw = integrate_ivp(
            system,
            ground,
            output_times=output_dt * np.arange(n_out + 1),
            method=opts.ivp_method,
            rtol=opts.rtol,
            atol=opts.atol,
        )
    else:
        raw = integrate_newmark(
            system,
            ground,
            dt=dt,
            output_every=every,
            n_steps=n_out * every,
            scheme=get_scheme(opts.method, alpha=opts.alpha)
            if opts.method == "hht"
            else opts.method,
            tol=opts.tol,
            max_iter=opts.max_iter,
            max_halvings=opts.max_halvings,
            locate_onset=opts.locate_onset,
        )
    info.update({k: v for k, v in raw.info.items() if k != "dt"})
    return raw, info
