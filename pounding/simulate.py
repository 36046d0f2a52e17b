"""``simulate(...) -> xr.Dataset``: one pounding analysis, from a case or from objects built in Python.

Options are validated before anything is integrated. Step control of the Newmark family:

- ``adaptive = true`` (default, event-aware): while every gap is open the step is the base step, at
  least ``steps_per_period`` (default 160) per shortest natural period and never more than the
  record's sampling interval; a step that closes a gap ends at the closure; inside a contact the step is the impact's own
  undamped contact duration at its v0 divided by ``steps_per_contact``. The cost of a record follows the
  impacts it has, not a global tiny step.
- ``adaptive = false``: one fixed step everywhere, by default also resolving the contact duration
  estimated at an approach speed of twice the record's peak ground velocity (at least 0.1 m/s).

``dt`` given by the user replaces the base step. The output step is separate and honoured when
given: the step is shortened so that a whole number of steps fills each output interval (without
``output_dt`` the output step is 0.005 s, or the step when that is longer). Peaks are tracked at every
step.

The defaults keep the pointwise error of the floor displacements within about 0.15 % of each
building's peak (average acceleration: period error (π²/3)(h/T)², Chopra 2017 §5.5; the worst case is
a one-story building, whose fundamental period is its shortest): see
``benchmarks/accuracy_defaults.py``.
"""

from __future__ import annotations

import dataclasses
import datetime
import json
import math
import os
from typing import TYPE_CHECKING, Any

import numpy as np

from pounding._schema import ResultVariables, result_variables, with_baseline, with_floor_spectra
from pounding._version import __version__
from pounding.contact.laws import get_contact_law
from pounding.errors import PoundingInputError
from pounding.ground_motion import GroundMotion
from pounding.integrators import get_integrator
from pounding.integrators.base import RawResult, compiled_core
from pounding.integrators.ivp import IVP_METHODS
from pounding.integrators.newmark import (
    SCHEMES,
    contact_duration_coefficients,
    get_scheme,
    integrate_newmark,
    stiffness_exponent,
)
from pounding.structure import ModalDamping, ShearBuilding
from pounding.system import WALL, Contact, PoundingSystem, assemble
from pounding.validation import Key, check_table

if TYPE_CHECKING:  # xarray (and pandas) cost ~0.3 s to import: only when a Dataset is built
    import xarray as xr

#: Integration methods by name (pounding.integrators.INTEGRATORS, with the alias average_acceleration).
METHODS = (*SCHEMES, "ivp")

#: Default steps per shortest natural period and per contact duration (benchmarks/accuracy_defaults.py:
#: pointwise displacement error <= 0.15 % of the peak on a 0.2 s one-story building, 2 % at 40;
#: benchmarks/impact_fidelity.py: a free impact's restitution within 1.3e-4 of the law's own for every
#: law at 160 steps per contact, 9.6e-4 at 40 — the error of the trapezoidal rule inside a nonlinear
#: contact falls as the square of the step, and it always adds energy).
STEPS_PER_PERIOD = 160
STEPS_PER_CONTACT = 160

#: Peak drift ratio above which a run is flagged: beyond it elastic stories are no model of a real
#: building (the ``[output] drift_limit`` of a case file).
DRIFT_LIMIT = 0.02

#: Story drift ratio beyond which a building with yielding stories or P-Δ counts as collapsed
#: (sidesway; an elastic story has no strength to lose): the run records the
#: time (``collapse_time``), and Newton's failure past it ends the analysis instead of an error.
#: 10 % is the usual non-simulated limit of IDA studies (e.g. FEMA P695 archetypes; Vamvatsikos &
#: Cornell 2002 use the flattening of the IDA curve, which this bounds).
COLLAPSE_DRIFT = 0.10

