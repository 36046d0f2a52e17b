"""Separation rules as pure formulas: modal correlation and combination, ABS/SRSS/DDC gaps, modal
spectral displacements, and the ASCE 7 and Eurocode 8 code rules."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from pounding.errors import PoundingInputError
from pounding.ground_motion import GroundMotion
from pounding.spectra import (
    design_spectrum,
    spectral_peaks,
)
from pounding.structure import ShearBuilding

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
    r"""Absolute-sum separation :math:`S = |u_A| + |u_B|` [m] ([3]_, [4]_): the two peaks in opposite phase."""
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
    :math:`S = |u_A - u_B|` (the buildings move in phase); widely separated periods give ρ → 0 and the SRSS.

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
