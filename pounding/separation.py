r"""Separation distance: how wide must the seismic gap be? Time-history, spectral and code estimates.

Every estimate answers the same question for each pair of facing points (a floor of the left building
and the floor of its right neighbour it can hit, or a floor and a rigid wall): the clear distance g
below which the pair comes into contact. With the sign convention of :mod:`pounding.system`
(penetration δ = u_left − u_right − g, displacements relative to the ground, positive to the right):

* **exact, from time histories**: with the contacts removed, the pair touches iff g < g* where

  .. math:: g^* = \max\Big(0,\ \max_t \big[u_\mathrm{left}(t) - u_\mathrm{right}(t)\big]\Big)

  (u ≡ 0 for a wall, so g* = max u for a wall on the right and max(−u) for one on the left). For
  buildings fixed at the base (linear, classically damped) every mode is integrated exactly for the
  record linear between samples (Nigam and Jennings 1969) and the maximum is refined between
  sub-steps by cubic Hermite interpolation: g* is the maximum of the continuous solution to about
  1e-4. Isolated buildings (friction bearings) are run without contacts with the case's own method
  and step, the maximum taken at every integration step;
* **spectral**: floor peaks u_A, u_B from each building's modes and a response spectrum (the
  record's own or a code design spectrum), combined over modes by SRSS or CQC, then over the pair by
  ABS, SRSS or the double-difference combination (DDC) with the CQC correlation of the buildings'
  fundamental modes, and by the CQC of the relative displacement over the modes of both buildings;
* **code rules**: ASCE/SEI 7-16 §12.12.3 and EN 1998-1:2004 §4.4.2.7 applied to the spectral peaks;
* **probability of pounding** over a record suite: P(pound | g) = P(g* > g), empirical and lognormal.

References
----------
.. [1] Der Kiureghian, A. (1981). A response spectrum method for random vibration analysis of MDF
   systems. Earthquake Engineering & Structural Dynamics 9(5), 419-435. doi:10.1002/eqe.4290090503
.. [2] Wilson, E.L., Der Kiureghian, A., Bayo, E.P. (1981). A replacement for the SRSS method in
   seismic analysis. Earthquake Engineering & Structural Dynamics 9(2), 187-192.
   doi:10.1002/eqe.4290090207
.. [3] Jeng, V., Kasai, K., Maison, B.F. (1992). A spectral difference method to estimate building
   separations to avoid pounding. Earthquake Spectra 8(2), 201-223.
.. [4] Penzien, J. (1997). Evaluation of building separation distance required to prevent pounding
   during strong earthquakes. Earthquake Engineering & Structural Dynamics 26(8), 849-858.
.. [5] Lin, J.-H., Weng, C.-C. (2001). Probability analysis of seismic pounding of adjacent
   buildings. Earthquake Engineering & Structural Dynamics 30(10), 1539-1557. doi:10.1002/eqe.76
.. [6] ASCE (2017). Minimum Design Loads and Associated Criteria for Buildings and Other Structures,
   ASCE/SEI 7-16, §12.12.3 (Eqs. 12.12-1, 12.12-2).
.. [7] CEN (2004). Eurocode 8: Design of structures for earthquake resistance - Part 1,
   EN 1998-1:2004, §4.3.4 (Eq. 4.23) and §4.4.2.7.
.. [8] Chopra, A.K. (2017). Dynamics of Structures, 5th ed. Pearson. §13.7 (modal combination rules).
.. [9] Nigam, N.C., Jennings, P.C. (1969). Calculation of response spectra from strong-motion
   earthquake records. Bulletin of the Seismological Society of America 59(2), 909-922.
"""

from __future__ import annotations

import dataclasses
import datetime
import json
import math
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr
from scipy.stats import norm

from pounding._version import __version__
from pounding.case import Case, CaseError, load_case
from pounding.errors import PoundingInputError
from pounding.ground_motion import GroundMotion
from pounding.records import resolve
from pounding.simulate import AnalysisOptions, run, step_plan
from pounding.spectra import (
    EC8_GROUND_TYPES,
    design_spectrum,
    modal_extremes,
    spectral_peaks,
)
from pounding.structure import ShearBuilding
from pounding.system import LEFT_SIGN, LEVEL_TOLERANCE, RIGHT_SIGN, WALL, PoundingSystem, assemble
from pounding.units import G

# ---------------------------------------------------------------------------------------------
# Modal correlation and combination rules
# ---------------------------------------------------------------------------------------------


def cqc_correlation(period_i: Any, period_j: Any, damping_i: Any, damping_j: Any) -> np.ndarray:
    r"""Correlation coefficient of two modal (or SDOF) responses, Der Kiureghian's CQC formula.

    .. math::

        \rho_{ij} = \frac{8\sqrt{\zeta_i\zeta_j}\,(\zeta_i + r\,\zeta_j)\,r^{3/2}}
        {(1 - r^2)^2 + 4\zeta_i\zeta_j\,r\,(1 + r^2) + 4(\zeta_i^2 + \zeta_j^2)\,r^2},
        \qquad r = \frac{\omega_j}{\omega_i} = \frac{T_i}{T_j}

    ([1]_ Eq. 30; [8]_ Eq. 13.7.10, with i = A, j = B). It is the correlation of the
    stationary displacement responses of the two oscillators to white noise, symmetric under
    (i, ζ_i) ↔ (j, ζ_j), equal to 1 for equal periods and damping and → 0 as the periods separate.

    Parameters
    ----------
    period_i, period_j : array_like
        Natural periods T_i, T_j [s] > 0 (broadcast together).
    damping_i, damping_j : array_like
        Damping ratios ζ_i, ζ_j [-] in [0, 1). With ζ_i = ζ_j = 0 the result is 0 except at
        r = 1 (taken as 1).

    Returns
    -------
    ndarray
        ρ_ij [-] in [0, 1].
    """
    ti, tj, zi, zj = np.broadcast_arrays(
        *(np.asarray(x, dtype=float) for x in (period_i, period_j, damping_i, damping_j))
    )
    if np.any(~np.isfinite(ti) | (ti <= 0)) or np.any(~np.isfinite(tj) | (tj <= 0)):
        raise PoundingInputError("cqc_correlation: periods must be finite and > 0 [s]")
    if np.any(~((zi >= 0) & (zi < 1))) or np.any(~((zj >= 0) & (zj < 1))):
        raise PoundingInputError("cqc_correlation: damping ratios must be in [0, 1)")
    r = ti / tj
    num = 8.0 * np.sqrt(zi * zj) * (zi + r * zj) * r**1.5
    den = (1.0 - r**2) ** 2 + 4.0 * zi * zj * r * (1.0 + r**2) + 4.0 * (zi**2 + zj**2) * r**2
    with np.errstate(invalid="ignore", divide="ignore"):
        rho = np.where(den > 0.0, num / np.where(den > 0.0, den, 1.0), 1.0)
    return np.clip(rho, 0.0, 1.0)