#: Output step [s] when none is given (or the integration step when that is longer).
DEFAULT_OUTPUT_DT = 0.005


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
        Output step [s], honoured (the integration step is shortened to fit it); default 0.005 s,
        or the integration step when that is longer.
    duration : float or None
        Analysed time [s]; default the record's duration.
    alpha : float
        HHT α in [−1/3, 0].
    ivp_method : str
        ``solve_ivp`` method for ``method = "ivp"``: RK45, DOP853, Radau, BDF, LSODA.
    rtol, atol : float
        ``solve_ivp`` tolerances.
    tol : float
        Newton tolerance on the displacement increment, relative to ``max(|u|, 1 mm)``.
    max_iter, max_halvings : int
        Newton iterations per step; step halvings allowed when Newton fails.
    locate_onset : bool
        Shorten a step that closes or separates a gap so it ends there.
    steps_per_contact, steps_per_period : int
        Steps per contact duration and per shortest natural period (both 160 by default).
    adaptive : bool
        Event-aware stepping (module docstring); False keeps one fixed step.
    collapse_drift : float
        Story drift ratio taken as (sidesway) collapse, default :data:`COLLAPSE_DRIFT`.
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
    steps_per_contact: int = STEPS_PER_CONTACT
    steps_per_period: int = STEPS_PER_PERIOD
    adaptive: bool = True
    collapse_drift: float = COLLAPSE_DRIFT

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise PoundingInputError(
                f"analysis.method = {self.method!r}; allowed: {', '.join(METHODS)}"
            )
        if self.ivp_method not in IVP_METHODS:
            raise PoundingInputError(
                f"analysis.ivp_method = {self.ivp_method!r}; allowed: {', '.join(IVP_METHODS)}"
            )
        for name in ("dt", "output_dt", "duration", "atol"):
            value = getattr(self, name)
            if value is not None and not (math.isfinite(value) and value > 0):
                raise PoundingInputError(f"analysis.{name} = {value}; allowed: a positive number")
        for name in ("rtol", "tol"):
            value = getattr(self, name)
            if not (math.isfinite(value) and 0 < value < 1):
                raise PoundingInputError(f"analysis.{name} = {value}; allowed: 0 < {name} < 1")
        if not (math.isfinite(self.collapse_drift) and self.collapse_drift > 0):
            raise PoundingInputError(
                f"analysis.collapse_drift = {self.collapse_drift}; allowed: a positive drift ratio"
            )
        for name in ("max_iter", "steps_per_contact", "steps_per_period"):
            if int(getattr(self, name)) < 1:
                raise PoundingInputError(f"analysis.{name} = {getattr(self, name)}; allowed: >= 1")
        if int(self.max_halvings) < 0:
            raise PoundingInputError(f"analysis.max_halvings = {self.max_halvings}; allowed: >= 0")
        if self.method == "hht":
            get_scheme("hht", alpha=self.alpha)

    @classmethod
    def from_mapping(cls, options: dict[str, Any]) -> AnalysisOptions:
        """Build from a mapping (the ``[analysis]`` table): every key's type and range checked
        against :data:`ANALYSIS_KEYS`, unknown keys named with the allowed ones."""
        return cls(**check_table(options, ANALYSIS_KEYS, "analysis"))


#: The ``[output]`` keys of a case file.
OUTPUT_KEYS = (
    Key(
        "drift_limit",
        "number",
        f"peak drift ratio flagged in the summary and report (default {DRIFT_LIMIT}: the elastic "
        "stories' validity)",
        "",
        0.0,
        1.0,
        open_low=True,
    ),
    Key(
        "floor_spectra",
        "any",
        '"roof", "all" or a list of floor numbers: floor response spectra (5 % damped PSa of the '
        "absolute floor acceleration, 0.02-5 s) stored as floor_spectrum (default none)",
    ),
)

#: The ``[analysis]`` keys: type, unit, range and meaning (the case-file reference is made from them).
ANALYSIS_KEYS = (
    Key("method", "string", "integration method", choices=tuple(METHODS)),
    Key(
        "dt", "number", "integration step (default: from the periods and contacts)", "s", 1e-6, 1.0
    ),
    Key("output_dt", "number", f"output step (default {DEFAULT_OUTPUT_DT} s)", "s", 1e-6, 10.0),
    Key(
        "duration", "number", "analysed time (default: the record's)", "s", 0.0, 1e4, open_low=True
    ),
    Key("alpha", "number", "HHT α (method = hht)", "", -1.0 / 3.0, 0.0),
    Key("ivp_method", "string", "solve_ivp method (method = ivp)", choices=tuple(IVP_METHODS)),
    Key("rtol", "number", "solve_ivp relative tolerance", "", 0.0, 0.1, open_low=True),
    Key(
        "atol",
        "number",
        "solve_ivp absolute tolerance (default: scaled)",
        "",
        0.0,
        1.0,
        open_low=True,
    ),
    Key(
        "tol",
        "number",
        "Newton tolerance, relative to max(|u|, 1 mm)",
        "",
        0.0,
        1e-2,
        open_low=True,
    ),
    Key("max_iter", "integer", "Newton iterations per step", "", 1, 1000),
    Key("max_halvings", "integer", "step halvings when Newton fails", "", 0, 40),
    Key("locate_onset", "bool", "end a step at a gap's closure or separation"),
    Key("steps_per_contact", "integer", "steps per contact duration", "", 1, 10000),
    Key("steps_per_period", "integer", "steps per shortest natural period", "", 1, 10000),
    Key("adaptive", "bool", "event-aware steps (false: one fixed step)"),
    Key(
        "collapse_drift",
        "number",
        f"story drift ratio taken as collapse of a building with yielding stories or P-Δ (default "
        f"{COLLAPSE_DRIFT}): the analysis stops there and records the time (an IMK story whose "
        "energy capacity is spent is a collapse too)",
        "",
        0.0,
        10.0,
        open_low=True,
    ),
)


