"""Facing pairs of a system and their exact required gaps from time histories without contact."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import xarray as xr

from pounding.case import Case
from pounding.errors import PoundingInputError
from pounding.ground_motion import GroundMotion
from pounding.integrators.hermite import hermite_extremum
from pounding.separation.variables import _apply_attrs, _pair_coords
from pounding.simulate import AnalysisOptions, run, step_plan
from pounding.spectra import (
    modal_extremes,
)
from pounding.system import LEFT_SIGN, LEVEL_TOLERANCE, RIGHT_SIGN, WALL, PoundingSystem, assemble

# ---------------------------------------------------------------------------------------------
# Facing pairs and the exact gap from time histories
# ---------------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class FacingPair:
    """Two points that can hit each other: a left and a right end, each a building floor or a wall.

    ``left_floor``/``right_floor`` are 1-based, 0 for a wall; ``left_dof``/``right_dof`` are the
    system's degrees of freedom, −1 for a wall; elevations [m] (NaN for a wall).
    """

    left: str
    right: str
    left_floor: int
    right_floor: int
    left_dof: int
    right_dof: int
    left_elevation: float
    right_elevation: float

    @property
    def interface(self) -> str:
        """The two neighbours (or building and wall) the pair belongs to, ``"A|B"``."""
        return f"{self.left}|{self.right}"

    @property
    def label(self) -> str:
        left = self.left if self.left == WALL else f"{self.left}:{self.left_floor}"
        right = self.right if self.right == WALL else f"{self.right}:{self.right_floor}"
        return f"{left}-{right}"

    @property
    def same_level(self) -> bool:
        """Both ends are floors at the same elevation (slab to slab)."""
        return (
            self.left != WALL
            and self.right != WALL
            and abs(self.left_elevation - self.right_elevation) < LEVEL_TOLERANCE
        )


def facing_pairs(system: PoundingSystem) -> tuple[FacingPair, ...]:
    """Every pair of facing points of a system, in a fixed order.

    Every floor pair at a common elevation between neighbours in the row; the explicit floor pairs
    (possibly at different heights) and the wall contacts given in the system's contacts (whatever their
    gap and law). Duplicates are dropped.
    """
    blds = system.buildings
    index = {b.name: i for i, b in enumerate(blds)}
    seen: set[tuple[str, int, str, int]] = set()
    out: list[FacingPair] = []

    def add(left: str, lf: int, right: str, rf: int) -> None:
        key = (left, lf, right, rf)
        if key in seen:
            return
        seen.add(key)
        li, ri = index.get(left), index.get(right)
        out.append(
            FacingPair(
                left=left,
                right=right,
                left_floor=lf,
                right_floor=rf,
                left_dof=system.dof(li, lf) if li is not None else -1,
                right_dof=system.dof(ri, rf) if ri is not None else -1,
                # floor 0 is an isolated building's base slab, at ground level
                left_elevation=(float(blds[li].elevations[lf - 1]) if lf > 0 else 0.0)
                if li is not None
                else math.nan,
                right_elevation=(float(blds[ri].elevations[rf - 1]) if rf > 0 else 0.0)
                if ri is not None
                else math.nan,
            )
        )

    for a, b in zip(blds[:-1], blds[1:], strict=True):
        for i, zi in enumerate(a.elevations):
            for j, zj in enumerate(b.elevations):
                if abs(zi - zj) < LEVEL_TOLERANCE:
                    add(a.name, i + 1, b.name, j + 1)
    el = system.elements
    for c in range(len(el)):
        if el.left_column[c] >= 0 or el.right_column[c] >= 0:
            continue  # a slab against a column between floors: no floor pair to check
        add(el.left[c], int(el.left_floor[c]), el.right[c], int(el.right_floor[c]))
    return tuple(out)


def _analysis_step(system: PoundingSystem, ground: GroundMotion, opts: AnalysisOptions):
    """(integration step [s], analysed duration [s]) of a Newmark-family run of the case."""
    dt, output_dt, _, n_out = step_plan(system, ground.starting_from_rest(), opts, ivp_grid=False)
    return dt, n_out * output_dt


def _hermite_max(d: np.ndarray, v: np.ndarray, h: float) -> float:
    """Max of the cubic Hermite interpolant of (d, ḋ) sampled every h: the largest sample, or the
    extremum inside a step next to it where ḋ turns from positive to negative."""
    k = int(np.argmax(d))
    best = float(d[k])
    for i in (k - 1, k):
        if 0 <= i < d.size - 1 and v[i] > 0.0 >= v[i + 1]:
            best = max(best, float(hermite_extremum(d[i], v[i], d[i + 1], v[i + 1], h)))
    return best


@dataclasses.dataclass(frozen=True)
class _TimeHistory:
    exact_gap: np.ndarray  # (n_pairs,) [m]
    peak_displacement: np.ndarray  # (n_dof,) [m]
    dt: float
    duration: float
    method: str


#: Name of the exact modal path in results (``method`` attribute of a separation Dataset).
MODAL_METHOD = "modal_exact"

#: Sub-steps per shortest period of the exact modal solution; with the cubic Hermite extremum
#: between sub-steps the maximum of a sinusoid is then within 1e-4 of its own.
MODAL_STEPS_PER_PERIOD = 20


def _modal_rows(system: PoundingSystem) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """(ω [rad/s], ζ, R) with u(t) = R D(t): every mode of every building, R = φ_j Γ_j [-].

    None when the system is not a set of classically damped linear buildings: an isolated building
    (friction bearings), or a mode damped at or above critical (Rayleigh damping on high modes).
    """
    if system.isolated:
        return None
    omegas, zetas = [], []
    rows = np.zeros((system.n_dof, system.n_dof))
    col = 0
    for i, b in enumerate(system.buildings):
        modal = b.modal()
        n = b.n_floors
        off = int(system.dof_offset[i])
        rows[off : off + n, col : col + n] = modal.shapes * modal.participation_factors
        omegas.append(modal.circular_frequencies)
        zetas.append(modal.damping_ratios)
        col += n
    omega, zeta = np.concatenate(omegas), np.concatenate(zetas)
    if col != system.n_dof or not np.all(zeta < 1.0):
        return None
    return omega, zeta, rows


def _time_history(
    system: PoundingSystem, gm: GroundMotion, opts: AnalysisOptions, pairs: Sequence[FacingPair]
) -> _TimeHistory:
    """The buildings without contacts over the case's analysed duration; approach of each pair.

    Buildings fixed at the base: the exact modal solution (:func:`pounding.spectra.modal_extremes`).
    Isolated buildings: a run with the case's own method and integration step.
    """
    dt, duration = _analysis_step(system, gm, opts)
    modal = _modal_rows(system)
    if modal is not None:
        omega, zeta, rows = modal
        pair_rows = np.zeros((len(pairs), system.n_dof))
        for p, pair in enumerate(pairs):
            # δ + g of the pair, with the signs of pounding.system
            for dof, sign in ((pair.left_dof, LEFT_SIGN), (pair.right_dof, RIGHT_SIGN)):
                if dof >= 0:
                    pair_rows[p] += sign * rows[dof]
        ground = gm.starting_from_rest()
        hi, lo, h = modal_extremes(
            ground.acceleration,
            ground.dt,
            omega,
            zeta,
            np.vstack((pair_rows, rows)),
            duration,
            steps_per_period=MODAL_STEPS_PER_PERIOD,
        )
        n_p = len(pairs)
        peaks = np.maximum(hi[n_p:], -lo[n_p:])
        return _TimeHistory(np.maximum(hi[:n_p], 0.0), peaks, h, duration, MODAL_METHOD)
    free = assemble(system.buildings)
    raw, _ = run(free, gm, dataclasses.replace(opts, dt=dt, output_dt=dt, duration=duration))
    u, v = raw.displacement, raw.velocity
    gaps = np.empty(len(pairs))
    for p, pair in enumerate(pairs):
        d = np.zeros(u.shape[0])
        dd = np.zeros(u.shape[0])
        for dof, sign in ((pair.left_dof, LEFT_SIGN), (pair.right_dof, RIGHT_SIGN)):
            if dof >= 0:
                d += sign * u[:, dof]
                dd += sign * v[:, dof]
        # the Newmark family detects contact at step ends only; ivp is continuous in time
        peak = _hermite_max(d, dd, dt) if opts.method == "ivp" else float(d.max())
        gaps[p] = max(0.0, peak)
    return _TimeHistory(gaps, np.asarray(raw.peak_displacement, float), dt, duration, opts.method)


def _unique_names(grounds: Sequence[GroundMotion]) -> list[str]:
    names: list[str] = []
    for gm in grounds:
        name, k = gm.name, 2
        while name in names:
            name = f"{gm.name} ({k})"
            k += 1
        names.append(name)
    return names


def exact_gaps(
    case_or_system: Case | PoundingSystem,
    grounds: Sequence[GroundMotion] | GroundMotion | None = None,
    **analysis: Any,
) -> xr.DataArray:
    r"""Exact minimum gap g* [m] of every facing pair for every record, from time histories.

    .. math:: g^* = \max\big(0,\ \max_t [u_\mathrm{left}(t) - u_\mathrm{right}(t)]\big)

    The buildings are run without contacts over the duration the case's own analysis covers.
    Buildings fixed at the base: each mode exactly (Nigam-Jennings recurrence on sub-steps of at most
    T_min/20, the record linear between samples), the maximum refined between sub-steps by cubic
    Hermite interpolation (:func:`pounding.spectra.modal_extremes`). A system with an isolated building:
    a run with the case's method and integration step, the maximum at every integration step (Newmark
    family: contact is detected at step ends; ``ivp``: refined between output points by cubic Hermite
    interpolation). A pounding run at the default steps follows the exact solution to about 0.1 %
    of the peak, so with gap g*(1 − ε) it pounds and with g*(1 + ε) it does not for ε of that order.

    Parameters
    ----------
    case_or_system : Case or PoundingSystem
        Buildings in a row; its contacts only add facing pairs (explicit floors, walls) and set the
        default integration step.
    grounds : GroundMotion or sequence, optional
        Records; default the case's ground motion.
    **analysis
        Overrides of :class:`pounding.simulate.AnalysisOptions` (``method``, ``dt``, ``output_dt``, ...).

    Returns
    -------
    xarray.DataArray
        ``exact_gap`` over (``record``, ``pair``) with the pair labels as coordinates.
    """
    system, opts = _system_and_options(case_or_system, analysis)
    grounds = _as_grounds(case_or_system, grounds)
    pairs = facing_pairs(system)
    if not pairs:
        raise PoundingInputError(
            "the system has no facing points: give at least two buildings with a floor at a common "
            "elevation, or contacts with explicit floors or walls"
        )
    values = np.array([_time_history(system, gm, opts, pairs).exact_gap for gm in grounds])
    ds = xr.Dataset(
        {"exact_gap": (("record", "pair"), values)},
        coords={"record": _unique_names(grounds), **_pair_coords(pairs)},
    )
    _apply_attrs(ds)
    return ds["exact_gap"]


def _system_and_options(case_or_system: Any, analysis: Mapping[str, Any]):
    if isinstance(case_or_system, PoundingSystem):
        return case_or_system, AnalysisOptions.from_mapping(dict(analysis))
    if isinstance(case_or_system, Case):
        opts = case_or_system.analysis
        return case_or_system.system, (dataclasses.replace(opts, **analysis) if analysis else opts)
    raise TypeError("expected a Case (pounding.load_case) or a PoundingSystem")


def _as_grounds(case_or_system: Any, grounds: Any) -> list[GroundMotion]:
    if grounds is None:
        if not isinstance(case_or_system, Case):
            raise PoundingInputError("grounds: give the record(s) when passing a PoundingSystem")
        return [case_or_system.ground_motion]
    if isinstance(grounds, GroundMotion):
        return [grounds]
    grounds = list(grounds)
    if not grounds or not all(isinstance(g, GroundMotion) for g in grounds):
        raise PoundingInputError("grounds: give one or more GroundMotion objects")
    return grounds