def _srss_modes(contributions: np.ndarray, periods: np.ndarray, dampings: np.ndarray) -> np.ndarray:
    return np.sqrt(np.sum(contributions**2, axis=-1))


def _cqc_modes(contributions: np.ndarray, periods: np.ndarray, dampings: np.ndarray) -> np.ndarray:
    rho = cqc_correlation(periods[:, None], periods[None, :], dampings[:, None], dampings[None, :])
    quad = np.einsum("...i,ij,...j->...", contributions, rho, contributions)
    return np.sqrt(np.maximum(quad, 0.0))


#: Modal combination rules by name: ``f(contributions (..., n_modes), periods, dampings)``.
MODAL_COMBINATIONS: dict[str, Callable[..., np.ndarray]] = {"srss": _srss_modes, "cqc": _cqc_modes}


def combine_modes(contributions: Any, periods: Any, dampings: Any, rule: str = "cqc") -> np.ndarray:
    r"""Peak of a response from its peak modal contributions.

    .. math::

        \mathrm{SRSS:}\ r = \sqrt{\textstyle\sum_n r_n^2}, \qquad
        \mathrm{CQC:}\ r = \sqrt{\textstyle\sum_i \sum_j \rho_{ij} r_i r_j}

    with ρ_ij from :func:`cqc_correlation` ([2]_; [8]_ Eqs. 13.7.3 and 13.7.9).

    Parameters
    ----------
    contributions : array_like, shape (..., n_modes)
        Signed peak modal contributions r_n (e.g. Γ_n φ_n D_n [m]).
    periods, dampings : array_like, shape (n_modes,)
        Modal periods [s] and damping ratios [-].
    rule : {"srss", "cqc"}
    """
    if rule not in MODAL_COMBINATIONS:
        raise PoundingInputError(
            f"modal combination rule = {rule!r}; allowed: {', '.join(MODAL_COMBINATIONS)}"
        )
    c = np.asarray(contributions, dtype=float)
    return MODAL_COMBINATIONS[rule](
        c, np.atleast_1d(np.asarray(periods, float)), np.atleast_1d(np.asarray(dampings, float))
    )


def abs_gap(u_a: Any, u_b: Any) -> np.ndarray:
    r"""Absolute-sum separation S = |u_A| + |u_B| [m] ([3]_, [4]_): the two peaks in opposite phase."""
    return np.abs(np.asarray(u_a, float)) + np.abs(np.asarray(u_b, float))


def srss_gap(u_a: Any, u_b: Any) -> np.ndarray:
    r"""Square-root-of-sum-of-squares separation S = √(u_A² + u_B²) [m] ([3]_, [4]_)."""
    return np.hypot(np.asarray(u_a, float), np.asarray(u_b, float))


def ddc_gap(
    u_a: Any,
    u_b: Any,
    *,
    period_a: Any,
    period_b: Any,
    damping_a: Any,
    damping_b: Any,
) -> np.ndarray:
    r"""Double-difference combination (DDC) of two peak displacements [m].

    .. math::

        S = \sqrt{u_A^2 + u_B^2 - 2\rho_{AB}\,u_A u_B}

    with ρ_AB the CQC correlation (:func:`cqc_correlation`) of the two buildings' fundamental periods
    and damping ratios ([3]_, [4]_). Equal periods and damping give ρ = 1 and
    S = |u_A − u_B| (the buildings move in phase); widely separated periods give ρ → 0 and the SRSS.

    Parameters
    ----------
    u_a, u_b : array_like
        Peak displacements of the two buildings at the potential contact level [m].
    period_a, period_b : array_like
        Fundamental periods [s].
    damping_a, damping_b : array_like
        Damping ratios of those modes [-].
    """
    ua = np.abs(np.asarray(u_a, float))
    ub = np.abs(np.asarray(u_b, float))
    rho = cqc_correlation(period_a, period_b, damping_a, damping_b)
    return np.sqrt(np.maximum(ua**2 + ub**2 - 2.0 * rho * ua * ub, 0.0))


# ---------------------------------------------------------------------------------------------
# Modal peaks of a building from a response spectrum
# ---------------------------------------------------------------------------------------------


def modal_contributions(building: ShearBuilding, spectral_displacement: Any) -> np.ndarray:
    r"""Peak floor displacement of each mode, Γ_n φ_n D_n [m], shape (n_floors, n_modes).

    .. math:: u_{jn} = \Gamma_n\,\phi_{jn}\,D_n, \qquad \Gamma_n = \phi_n^T M \iota

    with mass-normalised φ_n ([8]_ §13.2); D_n is the spectral displacement at the mode's period and
    damping. Σ_n Γ_n φ_jn = 1 at every floor.
    """
    modal = building.modal()
    sd = np.asarray(spectral_displacement, dtype=float)
    if sd.shape != modal.periods.shape:
        raise PoundingInputError(
            f"building {building.name!r}: spectral_displacement has shape {sd.shape}; "
            f"one value per mode is needed, shape {modal.periods.shape}"
        )
    return modal.shapes * (modal.participation_factors * sd)[None, :]


def record_spectral_displacements(building: ShearBuilding, gm: GroundMotion) -> np.ndarray:
    """Spectral displacement D_n = Sd(T_n, ζ_n) [m] of each mode from a record's own spectrum.

    Exact piecewise-linear recurrence of :func:`pounding.spectra.spectral_peaks`, including one period of
    free vibration after the record.
    """
    modal = building.modal()
    gm = gm.starting_from_rest()
    out = np.empty(modal.periods.size)
    for z in np.unique(modal.damping_ratios):
        sel = modal.damping_ratios == z
        out[sel] = spectral_peaks(gm.acceleration, gm.dt, modal.periods[sel], float(z))[:, 0]
    return out


def design_spectral_displacements(building: ShearBuilding, code: str, **params: Any) -> np.ndarray:
    r"""Spectral displacement D_n = PSa(T_n) / ω_n² [m] of each mode from a design spectrum.

    ``code`` and ``params`` as :func:`pounding.spectra.design_spectrum` (``asce7``: s_ds, s_d1 [g],
    t_l [s], 5 % damping; ``ec8``: a_g [m/s²], ground_type, spectrum_type, evaluated at each mode's
    damping through η of EN 1998-1 Eq. 3.6).
    """
    modal = building.modal()
    omega2 = modal.circular_frequencies**2
    if code == "ec8":
        psa = np.empty(modal.periods.size)
        for z in np.unique(modal.damping_ratios):
            sel = modal.damping_ratios == z
            psa[sel] = design_spectrum(code, modal.periods[sel], damping=float(z), **params).values
    else:
        psa = design_spectrum(code, modal.periods, **params).values
    return psa / omega2


# ---------------------------------------------------------------------------------------------
# Code rules
# ---------------------------------------------------------------------------------------------