def default_time_step(
    system: PoundingSystem,
    ground: GroundMotion,
    *,
    steps_per_contact: int = STEPS_PER_CONTACT,
    steps_per_period: int = STEPS_PER_PERIOD,
    adaptive: bool = True,
) -> float:
    """Default (base) integration step [s] (see the module docstring)."""
    candidates = [system.shortest_period() / steps_per_period, ground.dt]
    if not adaptive and len(system.elements):
        pgv = float(np.max(np.abs(np.cumsum(ground.acceleration) * ground.dt)))
        v_approach = max(2.0 * pgv, 0.1)
        coef, expo = contact_duration_coefficients(system)
        candidates.append(float(np.min(coef * v_approach**expo)) / steps_per_contact)
    return min(candidates)


def _resolve(case_or_system: Any, ground: GroundMotion | None, options: dict[str, Any]):
    """(system, ground, options, title) from a case object or from a system and a ground motion."""
    if isinstance(case_or_system, PoundingSystem):
        if ground is None:
            raise PoundingInputError(
                "simulate(system, ground): a GroundMotion is required with a system"
            )
        return case_or_system, ground, AnalysisOptions.from_mapping(options), ""
    for attr in ("system", "ground_motion", "analysis"):
        if not hasattr(case_or_system, attr):
            raise TypeError(
                "simulate() takes a case (pounding.load_case) or a PoundingSystem and a GroundMotion"
            )
    return (
        case_or_system.system,
        ground if ground is not None else case_or_system.ground_motion,
        with_overrides(case_or_system.analysis, options),
        getattr(case_or_system, "title", ""),
    )


def with_overrides(analysis: AnalysisOptions, options: dict[str, Any]) -> AnalysisOptions:
    """``analysis`` with ``options`` (the command line's --dt ...) set, checked like the case
    file's keys: the command line calls it before compiling anything."""
    if not options:
        return analysis
    merged = {**dataclasses.asdict(analysis), **options}
    return AnalysisOptions.from_mapping({k: v for k, v in merged.items() if v is not None})


def simulate(
    case_or_system: Any,
    ground: GroundMotion | None = None,
    *,
    baseline: bool = False,
    **options: Any,
) -> xr.Dataset:
    """Run one pounding analysis and return the results Dataset.

    Parameters
    ----------
    case_or_system : Case or PoundingSystem
        A case from :func:`pounding.load_case`, or a system from :func:`pounding.system.assemble`.
    ground : GroundMotion, optional
        Ground motion (required with a system; overrides the case's record when given).
    baseline : bool
        Also run the same analysis without contacts and add its peaks (``no_contact_peak_*``), the
        amplifications (``drift_amplification``, ``story_drift_amplification``, ...) and the story
        shear the impacts add (``impact_story_shear``); ``pounding run`` does this by default.
    **options
        Any field of :class:`AnalysisOptions` (``method``, ``dt``, ``output_dt``, ``duration``, ...).
    """
    from pounding.results import to_dataset

    return to_dataset(simulate_variables(case_or_system, ground, baseline=baseline, **options))


def simulate_variables(
    case_or_system: Any,
    ground: GroundMotion | None = None,
    *,
    baseline: bool = False,
    **options: Any,
) -> ResultVariables:
    """:func:`simulate` without building the ``xr.Dataset``: the same result as plain arrays
    (for the ``pounding run`` console process, which then needs neither xarray nor pandas)."""
    system, ground, opts, title = _resolve(case_or_system, ground, options)
    result = _variables(system, ground, opts, title)
    if baseline and len(system.elements):
        free = assemble(system.buildings, (), system.link_specs)  # the links stay
        result = with_baseline(result, _variables(free, ground, opts, title))
    output = getattr(case_or_system, "output", None) or {}
    result.attrs["drift_limit"] = float(output.get("drift_limit", DRIFT_LIMIT))
    mismatch = restitution_warnings(system, result.variables, opts)
    if mismatch:
        earlier = json.loads(result.attrs.get("warnings", "[]"))
        result.attrs["warnings"] = json.dumps([*earlier, *mismatch])
    if output.get("floor_spectra"):
        result = with_floor_spectra(result, output["floor_spectra"])
    return result


#: A law whose single-impact restitution misses its nominal e by more than this fraction is
#: flagged (Lankarani–Nikravesh at e = 0.65 rebounds at 0.775 in a free impact).
E_MISMATCH = 0.05
#: Length of the ground pulse that throws the mass of the single-impact check [s].
_KICK = 0.05


def single_impact_restitution(
    contact: Contact, mass: float, v0: float, opts: AnalysisOptions, core: str | None = None
) -> float:
    """Rebound/approach speed of one free impact of ``mass`` [kg] at ``v0`` [m/s] against a rigid
    wall through ``contact``'s law, integrated by the analysis's own method and settings: a nearly
    free mass (T = 2000 s) thrown at the wall by a half-sine ground pulse. Through the compiled loop
    this costs a few milliseconds and no compilation beyond the analysis's own (``core``: the
    compilation of the core the analysis ran on, :func:`pounding.integrators.base.compiled_core`)."""
    k_b = mass * (2.0 * math.pi / 2000.0) ** 2
    building = ShearBuilding("m", [mass], [k_b], damping=ModalDamping((0.0,)))
    wall = dataclasses.replace(
        contact, left="m", right=WALL, floors="all", gap=v0 * _KICK, column_share=None,
        column_mass=None, column_capacity=None, level_tolerance=None,
    )  # fmt: skip
    amplitude = v0 * math.pi / (2.0 * _KICK)  # a half sine of this amplitude gives the mass v0
    t = np.arange(0.0, _KICK + 1e-12, _KICK / 20)
    system = assemble([building], [wall])
    coef, exp = contact_duration_coefficients(system)
    duration = 2.0 * _KICK + 3.0 * float(coef[0] * v0 ** exp[0])
    ground = GroundMotion(-amplitude * np.sin(np.pi * t / _KICK), _KICK / 20)
    single = dataclasses.replace(opts, duration=duration, dt=None, output_dt=None)
    raw, _ = run(system, ground, single, core=core)
    imp = raw.impacts
    if imp["v0"].size == 0 or not np.isfinite(imp["v_end"][0]):
        return math.nan
    return float(-imp["v_end"][0] / imp["v0"][0])


def restitution_warnings(
    system: PoundingSystem, variables: dict[str, Any], opts: AnalysisOptions
) -> list[str]:
    """A warning per contact whose law, at the largest approach speed it saw, rebounds more than
    :data:`E_MISMATCH` away from its nominal e in a free impact, with what to set instead; or whose
    impact at that speed would outlast the analysis (a k in the wrong units: the buildings pass
    through each other instead of rebounding)."""
    el = system.elements
    if not len(el):
        return []
    time = np.asarray(variables["time"][1], dtype=float)
    span = float(time[-1] - time[0]) if time.size else 0.0
    tc_coef, tc_exp = contact_duration_coefficients(system)
    if opts.method == "ivp":  # the check's one free impact goes through the compiled loop
        opts = AnalysisOptions()
    elements = np.asarray(variables["impact_contact"][1], dtype=np.int64)
    core = compiled_core(system)  # the free impacts run on the analysis's own compiled core
    v0 = np.asarray(variables["impact_v0"][1], dtype=float)
    found = []
    for g, contact in enumerate(system.contacts):
        law = get_contact_law(contact.law)
        if law.is_bumper or law.is_filler:  # the layer in the gap sets the rebound, not one e
            continue
        mine = np.isin(elements, np.flatnonzero(el.group == g))
        if not mine.any():
            continue
        i = int(np.argmax(np.where(mine, v0, -np.inf)))
        c = elements[i]
        t_c = float(tc_coef[c] * max(float(v0[i]), 1e-3) ** tc_exp[c])
        if not t_c <= span:
            n = stiffness_exponent(system, c)
            found.append(
                f"contact {contact.left}-{contact.right}: an impact at {v0[i]:.3g} m/s through "
                f"{law.name} with k = {el.el_params[c, 0]:.3g} N/m^{n:g} would last {t_c:.3g} s, "
                f"longer than the analysis ({span:g} s): the buildings pass through each other "
                "instead of rebounding; check k and its units"
            )
            continue
        if not law.has_damping or contact.e is None or contact.calibration == "exact":
            continue
        e_eff = single_impact_restitution(
            contact, float(el.el_mass[elements[i]]), float(v0[i]), opts, core
        )
        if abs(e_eff - contact.e) > E_MISMATCH * contact.e:
            fix = (
                "a delta_m consistent with the penetration"
                if law.is_bilinear
                else 'calibration = "exact"'
            )
            found.append(
                f"contact {contact.left}-{contact.right}: {law.name} rebounds at e = {e_eff:.3f} in a "
                f"free impact at {v0[i]:.3g} m/s for the nominal e = {contact.e:g} "
                f"({100 * (e_eff / contact.e - 1):+.0f} %): set {fix} to get the e you mean"
            )
    return found