def _positive(value: Any, field: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise PoundingInputError(f"{field} = {value!r}; allowed: a positive number") from None
    if not (math.isfinite(v) and v > 0.0):
        raise PoundingInputError(f"{field} = {value!r}; allowed: a positive number")
    return v


def asce7_inelastic_displacement(delta_max: Any, *, c_d: float, i_e: float) -> np.ndarray:
    r"""ASCE 7-16 maximum inelastic response displacement δ_M [m], Eq. 12.12-1.

    .. math:: \delta_M = \frac{C_d\,\delta_{max}}{I_e}

    Parameters
    ----------
    delta_max : array_like
        Maximum elastic displacement at the critical location [m], from the analysis under the
        design forces (the elastic spectral displacement times I_e/R).
    c_d : float
        Deflection amplification factor C_d [-] (ASCE 7-16 Table 12.2-1, typically 1.25-6.5).
    i_e : float
        Seismic importance factor I_e [-] (Table 1.5-2: 1.0, 1.25 or 1.5).

    References
    ----------
    ASCE/SEI 7-16 §12.12.3 [6]_.
    """
    c_d = _positive(c_d, "c_d (ASCE 7 deflection amplification factor C_d)")
    i_e = _positive(i_e, "i_e (ASCE 7 importance factor I_e)")
    return c_d * np.abs(np.asarray(delta_max, float)) / i_e


def asce7_separation(
    delta_m1: Any, delta_m2: Any = 0.0, *, same_property: bool = True
) -> np.ndarray:
    r"""ASCE 7-16 §12.12.3 separation between two structures (or a structure and a line) [m].

    Same property, Eq. 12.12-2: :math:`\delta_{MT} = \sqrt{\delta_{M1}^2 + \delta_{M2}^2}`. Different
    properties: each structure is set back from the property line by its own δ_M, so the gap between
    them is δ_M1 + δ_M2. With ``delta_m2 = 0`` (a wall or a property line) both give δ_M1.

    Parameters
    ----------
    delta_m1, delta_m2 : array_like
        Maximum inelastic response displacements at the adjacent edges [m]
        (:func:`asce7_inelastic_displacement`).
    same_property : bool
        True for adjacent structures on the same property.
    """
    d1 = np.abs(np.asarray(delta_m1, float))
    d2 = np.abs(np.asarray(delta_m2, float))
    return np.hypot(d1, d2) if same_property else d1 + d2


def ec8_design_displacement(d_e: Any, *, q_d: float) -> np.ndarray:
    r"""EN 1998-1 design displacement d_s [m], Eq. 4.23 (§4.3.4).

    .. math:: d_s = q_d\,d_e

    Parameters
    ----------
    d_e : array_like
        Displacement from the linear analysis with the design spectrum [m] (for T ≥ T_B the design
        spectrum is the elastic one divided by q, so d_e = elastic displacement / q).
    q_d : float
        Displacement behaviour factor [-], equal to the behaviour factor q unless specified
        (typically 1.5-5).
    """
    q_d = _positive(q_d, "q_d (EC8 displacement behaviour factor)")
    return q_d * np.abs(np.asarray(d_e, float))


def ec8_separation(
    d_s1: Any,
    d_s2: Any = 0.0,
    *,
    same_property: bool = True,
    same_levels: Any = False,
) -> np.ndarray:
    r"""EN 1998-1:2004 §4.4.2.7 minimum distance between two buildings [m].

    (2)a, different properties: each building at least its own d_s from the property line, so
    d_s1 + d_s2 between them; (2)b, same property: √(d_s1² + d_s2²); (3) where the floor levels of the
    two buildings coincide, the distance may be reduced by the factor 0.7. With ``d_s2 = 0`` (a
    wall) both give d_s1.

    Parameters
    ----------
    d_s1, d_s2 : array_like
        Design displacements at the level considered [m] (:func:`ec8_design_displacement`).
    same_property : bool
        True for buildings of the same property.
    same_levels : array_like of bool
        True where the floors of the two buildings are at the same elevation (0.7 applies).
    """
    d1 = np.abs(np.asarray(d_s1, float))
    d2 = np.abs(np.asarray(d_s2, float))
    base = np.hypot(d1, d2) if same_property else d1 + d2
    return np.where(np.asarray(same_levels, bool), 0.7 * base, base)


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
        add(el.left[c], int(el.left_floor[c]), el.right[c], int(el.right_floor[c]))
    return tuple(out)


def _analysis_step(system: PoundingSystem, ground: GroundMotion, opts: AnalysisOptions):
    """(integration step [s], analysed duration [s]) of a Newmark-family run of the case."""
    dt, output_dt, _, n_out = step_plan(system, ground.starting_from_rest(), opts, ivp_grid=False)
    return dt, n_out * output_dt


def _hermite_max(d: np.ndarray, v: np.ndarray, h: float) -> float:
    """Max of the cubic Hermite interpolant of (d, ḋ) sampled every h, near the largest sample."""
    k = int(np.argmax(d))
    best = float(d[k])
    th = np.linspace(0.0, 1.0, 201)
    h00, h10 = 2 * th**3 - 3 * th**2 + 1, th**3 - 2 * th**2 + th
    h01, h11 = -2 * th**3 + 3 * th**2, th**3 - th**2
    for i in (k - 1, k):
        if 0 <= i < d.size - 1:
            cubic = h00 * d[i] + h10 * h * v[i] + h01 * d[i + 1] + h11 * h * v[i + 1]
            best = max(best, float(cubic.max()))
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


# ---------------------------------------------------------------------------------------------
# Probability of pounding over a record suite
# ---------------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class LognormalFit:
    r"""Lognormal distribution of the exact gap over a suite, with an atom at zero.

    P(g* > g) = p (1 − Φ((ln g − ln θ)/β)) for g > 0, where p is the fraction of records whose g* > 0.

    Attributes
    ----------
    median : float
        θ = exp(mean ln g*) over the records with g* > 0 [m] (NaN if none).
    beta : float
        Logarithmic standard deviation β [-] (maximum likelihood, divisor n; 0 for one record).
    fraction : float
        p, the fraction of records with g* > 0 [-].
    n : int
        Number of records.
    """

    median: float
    beta: float
    fraction: float
    n: int


def fit_lognormal(exact_gaps: Any) -> LognormalFit:
    r"""Maximum-likelihood lognormal fit of per-record exact gaps [m].

    .. math:: \ln\theta = \frac1n\sum \ln g^*_k, \qquad
              \beta^2 = \frac1n\sum (\ln g^*_k - \ln\theta)^2

    over the records with g* > 0 (the others never approach and never pound); the moments of ln g*
    are the maximum-likelihood estimates of the lognormal parameters ([5]_ uses the lognormal for the
    peak relative displacement).
    """
    g = np.asarray(exact_gaps, float).ravel()
    if g.size == 0 or np.any(~np.isfinite(g)) or np.any(g < 0):
        raise PoundingInputError(f"exact gaps = {g!r}; allowed: one or more finite values >= 0 [m]")
    pos = g[g > 0]
    if pos.size == 0:
        return LognormalFit(math.nan, math.nan, 0.0, int(g.size))
    ln = np.log(pos)
    mu = float(ln.mean())
    beta = float(np.sqrt(np.mean((ln - mu) ** 2)))
    return LognormalFit(math.exp(mu), beta, pos.size / g.size, int(g.size))


def empirical_pounding_probability(gaps: Any, exact_gaps: Any) -> np.ndarray:
    """Fraction of records that pound with gap g: #{k : g*_k > g} / n, for each gap [m].

    Exact by the property of g*: a record pounds with gap g iff g < g*.
    """
    g = np.asarray(gaps, float)
    s = np.asarray(exact_gaps, float).ravel()
    return (s[None, :] > g.ravel()[:, None]).mean(axis=1).reshape(g.shape)


def lognormal_pounding_probability(gaps: Any, fit: LognormalFit) -> np.ndarray:
    r"""P(pound | g) = p (1 − Φ((ln g − ln θ)/β)) from a :class:`LognormalFit`, for each gap [m]."""
    g = np.asarray(gaps, float)
    if fit.fraction == 0.0:
        return np.zeros_like(g)
    with np.errstate(divide="ignore"):
        if fit.beta > 0:
            surv = norm.sf((np.log(g) - math.log(fit.median)) / fit.beta)
        else:
            surv = (g < fit.median).astype(float)
    return fit.fraction * surv


def gap_for_probability(probability: float, fit: LognormalFit) -> float:
    r"""Gap [m] whose probability of pounding under the fitted distribution is ``probability``.

    .. math:: g_P = \theta \exp\big(\beta\,\Phi^{-1}(1 - P/p)\big)

    (0 when P ≥ p: at least that fraction of the records never approach).
    """
    if not (0.0 < probability < 1.0):
        raise PoundingInputError(f"target probability = {probability!r}; allowed: 0 < P < 1")
    if fit.fraction == 0.0 or probability >= fit.fraction:
        return 0.0
    return float(fit.median * math.exp(fit.beta * norm.isf(probability / fit.fraction)))


# ---------------------------------------------------------------------------------------------
# Options ([separation] table of a case file)
# ---------------------------------------------------------------------------------------------

#: Sources of the spectral estimates: the record's own spectrum or a code design spectrum.
SPECTRUM_SOURCES = ("record", "asce7", "ec8")


@dataclasses.dataclass(frozen=True)
class SeparationOptions:
    """Options of a separation analysis (the ``[separation]`` table of a case file).

    Attributes
    ----------
    records : tuple of str
        Record references (:func:`pounding.records.resolve`); default the case's ground motion.
    spectrum : {"record", "asce7", "ec8"}
        Spectrum of the spectral and code estimates: each record's own, or a design spectrum.
    s_ds, s_d1 : float
        ASCE 7 design spectral accelerations [g] (``spectrum = "asce7"``).
    t_l : float
        ASCE 7 long-period transition period [s].
    a_g : float
        EC8 design ground acceleration on type A ground [g] (``spectrum = "ec8"``).
    ground_type, spectrum_type
        EC8 ground type A-E and spectrum type 1 or 2.
    c_d, i_e, r : float
        ASCE 7 deflection amplification factor C_d, importance factor I_e (default 1.0) and response
        modification coefficient R [-]; the ASCE 7 estimates need C_d and R.
    q, q_d : float
        EC8 behaviour factor q and displacement behaviour factor q_d (default q) [-]; the EC8
        estimates need q.
    target_probability : float
        Probability of pounding for which the gap is reported (default 0.1).
    gaps : tuple of float, optional
        Gaps [m] of the probability curve; default 121 points from 0 to 1.5 × the largest g*.
    """

    records: tuple[str, ...] = ()
    spectrum: str = "record"
    s_ds: float | None = None
    s_d1: float | None = None
    t_l: float = 8.0
    a_g: float | None = None
    ground_type: str = "C"
    spectrum_type: int = 1
    c_d: float | None = None
    i_e: float = 1.0
    r: float | None = None
    q: float | None = None
    q_d: float | None = None
    target_probability: float = 0.1
    gaps: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        w = "separation"
        records = (self.records,) if isinstance(self.records, str) else tuple(self.records)
        if not all(isinstance(r, str) and r.strip() for r in records):
            raise PoundingInputError(
                f"{w}.records = {self.records!r}; allowed: record references (strings)"
            )
        object.__setattr__(self, "records", records)
        if self.spectrum not in SPECTRUM_SOURCES:
            raise PoundingInputError(
                f"{w}.spectrum = {self.spectrum!r}; allowed: {', '.join(SPECTRUM_SOURCES)}"
            )
        for name in ("s_ds", "s_d1", "t_l", "a_g", "c_d", "i_e", "r", "q", "q_d"):
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, _positive(value, f"{w}.{name}"))
        if self.spectrum == "asce7" and (self.s_ds is None or self.s_d1 is None):
            raise PoundingInputError(f"{w}: spectrum = 'asce7' needs s_ds and s_d1 [g]")
        if self.spectrum == "ec8" and self.a_g is None:
            raise PoundingInputError(f"{w}: spectrum = 'ec8' needs a_g [g]")
        if self.spectrum_type not in EC8_GROUND_TYPES:
            raise PoundingInputError(f"{w}.spectrum_type = {self.spectrum_type!r}; allowed: 1, 2")
        ground = str(self.ground_type).strip().upper()
        if ground not in EC8_GROUND_TYPES[self.spectrum_type]:
            raise PoundingInputError(
                f"{w}.ground_type = {self.ground_type!r}; allowed: "
                f"{', '.join(EC8_GROUND_TYPES[self.spectrum_type])}"
            )
        object.__setattr__(self, "ground_type", ground)
        if (self.c_d is None) != (self.r is None):
            raise PoundingInputError(
                f"{w}: the ASCE 7 estimates need both c_d (C_d) and r (R); got c_d = {self.c_d}, "
                f"r = {self.r}"
            )
        if self.q_d is not None and self.q is None:
            raise PoundingInputError(f"{w}: q_d = {self.q_d} needs the behaviour factor q as well")
        p = float(self.target_probability)
        if not (0.0 < p < 1.0):
            raise PoundingInputError(f"{w}.target_probability = {p}; allowed: 0 < P < 1")
        object.__setattr__(self, "target_probability", p)
        if self.gaps is not None:
            gaps = np.asarray(self.gaps, float).ravel()
            if gaps.size == 0 or np.any(~np.isfinite(gaps)) or np.any(gaps < 0):
                raise PoundingInputError(f"{w}.gaps = {self.gaps!r}; allowed: numbers >= 0 [m]")
            object.__setattr__(self, "gaps", tuple(np.unique(gaps).tolist()))

    @classmethod
    def from_mapping(cls, options: Mapping[str, Any]) -> SeparationOptions:
        """Build from a mapping (a ``[separation]`` table), naming unknown keys and the allowed ones."""
        allowed = [f.name for f in dataclasses.fields(cls)]
        unknown = sorted(set(options) - set(allowed))
        if unknown:
            raise PoundingInputError(
                f"unknown separation option(s) {', '.join(unknown)}; allowed: {', '.join(allowed)}"
            )
        return cls(**dict(options))

    def spectrum_parameters(self) -> dict[str, Any]:
        """Keyword arguments of :func:`pounding.spectra.design_spectrum` in SI (a_g converted from g)."""
        if self.spectrum == "asce7":
            return {"s_ds": self.s_ds, "s_d1": self.s_d1, "t_l": self.t_l}
        if self.spectrum == "ec8":
            return {
                "a_g": self.a_g * G,
                "ground_type": self.ground_type,
                "spectrum_type": self.spectrum_type,
            }
        return {}

    def spectrum_description(self) -> str:
        """The spectrum of the spectral and code estimates, with its clause and parameters."""
        if self.spectrum == "asce7":
            return (
                f"ASCE/SEI 7-16 §11.4.6 design spectrum, S_DS = {self.s_ds:g} g, "
                f"S_D1 = {self.s_d1:g} g, T_L = {self.t_l:g} s (5 % damping)"
            )
        if self.spectrum == "ec8":
            return (
                f"EN 1998-1:2004 §3.2.2.2 elastic spectrum type {self.spectrum_type}, ground type "
                f"{self.ground_type}, a_g = {self.a_g:g} g (eta from each mode's damping, Eq. 3.6)"
            )
        return "each record's own elastic response spectrum at the modal periods and damping"

    def to_attrs(self) -> dict[str, Any]:
        """The options as NetCDF-safe attributes (None left out, sequences as JSON)."""
        out: dict[str, Any] = {}
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if value is None:
                continue
            out[f.name] = json.dumps(list(value)) if isinstance(value, tuple) else value
        return out