def _variables(
    system: PoundingSystem, ground: GroundMotion, opts: AnalysisOptions, title: str
) -> ResultVariables:
    """Integrate one system and wrap the raw result in the schema's variables."""
    raw, info = run(system, ground, opts)
    provenance = {
        "title": title,
        "pounding_version": __version__,
        "created": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "laws": sorted(set(system.elements.law)),
        "friction_laws": sorted(set(system.friction.law)),
        "method": opts.method,
        **info,
    }
    return result_variables(system, ground.starting_from_rest(), raw, provenance=provenance)


def step_plan(
    system: PoundingSystem, ground: GroundMotion, opts: AnalysisOptions, *, ivp_grid: bool = True
) -> tuple[float, float, int, int]:
    """(integration step [s], output step [s], steps per output, output rows after t = 0) of
    :func:`run`: the base step (``opts.dt`` or :func:`default_time_step`) shortened so that a whole
    number of steps fills each output interval, over the duration rounded up to whole outputs. A
    given ``opts.output_dt`` is honoured, also when it is shorter than the base step; without one
    the output step is :data:`DEFAULT_OUTPUT_DT` or the base step if that is longer.
    ``ground`` starts from rest. With ``ivp_grid=False`` the ivp method's output grid follows the
    Newmark-family rule too (the step a Newmark run of the case would take)."""
    duration = ground.duration if opts.duration is None else float(opts.duration)
    dt = opts.dt or default_time_step(
        system,
        ground,
        steps_per_contact=opts.steps_per_contact,
        steps_per_period=opts.steps_per_period,
        adaptive=opts.adaptive,
    )
    # the ivp path steps on its own: its output grid is the one asked for, not tied to a Newmark step
    if opts.output_dt is not None or (opts.method == "ivp" and ivp_grid):
        output_dt = opts.output_dt or DEFAULT_OUTPUT_DT
    else:
        output_dt = max(DEFAULT_OUTPUT_DT, dt)
    every = max(1, math.ceil(output_dt / dt - 1e-9))
    n_out = max(1, math.ceil(duration / output_dt - 1e-9))
    return output_dt / every, output_dt, every, n_out


#: A given step longer than this fraction of the shortest natural period is refused (fewer than two
#: steps per period: the mode cannot be represented), one longer than the second fraction is warned
#: about (the mode is integrated, with period elongation; legitimate for a stiff mode that carries
#: no response, e.g. the superstructure of an isolated building).
MAX_DT_PERIOD_FRACTION, WARN_DT_PERIOD_FRACTION = 0.5, 0.1
#: Most time steps of one analysis: ~10-60 min of integration; a model with a period of 2e-7 s
#: (a 1 kg floor on a 1e15 N/m story) asked for 5e9 steps and hung.
MAX_STEPS = 10**9
#: Bytes held per output row and per dof (u, v, a and their Dataset copies) or gap element.
_BYTES_PER_DOF_ROW, _BYTES_PER_ELEMENT_ROW = 8 * 3 * 3, 8 * 2 * 3