def load_separation_case(path: str | Path) -> tuple[Case, SeparationOptions]:
    """Read a case file and the options of its optional ``[separation]`` table."""
    case = load_case(path)
    table = case.data.get("separation", {})
    if not isinstance(table, Mapping):
        raise CaseError(f"{path}: [separation] must be a table")
    try:
        options = SeparationOptions.from_mapping(table)
    except (ValueError, TypeError) as exc:
        raise CaseError(f"{path}: {exc}") from None
    return case, options


# ---------------------------------------------------------------------------------------------
# The comparison
# ---------------------------------------------------------------------------------------------

#: Estimates of the required gap: name -> (label, basis: formula, clause, edition).
ESTIMATES: dict[str, tuple[str, str]] = {
    "time_history": (
        "exact, time history without contact",
        "max over t of u_left - u_right at every integration step",
    ),
    "abs_time_history": ("ABS of time-history peaks", "|u_A| + |u_B|"),
    "srss_time_history": ("SRSS of time-history peaks", "sqrt(u_A^2 + u_B^2)"),
    "ddc_time_history": (
        "DDC of time-history peaks",
        "sqrt(u_A^2 + u_B^2 - 2 rho u_A u_B), rho: CQC of T1, zeta1 (Jeng et al. 1992; Penzien 1997)",
    ),
    "abs_spectral": ("ABS of spectral peaks (CQC over modes)", "|u_A| + |u_B|"),
    "srss_spectral": ("SRSS of spectral peaks (CQC over modes)", "sqrt(u_A^2 + u_B^2)"),
    "ddc_spectral": (
        "DDC of spectral peaks (CQC over modes)",
        "sqrt(u_A^2 + u_B^2 - 2 rho u_A u_B), rho: CQC of T1, zeta1 (Jeng et al. 1992; Penzien 1997)",
    ),
    "cqc_relative_spectral": (
        "CQC of u_A - u_B over the modes of both buildings",
        "sqrt(sum_ij rho_ij c_i c_j) (Der Kiureghian 1981)",
    ),
    "asce7_same_property": (
        "ASCE 7-16, same property",
        "ASCE/SEI 7-16 §12.12.3 Eq. 12.12-2: sqrt(dM1^2 + dM2^2), dM = Cd dmax/Ie (Eq. 12.12-1), "
        "dmax = Ie u_el/R",
    ),
    "asce7_property_line": (
        "ASCE 7-16, setbacks from a property line",
        "ASCE/SEI 7-16 §12.12.3: dM1 + dM2, dM = Cd dmax/Ie (Eq. 12.12-1), dmax = Ie u_el/R",
    ),
    "ec8_same_property": (
        "EC8, same property",
        "EN 1998-1:2004 §4.4.2.7(2)b: sqrt(ds1^2 + ds2^2), ds = qd de (Eq. 4.23), de = u_el/q; "
        "x0.7 where floor levels coincide (§4.4.2.7(3))",
    ),
    "ec8_property_line": (
        "EC8, distances to a property line",
        "EN 1998-1:2004 §4.4.2.7(2)a: ds1 + ds2, ds = qd de (Eq. 4.23), de = u_el/q; "
        "x0.7 where floor levels coincide (§4.4.2.7(3))",
    ),
}

#: Statistics over the records.
STATISTICS = ("median", "p84", "max")

_ATTRS: dict[str, dict[str, str]] = {
    "record": {"long_name": "ground-motion record"},
    "pair": {"long_name": "facing pair"},
    "pair_label": {"long_name": "facing pair (building:floor-building:floor)"},
    "pair_left": {"long_name": "left end of the facing pair (building or wall)"},
    "pair_right": {"long_name": "right end of the facing pair (building or wall)"},
    "pair_left_floor": {"units": "1", "long_name": "floor of the left end (0 = wall)"},
    "pair_right_floor": {"units": "1", "long_name": "floor of the right end (0 = wall)"},
    "pair_left_elevation": {"units": "m", "long_name": "elevation of the left end"},
    "pair_right_elevation": {"units": "m", "long_name": "elevation of the right end"},
    "pair_interface": {"long_name": "interface (neighbours or building and wall) of the pair"},
    "pair_same_level": {"units": "1", "long_name": "floors of the pair at the same elevation"},
    "interface": {"long_name": "interface between neighbours (or a building and a wall)"},
    "building": {"long_name": "building"},
    "floor": {"long_name": "floor number (1 = lowest)"},
    "mode": {"long_name": "mode number"},
    "estimate": {"long_name": "estimate of the required gap"},
    "estimate_label": {"long_name": "estimate of the required gap, description"},
    "estimate_basis": {"long_name": "formula, clause and edition of the estimate"},
    "statistic": {"long_name": "statistic over the records (median, 84th percentile, maximum)"},
    "gap": {"units": "m", "long_name": "clear gap at rest"},
    "natural_period": {"units": "s", "long_name": "natural period"},
    "modal_damping_ratio": {"units": "1", "long_name": "modal damping ratio"},
    "spectral_displacement": {"units": "m", "long_name": "spectral displacement Sd(T_n, zeta_n)"},
    "peak_displacement_time_history": {
        "units": "m",
        "long_name": "peak floor displacement, time history without contact",
    },
    "peak_displacement_srss": {
        "units": "m",
        "long_name": "peak floor displacement, spectral, SRSS over modes",
    },
    "peak_displacement_cqc": {
        "units": "m",
        "long_name": "peak floor displacement, spectral, CQC over modes",
    },
    "exact_gap": {
        "units": "m",
        "long_name": "minimum gap avoiding contact (max over time of u_left - u_right)",
    },
    "pair_correlation": {
        "units": "1",
        "long_name": "CQC correlation of the fundamental modes of the pair's buildings (DDC)",
    },
    "required_gap_pair": {"units": "m", "long_name": "required gap of each facing pair"},
    "required_gap": {
        "units": "m",
        "long_name": "required gap (largest over the interface's pairs)",
    },
    "required_gap_statistic": {
        "units": "m",
        "long_name": "required gap, statistic over the records",
    },
    "pounding_probability": {
        "units": "1",
        "long_name": "fraction of records with contact (empirical probability of pounding)",
    },
    "pounding_probability_lognormal": {
        "units": "1",
        "long_name": "probability of pounding, lognormal fit of the exact gaps",
    },
    "lognormal_median": {"units": "m", "long_name": "median of the lognormal fit of the exact gap"},
    "lognormal_beta": {"units": "1", "long_name": "logarithmic standard deviation of the fit"},
    "lognormal_fraction": {
        "units": "1",
        "long_name": "fraction of records whose exact gap is positive",
    },
    "gap_for_target_probability": {
        "units": "m",
        "long_name": "gap with the target probability of pounding (lognormal fit)",
    },
    "case_gap": {"units": "m", "long_name": "gap of the case's contacts (smallest per interface)"},
}