def check_plan(
    system: PoundingSystem, opts: AnalysisOptions, dt: float, n_out: int, n_steps: int
) -> list[str]:
    """Refuse, before integrating, a given step too long for the structure (dt = 100 s gave
    all-zero peaks), a run whose results cannot fit in memory, with the estimate, and a run of
    more than :data:`MAX_STEPS` steps, with what set the step. Returns the warnings (a given step
    longer than a tenth of the shortest natural period)."""
    warnings = []
    if opts.dt is not None and opts.method != "ivp":
        t_min = system.shortest_period()
        if dt > MAX_DT_PERIOD_FRACTION * t_min:
            raise PoundingInputError(
                f"analysis.dt = {opts.dt:g} s is longer than half the shortest natural period "
                f"({t_min:.4g} s): that mode cannot be represented and the response would be lost; "
                f"allowed: dt <= {MAX_DT_PERIOD_FRACTION * t_min:.3g} s (or leave dt out)"
            )
        if dt > WARN_DT_PERIOD_FRACTION * t_min:
            warnings.append(
                f"analysis.dt = {opts.dt:g} s is longer than a tenth of the shortest natural period "
                f"({t_min:.4g} s): that mode's period is lengthened and its response filtered"
            )
    rows = n_out + 1
    need = rows * (
        _BYTES_PER_DOF_ROW * system.n_dof + _BYTES_PER_ELEMENT_ROW * len(system.elements)
    )
    need += 8 * 12 * system.n_dof**2  # dense and band matrices of the step
    have = _physical_memory()
    if have and need > 0.5 * have:
        raise PoundingInputError(
            f"the results would need about {need / 2**30:.1f} GiB ({rows} output rows x "
            f"{system.n_dof} dofs), more than half of this machine's {have / 2**30:.1f} GiB; "
            "allowed: a longer analysis.output_dt, a shorter analysis.duration or fewer floors"
        )
    if n_steps > MAX_STEPS:
        many = (
            f"the analysis would take {n_steps:.3g} steps of {dt:.3g} s, more than {MAX_STEPS:.0e}"
        )
        if opts.dt is not None or (opts.output_dt is not None and dt >= opts.output_dt * 0.999):
            key = "dt" if opts.dt is not None else "output_dt"
            raise PoundingInputError(
                f"{many}: set by analysis.{key}; allowed: a longer analysis.{key} or a shorter "
                "analysis.duration"
            )
        periods = system.shortest_periods()
        i = int(np.argmin(periods))
        raise PoundingInputError(
            f"{many}: building {system.buildings[i].name!r} has a natural period of "
            f"{periods[i]:.3g} s; allowed: the periods of a building (check the units of its "
            "masses [kg], stiffnesses [N/m], base and soil), or a shorter analysis.duration"
        )
    return warnings


def _physical_memory() -> int:
    """Physical memory [bytes], 0 when the system does not say."""
    try:
        return int(os.sysconf("SC_PAGE_SIZE")) * int(os.sysconf("SC_PHYS_PAGES"))
    except (AttributeError, ValueError, OSError):
        return 0


def run(
    system: PoundingSystem, ground: GroundMotion, opts: AnalysisOptions, *, core: str | None = None
) -> tuple[RawResult, dict]:
    """Integrate with validated options; returns the raw result and the provenance of the step choice.
    ``core``: see :func:`pounding.integrators.newmark.integrate_newmark`."""
    ground = ground.starting_from_rest()
    dt, output_dt, every, n_out = step_plan(system, ground, opts)
    if opts.method == "ivp":  # counted by the Newmark rule: the explicit solver slows alike
        step, _, every_n, n_n = step_plan(system, ground, opts, ivp_grid=False)
        warnings = check_plan(system, opts, step, n_out, n_n * every_n)
    else:
        warnings = check_plan(system, opts, dt, n_out, n_out * every)
    info = {
        "warnings": warnings,
        "dt": dt,
        "output_dt": output_dt,
        "duration": n_out * output_dt,
        "dt_chosen": int(opts.dt is None),
    }
    if opts.method == "ivp":
        integrator = get_integrator("ivp", method=opts.ivp_method, rtol=opts.rtol, atol=opts.atol)
        raw = integrator.integrate(system, ground, output_times=output_dt * np.arange(n_out + 1))
    else:
        raw = integrate_newmark(
            system,
            ground,
            dt=dt,
            output_every=every,
            n_steps=n_out * every,
            scheme=get_integrator(
                opts.method, **({"alpha": opts.alpha} if opts.method == "hht" else {})
            ),
            tol=opts.tol,
            max_iter=opts.max_iter,
            max_halvings=opts.max_halvings,
            locate_onset=opts.locate_onset,
            adaptive=opts.adaptive,
            steps_per_contact=opts.steps_per_contact,
            collapse_drift=opts.collapse_drift,
            core=core,
        )
    raw.info["collapse_drift"] = float(opts.collapse_drift)
    info.update({k: v for k, v in raw.info.items() if k not in ("dt", "failed_stories")})
    return raw, info