def _case_gaps(case: Any, interfaces: Sequence[str]) -> np.ndarray:
    """The case's gap at each interface (its smallest when floors differ); NaN where the case has
    no contact there."""
    gaps = dict.fromkeys(interfaces, math.inf)
    for c in getattr(case, "contacts", ()):
        name = f"{c.left}|{c.right}"
        if name in gaps:
            gaps[name] = min(gaps[name], float(c.gap))
    return np.array([g if math.isfinite(g) else np.nan for g in gaps.values()])


def _apply_attrs(ds: xr.Dataset) -> None:
    for name in ds.variables:
        if name in _ATTRS:
            ds[name].attrs.update(_ATTRS[name])


def _pair_coords(pairs: Sequence[FacingPair]) -> dict[str, Any]:
    return {
        "pair": np.arange(len(pairs)),
        "pair_label": ("pair", [p.label for p in pairs]),
        "pair_left": ("pair", [p.left for p in pairs]),
        "pair_right": ("pair", [p.right for p in pairs]),
        "pair_left_floor": ("pair", np.array([p.left_floor for p in pairs], dtype=np.int64)),
        "pair_right_floor": ("pair", np.array([p.right_floor for p in pairs], dtype=np.int64)),
        "pair_left_elevation": ("pair", np.array([p.left_elevation for p in pairs])),
        "pair_right_elevation": ("pair", np.array([p.right_elevation for p in pairs])),
        "pair_interface": ("pair", [p.interface for p in pairs]),
        "pair_same_level": ("pair", np.array([p.same_level for p in pairs], dtype=np.int8)),
    }


def _grounds_from_options(case: Case, refs: Sequence[str]) -> list[GroundMotion]:
    if not refs:
        return [case.ground_motion]
    base = case.path.parent if case.path is not None else None
    # the case's [ground_motion] scale applies to the suite too (a design level set once)
    scale = (case.data.get("ground_motion") or {}).get("scale")
    out: list[GroundMotion] = []
    for ref in refs:
        found = resolve(ref, base_dir=base)
        out.extend(found if scale is None else [gm.scaled(float(scale)) for gm in found])
    return out


def _pad(rows: Sequence[np.ndarray], width: int) -> np.ndarray:
    out = np.full((len(rows), width), np.nan)
    for i, r in enumerate(rows):
        out[i, : r.size] = r
    return out


def separation_analysis(
    case: Case,
    records: Sequence[GroundMotion] | Sequence[str] | None = None,
    options: SeparationOptions | Mapping[str, Any] | None = None,
    **analysis: Any,
) -> xr.Dataset:
    """Every estimate of the required gap of a case, side by side, as one Dataset.

    Parameters
    ----------
    case : Case
        Buildings (left to right), contacts (only to name facing pairs and set the integration step),
        analysis options and ground motion (:func:`load_separation_case`, :func:`pounding.load_case`).
    records : sequence of GroundMotion or of record references, optional
        The record suite; default ``options.records``, else the case's ground motion.
    options : SeparationOptions or mapping, optional
        Default: the case's ``[separation]`` table (``case.data["separation"]``), else the defaults.
    **analysis
        Overrides of the case's ``[analysis]`` options for the time histories (``method``, ``dt``).

    Returns
    -------
    xarray.Dataset
        Dims ``record``, ``pair``, ``interface``, ``estimate``, ``statistic``, ``gap``,
        ``building``, ``floor``, ``mode``. Key variables: ``exact_gap`` (record, pair),
        ``required_gap`` (record, interface, estimate), ``required_gap_statistic`` (interface,
        estimate, statistic), ``pounding_probability`` and ``pounding_probability_lognormal``
        (interface, gap), ``gap_for_target_probability`` (interface). CF ``units``/``long_name`` on
        every variable; parameters and provenance in ``attrs``. :func:`separation_table` and
        :func:`separation_summary` read it.
    """
    if not isinstance(case, Case):
        raise TypeError(
            "separation_analysis takes a Case (pounding.separation.load_separation_case)"
        )
    if options is None:
        options = SeparationOptions.from_mapping(case.data.get("separation", {}))
    elif not isinstance(options, SeparationOptions):
        options = SeparationOptions.from_mapping(options)
    if records is None:
        grounds = _grounds_from_options(case, options.records)
    else:
        records = list(records)
        if all(isinstance(r, str) for r in records):
            grounds = _grounds_from_options(case, records)
        else:
            grounds = _as_grounds(case, records)
    system, opts = _system_and_options(case, analysis)
    pairs = facing_pairs(system)
    if not pairs:
        raise PoundingInputError(
            "the case has no facing points: give at least two buildings with a floor at a common "
            "elevation, or contacts with explicit floors or walls"
        )
    blds = system.buildings
    index = {b.name: i for i, b in enumerate(blds)}
    modals = [b.modal() for b in blds]
    width = max(b.n_floors for b in blds)
    n_rec, n_pair = len(grounds), len(pairs)

    # spectra first (cheap, and a bad design-spectrum parameter fails before any integration)
    params = options.spectrum_parameters()
    sd = np.full((n_rec, len(blds), width), np.nan)
    for k, gm in enumerate(grounds):
        for i, b in enumerate(blds):
            sd[k, i, : b.n_floors] = (
                record_spectral_displacements(b, gm)
                if options.spectrum == "record"
                else design_spectral_displacements(b, options.spectrum, **params)
            )
    contrib = [
        np.stack([modal_contributions(b, sd[k, i, : b.n_floors]) for k in range(n_rec)])
        for i, b in enumerate(blds)
    ]  # per building: (record, floor, mode)
    th = [_time_history(system, gm, opts, pairs) for gm in grounds]
    peak_srss = np.full((n_rec, len(blds), width), np.nan)
    peak_cqc = np.full_like(peak_srss, np.nan)
    peak_th = np.full_like(peak_srss, np.nan)
    for i, (b, m) in enumerate(zip(blds, modals, strict=True)):
        peak_srss[:, i, : b.n_floors] = combine_modes(
            contrib[i], m.periods, m.damping_ratios, "srss"
        )
        peak_cqc[:, i, : b.n_floors] = combine_modes(contrib[i], m.periods, m.damping_ratios, "cqc")
        off = int(system.dof_offset[i])
        for k in range(n_rec):
            peak_th[k, i, : b.n_floors] = th[k].peak_displacement[off : off + b.n_floors]

    def end_values(pair: FacingPair, peaks: np.ndarray, side: str) -> np.ndarray:
        name, floor = (
            (pair.left, pair.left_floor) if side == "left" else (pair.right, pair.right_floor)
        )
        if name == WALL:
            return np.zeros(n_rec)
        if floor == 0:
            # an isolated building's base slab: its time-history peak is known; fixed-base modal
            # spectra (and the code rules built on them) say nothing about a sliding slab
            if peaks is peak_th:
                dof = int(system.base_dof[index[name]])
                return np.array([t.peak_displacement[dof] for t in th])
            return np.full(n_rec, np.nan)
        return peaks[:, index[name], floor - 1]

    estimates = [
        "time_history",
        "abs_time_history",
        "srss_time_history",
        "ddc_time_history",
        "abs_spectral",
        "srss_spectral",
        "ddc_spectral",
        "cqc_relative_spectral",
    ]
    if options.c_d is not None:
        estimates += ["asce7_same_property", "asce7_property_line"]
    if options.q is not None:
        estimates += ["ec8_same_property", "ec8_property_line"]
    q_d = options.q_d if options.q_d is not None else options.q

    per_pair = np.full((n_rec, n_pair, len(estimates)), np.nan)
    rho_pair = np.full(n_pair, np.nan)
    exact = np.array([t.exact_gap for t in th])  # (record, pair)
    for p, pair in enumerate(pairs):
        cols: dict[str, np.ndarray] = {"time_history": exact[:, p]}
        both = pair.left != WALL and pair.right != WALL
        if both:
            ia, ib = index[pair.left], index[pair.right]
            ta, tb = modals[ia].periods[0], modals[ib].periods[0]
            za, zb = modals[ia].damping_ratios[0], modals[ib].damping_ratios[0]
            rho_pair[p] = float(cqc_correlation(ta, tb, za, zb))
        for source, peaks in (("time_history", peak_th), ("spectral", peak_cqc)):
            ua, ub = end_values(pair, peaks, "left"), end_values(pair, peaks, "right")
            cols[f"abs_{source}"] = abs_gap(ua, ub)
            cols[f"srss_{source}"] = srss_gap(ua, ub)
            cols[f"ddc_{source}"] = (
                ddc_gap(ua, ub, period_a=ta, period_b=tb, damping_a=za, damping_b=zb)
                if both
                else abs_gap(ua, ub)
            )
        # u_left - u_right over the modes of both buildings (a wall contributes nothing)
        terms, periods, damps = [], [], []
        for name, floor, sign in (
            (pair.left, pair.left_floor, LEFT_SIGN),
            (pair.right, pair.right_floor, RIGHT_SIGN),
        ):
            if name != WALL:
                i = index[name]
                terms.append(sign * contrib[i][:, floor - 1, :])
                periods.append(modals[i].periods)
                damps.append(modals[i].damping_ratios)
        cols["cqc_relative_spectral"] = combine_modes(
            np.concatenate(terms, axis=1), np.concatenate(periods), np.concatenate(damps), "cqc"
        )
        if pair.left_floor == 0 or pair.right_floor == 0:
            # fixed-base modes do not describe a sliding base slab
            cols["cqc_relative_spectral"] = np.full(n_rec, np.nan)
        u_el_a = end_values(pair, peak_cqc, "left")
        u_el_b = end_values(pair, peak_cqc, "right")
        if options.c_d is not None:
            dm_a, dm_b = (
                asce7_inelastic_displacement(
                    options.i_e * u / options.r, c_d=options.c_d, i_e=options.i_e
                )
                for u in (u_el_a, u_el_b)
            )
            cols["asce7_same_property"] = asce7_separation(dm_a, dm_b, same_property=True)
            cols["asce7_property_line"] = asce7_separation(dm_a, dm_b, same_property=False)
        if options.q is not None:
            ds_a, ds_b = (ec8_design_displacement(u / options.q, q_d=q_d) for u in (u_el_a, u_el_b))
            for key, same in (("ec8_same_property", True), ("ec8_property_line", False)):
                cols[key] = ec8_separation(
                    ds_a, ds_b, same_property=same, same_levels=pair.same_level
                )
        for e, name in enumerate(estimates):
            per_pair[:, p, e] = cols[name]

    interfaces = list(dict.fromkeys(p.interface for p in pairs))
    members = [np.array([p.interface == f for p in pairs]) for f in interfaces]
    required = np.stack([per_pair[:, m, :].max(axis=1) for m in members], axis=1)
    stats = np.stack(
        [
            np.median(required, axis=0),
            np.percentile(required, 84.0, axis=0),
            required.max(axis=0),
        ],
        axis=-1,
    )  # (interface, estimate, statistic)

    # probability of pounding versus gap, per interface
    gstar = required[:, :, estimates.index("time_history")]  # (record, interface)
    if options.gaps is not None:
        gap_grid = np.asarray(options.gaps, float)
    else:
        top = float(gstar.max()) if gstar.size and gstar.max() > 0 else 0.01
        gap_grid = np.linspace(0.0, 1.5 * top, 121)
    fits = [fit_lognormal(gstar[:, j]) for j in range(len(interfaces))]
    prob_emp = np.stack(
        [empirical_pounding_probability(gap_grid, gstar[:, j]) for j in range(len(interfaces))]
    )
    prob_ln = np.stack([lognormal_pounding_probability(gap_grid, f) for f in fits])
    g_target = np.array([gap_for_probability(options.target_probability, f) for f in fits])

    modes = np.arange(1, width + 1)
    data = {
        "natural_period": (("building", "mode"), _pad([m.periods for m in modals], width)),
        "modal_damping_ratio": (
            ("building", "mode"),
            _pad([m.damping_ratios for m in modals], width),
        ),
        "spectral_displacement": (("record", "building", "mode"), sd),
        "peak_displacement_time_history": (("record", "building", "floor"), peak_th),
        "peak_displacement_srss": (("record", "building", "floor"), peak_srss),
        "peak_displacement_cqc": (("record", "building", "floor"), peak_cqc),
        "exact_gap": (("record", "pair"), exact),
        "pair_correlation": (("pair",), rho_pair),
        "required_gap_pair": (("record", "pair", "estimate"), per_pair),
        "required_gap": (("record", "interface", "estimate"), required),
        "required_gap_statistic": (("interface", "estimate", "statistic"), stats),
        "pounding_probability": (("interface", "gap"), prob_emp),
        "pounding_probability_lognormal": (("interface", "gap"), prob_ln),
        "lognormal_median": (("interface",), np.array([f.median for f in fits])),
        "lognormal_beta": (("interface",), np.array([f.beta for f in fits])),
        "lognormal_fraction": (("interface",), np.array([f.fraction for f in fits])),
        "gap_for_target_probability": (("interface",), g_target),
        "case_gap": (("interface",), _case_gaps(case, interfaces)),
    }
    coords = {
        "record": _unique_names(grounds),
        **_pair_coords(pairs),
        "interface": interfaces,
        "estimate": estimates,
        "estimate_label": ("estimate", [ESTIMATES[e][0] for e in estimates]),
        "estimate_basis": ("estimate", [ESTIMATES[e][1] for e in estimates]),
        "statistic": list(STATISTICS),
        "gap": gap_grid,
        "building": [b.name for b in blds],
        "floor": modes,
        "mode": modes,
    }
    ds = xr.Dataset(data, coords=coords)
    _apply_attrs(ds)
    ds.attrs.update(
        {
            "title": case.title,
            "pounding_kind": "separation",
            "pounding_version": __version__,
            "created": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
            "Conventions": "CF-1.8",
            "sign_convention": (
                "displacements relative to ground, positive to the right; "
                "penetration = u_left - u_right - gap"
            ),
            "spectrum": options.spectrum,
            "spectrum_description": options.spectrum_description(),
            "method": th[0].method,
            "dt": float(th[0].dt),
            "duration": float(th[0].duration),
            "target_probability": options.target_probability,
            "n_records": n_rec,
            **{f"option_{k}": v for k, v in options.to_attrs().items()},
        }
    )
    return ds


def separation_table(ds: xr.Dataset) -> pd.DataFrame:
    """The comparison table of a :func:`separation_analysis` Dataset, one row per interface and estimate.

    Columns: ``interface``, ``estimate`` (key of :data:`ESTIMATES`), ``label``, ``basis`` (formula,
    clause and edition), ``median``, ``p84``, ``max`` [m] over the records; then one row per interface
    for the lognormal gap at the target probability (estimate ``lognormal_target``, the value in
    ``median``, NaN elsewhere).
    """
    stat = ds["required_gap_statistic"]
    p = float(ds.attrs.get("target_probability", np.nan))
    rows = []
    for f in ds["interface"].values:
        for e in ds["estimate"].values:
            values = stat.sel(interface=f, estimate=e)
            rows.append(
                {
                    "interface": str(f),
                    "estimate": str(e),
                    "label": str(ds["estimate_label"].sel(estimate=e).item()),
                    "basis": str(ds["estimate_basis"].sel(estimate=e).item()),
                    **{s: float(values.sel(statistic=s)) for s in STATISTICS},
                }
            )
        rows.append(
            {
                "interface": str(f),
                "estimate": "lognormal_target",
                "label": f"lognormal fit of the exact gaps, P(pounding) = {p:.3g}",
                "basis": (
                    f"median {float(ds['lognormal_median'].sel(interface=f)):.4g} m, "
                    f"beta {float(ds['lognormal_beta'].sel(interface=f)):.3g} "
                    "(maximum likelihood; Lin & Weng 2001)"
                ),
                "median": float(ds["gap_for_target_probability"].sel(interface=f)),
                "p84": np.nan,
                "max": np.nan,
            }
        )
    return pd.DataFrame(rows, columns=["interface", "estimate", "label", "basis", *STATISTICS])


def separation_summary(ds: xr.Dataset) -> dict[str, Any]:
    """What a report section needs: the comparison table and the probability curves, as plain data.

    Returns
    -------
    dict
        ``title``, ``records`` (names), ``spectrum`` (description), ``method``, ``dt`` [s],
        ``target_probability``, ``units`` ("m"), and ``interfaces``: a list with, per interface,
        ``name``, ``pairs`` (labels), ``exact_gaps`` (per record, largest over the pairs [m]),
        ``table`` (rows of :func:`separation_table` as dicts), ``lognormal`` (``median`` [m],
        ``beta``, ``fraction``, ``gap_for_target`` [m]) and ``curve`` (``gap`` [m], ``empirical``,
        ``lognormal``: probability of pounding at each gap).
    """
    table = separation_table(ds)
    out: dict[str, Any] = {
        "title": str(ds.attrs.get("title", "")),
        "records": [str(r) for r in ds["record"].values],
        "spectrum": str(ds.attrs.get("spectrum_description", "")),
        "method": str(ds.attrs.get("method", "")),
        "dt": float(ds.attrs.get("dt", np.nan)),
        "target_probability": float(ds.attrs.get("target_probability", np.nan)),
        "units": "m",
        "interfaces": [],
    }
    th = ds["required_gap"].sel(estimate="time_history")
    for f in ds["interface"].values:
        f = str(f)
        sel = ds["pair_interface"].values == f
        out["interfaces"].append(
            {
                "name": f,
                "pairs": [str(x) for x in ds["pair_label"].values[sel]],
                "exact_gaps": [float(x) for x in th.sel(interface=f).values],
                "table": table[table["interface"] == f]
                .drop(columns="interface")
                .to_dict("records"),
                "lognormal": {
                    "median": float(ds["lognormal_median"].sel(interface=f)),
                    "beta": float(ds["lognormal_beta"].sel(interface=f)),
                    "fraction": float(ds["lognormal_fraction"].sel(interface=f)),
                    "gap_for_target": float(ds["gap_for_target_probability"].sel(interface=f)),
                },
                "curve": {
                    "gap": [float(x) for x in ds["gap"].values],
                    "empirical": [
                        float(x) for x in ds["pounding_probability"].sel(interface=f).values
                    ],
                    "lognormal": [
                        float(x)
                        for x in ds["pounding_probability_lognormal"].sel(interface=f).values
                    ],
                },
            }
        )
    return out
