r"""FEMA P695 collapse-margin arithmetic: from the collapse intensities of a record set to the
adjusted collapse margin ratio and its acceptance [1]_.

Spectral accelerations are in g (as P695 writes them), periods in s, displacements in m.

MCE demand (P695 Ch. 5; the seismic design categories' MCE spectral parameters, ``SDC_SPECTRA``):

    S_MT(T) = S_MS              for T ≤ T_s = S_M1/S_MS
    S_MT(T) = S_M1/T            for T > T_s

with T = C_u T_a ≥ 0.25 s the archetype's fundamental period (Ch. 5): a period given below 0.25 s
is clipped to 0.25 s everywhere in this module.

Collapse margin ratio (Sec. 6.4) and its spectral-shape adjustment (Sec. 7.2, Eq. 7-1):

    CMR = Ŝ_CT / S_MT,          ACMR = SSF × CMR

with Ŝ_CT the median collapse intensity Sa(T) of the record set, the intensity at which half of
the records have caused collapse. Spectral shape factor (Appendix B, Eqs. B-1, B-3, B-4; it
reproduces Tables 7-1a and 7-1b to their 0.01):

    SSF = exp[β1 (ε̄0 − ε̄(T))],      β1 = 0.14 (μ_T − 1)^0.42  (μ_T capped at 8)

ε̄0 (``EPSILON_0``) = 1.5 for SDC Dmax, 1.0 for SDC B, C and Dmin; the far-field record set's mean
ε̄(T) = 0.6 for T ≤ 0.5 s, 0.6 (1.5 − T) for 0.5 < T < 1.5 s, 0 for T ≥ 1.5 s.

Total system collapse uncertainty (Sec. 7.3, Eq. 7-5):

    β_TOT = √(β_RTR² + β_DR² + β_TD² + β_MDL²),     β_RTR = 0.1 + 0.1 μ_T ≤ 0.4

with the quality ratings (``RATINGS``) of the design requirements, the test data and the
nonlinear model: A (superior) 0.10, B (good) 0.20, C (fair) 0.35, D (poor) 0.50; P695 rounds
β_TOT to the nearest 0.025 (Tables 7-2a to 7-2d).

Acceptable ACMR (Sec. 7.4, Table 7-3), the lognormal collapse fragility with median ACMR × S_MT
and dispersion β_TOT giving a collapse probability x at the MCE:

    ACMR_x = exp(−Φ⁻¹(x) β_TOT),        P(collapse | S_MT) = Φ(−ln ACMR / β_TOT)

Acceptance (Sec. 7.5): each archetype ACMR ≥ ACMR20 %, the mean of a performance group
≥ ACMR10 %.

Period-based ductility (Sec. 6.3, Eq. 6-7), from the pushover curve:

    μ_T = δ_u / δ_y,eff,        δ_y,eff = C0 (V_max/W) (g/4π²) max(T, T1)²

with δ_u the roof drift displacement at 20 % loss of the peak base shear V_max, W the seismic
weight, T1 the fundamental period of the model and C0 the roof-to-SDOF displacement factor.

References
----------
.. [1] FEMA (2009). Quantification of Building Seismic Performance Factors, FEMA P695. Federal
   Emergency Management Agency, Washington, D.C. (ATC-63 project): Ch. 5 (SDC spectra, the
   fundamental period), Sec. 6.3 (period-based ductility, Eq. 6-7), Sec. 6.4 (CMR), Sec. 7.2
   (SSF, Eq. 7-1, Tables 7-1a/7-1b), Sec. 7.3 (β_TOT, Eq. 7-5, Tables 7-2a-d), Sec. 7.4
   (Table 7-3), Sec. 7.5 (acceptance), Appendix B (Eqs. B-1, B-3, B-4).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from statistics import NormalDist
from typing import Any

import numpy as np

from pounding.errors import PoundingInputError
from pounding.units import G

__all__ = [
    "EPSILON_0",
    "MIN_PERIOD",
    "RATINGS",
    "SDC_SPECTRA",
    "CollapseMargin",
    "acceptable_acmr",
    "collapse_margin",
    "mce_spectral_acceleration",
    "period_based_ductility",
    "spectral_shape_factor",
    "total_uncertainty",
]

#: MCE spectral parameters (S_MS, S_M1) [g] of the seismic design categories (FEMA P695 Ch. 5).
SDC_SPECTRA: dict[str, tuple[float, float]] = {
    "Dmax": (1.50, 0.90),
    "Dmin": (0.75, 0.30),
    "Cmax": (0.75, 0.30),
    "Cmin": (0.50, 0.20),
    "Bmax": (0.50, 0.20),
    "Bmin": (0.25, 0.10),
}

#: Target mean ε̄0 of the rare MCE ground motions by SDC (FEMA P695 Appendix B, Sec. B.3).
EPSILON_0: dict[str, float] = {
    "Dmax": 1.5,
    "Dmin": 1.0,
    "Cmax": 1.0,
    "Cmin": 1.0,
    "Bmax": 1.0,
    "Bmin": 1.0,
}

#: Collapse uncertainty β [-] of a quality rating (FEMA P695 Sec. 7.3: design requirements, test
#: data, nonlinear model; A superior, B good, C fair, D poor).
RATINGS: dict[str, float] = {"A": 0.10, "B": 0.20, "C": 0.35, "D": 0.50}

#: Lower bound of the fundamental period T = C_u T_a [s] (FEMA P695 Ch. 5).
MIN_PERIOD = 0.25

#: μ_T above which the spectral shape factor no longer grows (FEMA P695 Tables 7-1a/b, "≥ 8").
_SSF_DUCTILITY_CAP = 8.0
#: Upper bound of the record-to-record uncertainty β_RTR (FEMA P695 Sec. 7.3).
_BETA_RTR_MAX = 0.4
#: β_TOT is rounded to the nearest multiple of this (FEMA P695 Tables 7-2a-d).
_BETA_STEP = 0.025

_NORMAL = NormalDist()


# ---------------------------------------------------------------------------------------------
# Input checks
# ---------------------------------------------------------------------------------------------


def _number(value: Any, field: str, allowed: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise PoundingInputError(f"{field} = {value!r}; allowed: {allowed}") from None
    if not math.isfinite(v):
        raise PoundingInputError(f"{field} = {value!r}; allowed: {allowed}")
    return v


def _positive(value: Any, field: str, unit: str = "") -> float:
    allowed = f"a positive number{f' [{unit}]' if unit else ''}"
    v = _number(value, field, allowed)
    if v <= 0.0:
        raise PoundingInputError(f"{field} = {value!r}; allowed: {allowed}")
    return v


def _period(period: Any, field: str = "period") -> float:
    """The period [s] P695 uses: positive, clipped below at 0.25 s."""
    return max(_positive(period, field, "s"), MIN_PERIOD)


def _ductility(ductility: Any, field: str = "ductility") -> float:
    v = _number(ductility, field, "a number ≥ 1")
    if v < 1.0:
        raise PoundingInputError(f"{field} = {ductility!r}; allowed: a number ≥ 1")
    return v


def _sdc(sdc: Any) -> str:
    if not isinstance(sdc, str) or sdc not in SDC_SPECTRA:
        raise PoundingInputError(f"sdc = {sdc!r}; allowed: {', '.join(SDC_SPECTRA)}")
    return sdc


def _rating(rating: Any, field: str) -> float:
    if not isinstance(rating, str) or rating not in RATINGS:
        raise PoundingInputError(f"{field} = {rating!r}; allowed: {', '.join(RATINGS)}")
    return RATINGS[rating]


# ---------------------------------------------------------------------------------------------
# Demand, spectral shape, uncertainty, acceptable margins
# ---------------------------------------------------------------------------------------------


def mce_spectral_acceleration(period: float, sdc: str) -> float:
    r"""MCE spectral acceleration S_MT(T) [g] of a seismic design category (FEMA P695 Ch. 5).

    .. math::

        S_{MT} = S_{MS} \ \ (T \le S_{M1}/S_{MS}), \qquad S_{MT} = S_{M1}/T \ \ (T > S_{M1}/S_{MS})

    Parameters
    ----------
    period : float
        Fundamental period T = C_u T_a [s] > 0; below 0.25 s it is taken as 0.25 s.
    sdc : {"Dmax", "Dmin", "Cmax", "Cmin", "Bmax", "Bmin"}
        Seismic design category (``SDC_SPECTRA``).
    """
    s_ms, s_m1 = SDC_SPECTRA[_sdc(sdc)]
    t = _period(period)
    t_s = s_m1 / s_ms
    # the corner period itself (0.4 s, 0.6 s) is on the plateau, whatever the rounding of S_M1/S_MS
    return s_ms if t <= t_s or math.isclose(t, t_s, rel_tol=1e-12) else s_m1 / t


def _mean_epsilon_far_field(period: float) -> float:
    """Mean ε̄(T) of the far-field record set (FEMA P695 Appendix B, Eq. B-1)."""
    if period <= 0.5:
        return 0.6
    if period >= 1.5:
        return 0.0
    return 0.6 * (1.5 - period)


def spectral_shape_factor(period: float, ductility: float, sdc: str) -> float:
    r"""Spectral shape factor SSF [-] for the far-field record set (FEMA P695 Appendix B).

    .. math::

        \mathrm{SSF} = \exp[\beta_1(\bar\varepsilon_0 - \bar\varepsilon(T))], \qquad
        \beta_1 = 0.14\,(\mu_T - 1)^{0.42}

    (Eqs. B-4 and B-3; μ_T capped at 8), ε̄0 from ``EPSILON_0`` (1.5 for SDC Dmax, 1.0 otherwise)
    and ε̄(T) of Eq. B-1 (0.6 up to 0.5 s, linear to 0 at 1.5 s). Rounded to 0.01 it gives every
    entry of Tables 7-1a (SDC B, C, Dmin) and 7-1b (SDC Dmax).

    Parameters
    ----------
    period : float
        Fundamental period T [s] > 0 (below 0.25 s taken as 0.25 s; no effect: ε̄ is constant
        up to 0.5 s).
    ductility : float
        Period-based ductility μ_T ≥ 1 (:func:`period_based_ductility`).
    sdc : {"Dmax", "Dmin", "Cmax", "Cmin", "Bmax", "Bmin"}
    """
    eps0 = EPSILON_0[_sdc(sdc)]
    t = _period(period)
    mu = min(_ductility(ductility), _SSF_DUCTILITY_CAP)
    beta1 = 0.14 * (mu - 1.0) ** 0.42
    return math.exp(beta1 * (eps0 - _mean_epsilon_far_field(t)))


def total_uncertainty(
    ductility: float, design: str, test: str, model: str, *, rounded: bool = True
) -> float:
    r"""Total system collapse uncertainty β_TOT [-] (FEMA P695 Sec. 7.3, Eq. 7-5).

    .. math::

        \beta_{TOT} = \sqrt{\beta_{RTR}^2 + \beta_{DR}^2 + \beta_{TD}^2 + \beta_{MDL}^2},
        \qquad \beta_{RTR} = \min(0.1 + 0.1\,\mu_T,\ 0.4)

    Parameters
    ----------
    ductility : float
        Period-based ductility μ_T ≥ 1 (sets the record-to-record uncertainty β_RTR).
    design, test, model : {"A", "B", "C", "D"}
        Quality ratings of the design requirements (β_DR), the test data (β_TD) and the
        nonlinear model (β_MDL): ``RATINGS`` (0.10, 0.20, 0.35, 0.50).
    rounded : bool
        Round to the nearest 0.025 (halves up), as Tables 7-2a-d do (default); False gives the
        unrounded value.
    """
    mu = _ductility(ductility)
    betas = (
        min(0.1 + 0.1 * mu, _BETA_RTR_MAX),
        _rating(design, "design"),
        _rating(test, "test"),
        _rating(model, "model"),
    )
    beta = math.sqrt(sum(b * b for b in betas))
    if not rounded:
        return beta
    steps = 1.0 / _BETA_STEP
    return math.floor(beta * steps + 0.5) / steps


def acceptable_acmr(beta_total: float, probability: float) -> float:
    r"""Acceptable adjusted collapse margin ratio ACMR_x [-] (FEMA P695 Sec. 7.4, Table 7-3).

    .. math:: \mathrm{ACMR}_x = \exp(-\Phi^{-1}(x)\,\beta_{TOT})

    the ACMR at which a lognormal collapse fragility of dispersion β_TOT gives the probability x
    of collapse at the MCE (Table 7-3: x = 5, 10, 15, 20, 25 %).

    Parameters
    ----------
    beta_total : float
        Total system collapse uncertainty β_TOT > 0 (:func:`total_uncertainty`).
    probability : float
        Collapse probability x at the MCE, in (0, 1) (0.10 for ACMR10 %, 0.20 for ACMR20 %).
    """
    beta = _positive(beta_total, "beta_total")
    x = _number(probability, "probability", "a number in (0, 1)")
    if not 0.0 < x < 1.0:
        raise PoundingInputError(f"probability = {probability!r}; allowed: a number in (0, 1)")
    return math.exp(-_NORMAL.inv_cdf(x) * beta)


def period_based_ductility(
    ultimate_roof_drift: float,
    max_base_shear_coefficient: float,
    period: float,
    t1: float,
    c0: float,
) -> float:
    r"""Period-based ductility μ_T [-] from a pushover curve (FEMA P695 Sec. 6.3).

    .. math::

        \mu_T = \frac{\delta_u}{\delta_{y,eff}}, \qquad
        \delta_{y,eff} = C_0\,\frac{V_{max}}{W}\,\frac{g}{4\pi^2}\,[\max(T, T_1)]^2 \quad
        \text{(Eq. 6-7)}

    δ_y,eff is the roof displacement of an SDOF oscillator of period max(T, T1) yielding at the
    base shear coefficient V_max/W, carried to the roof by C0.

    Parameters
    ----------
    ultimate_roof_drift : float
        δ_u [m], the roof drift displacement at which the base shear has dropped to 80 % of
        V_max (or the drift at which the model stops being valid, if smaller).
    max_base_shear_coefficient : float
        V_max/W [-], the peak pushover base shear over the seismic weight.
    period : float
        Fundamental period T = C_u T_a [s] (below 0.25 s taken as 0.25 s).
    t1 : float
        Fundamental period of the nonlinear model from eigenvalue analysis [s].
    c0 : float
        C0 [-], roof displacement of the fundamental mode over the SDOF displacement
        (φ_1,r Σ m_x φ_1,x / Σ m_x φ_1,x² with the mode shape φ_1).

    Returns
    -------
    float
        μ_T (values below 1 are returned as computed: P695 uses μ_T ≥ 1 downstream).
    """
    delta_u = _positive(ultimate_roof_drift, "ultimate_roof_drift", "m")
    cs = _positive(max_base_shear_coefficient, "max_base_shear_coefficient")
    t = _period(period)
    t1 = _positive(t1, "t1", "s")
    c0 = _positive(c0, "c0")
    delta_y = c0 * cs * G / (4.0 * math.pi**2) * max(t, t1) ** 2
    return delta_u / delta_y


# ---------------------------------------------------------------------------------------------
# Collapse margin of a record set
# ---------------------------------------------------------------------------------------------


def _median_collapse(collapse_sa: Any, censored_above: float | None) -> tuple[float, int, int]:
    """(Ŝ_CT [g], n_records, n_censored) of per-record collapse intensities, right-censored."""
    try:
        sa = np.atleast_1d(np.asarray(collapse_sa, dtype=float))
    except (TypeError, ValueError):
        raise PoundingInputError(
            f"collapse_sa = {collapse_sa!r}; allowed: one collapse Sa(T) [g] per record"
        ) from None
    if sa.ndim != 1 or sa.size == 0:
        raise PoundingInputError(
            f"collapse_sa has shape {sa.shape}; allowed: a non-empty 1-D sequence, "
            "one collapse Sa(T) [g] per record"
        )
    bad = np.flatnonzero(~np.isnan(sa) & ~(sa > 0.0))
    if bad.size:
        i = int(bad[0])
        raise PoundingInputError(
            f"collapse_sa[{i}] = {float(sa[i])!r}; allowed: a positive Sa(T) [g], or inf/NaN "
            "for a record that did not collapse"
        )
    limit = None if censored_above is None else _positive(censored_above, "censored_above", "g")
    censored = ~np.isfinite(sa)
    if limit is not None:
        censored |= sa > limit
    n, n_c = int(sa.size), int(np.count_nonzero(censored))
    if 2 * n_c >= n:
        if limit is None:
            finite = sa[~censored]
            limit = float(finite.max()) if finite.size else None
        level = "the largest level analysed" if limit is None else f"{limit:g} g"
        share = "more than half" if 2 * n_c > n else "half"
        raise PoundingInputError(
            f"CMR undefined: {share} of the records ({n_c} of {n}) did not collapse up to {level}"
        )
    # the censored records rank above every collapse; fewer than half of them keeps the middle
    # order statistic(s) among the collapses
    ranked = np.where(censored, np.inf, sa)
    return float(np.median(ranked)), n, n_c


@dataclass(frozen=True)
class CollapseMargin:
    """The FEMA P695 collapse margin of one archetype (:func:`collapse_margin`).

    Attributes
    ----------
    period : float
        Fundamental period T [s] used (the one given, at least 0.25 s).
    sdc : str
        Seismic design category.
    s_mt : float
        MCE spectral acceleration S_MT(T) [g].
    median_collapse_sa : float
        Median collapse intensity Ŝ_CT [g] of the record set.
    cmr : float
        Collapse margin ratio Ŝ_CT/S_MT [-].
    ssf : float
        Spectral shape factor [-].
    acmr : float
        Adjusted collapse margin ratio SSF × CMR [-].
    beta_total : float
        Total system collapse uncertainty β_TOT [-] (rounded to 0.025).
    acmr10, acmr20 : float
        Acceptable ACMR for 10 % and 20 % probability of collapse at the MCE [-].
    p_collapse_mce : float
        Probability of collapse at the MCE, Φ(−ln ACMR/β_TOT) [-].
    passes : bool
        ACMR ≥ ACMR20 % (the individual-archetype criterion).
    n_records, n_censored : int
        Records in the set, and those that did not collapse up to the largest level analysed.
    """

    period: float
    sdc: str
    s_mt: float
    median_collapse_sa: float
    cmr: float
    ssf: float
    acmr: float
    beta_total: float
    acmr10: float
    acmr20: float
    p_collapse_mce: float
    passes: bool
    n_records: int
    n_censored: int

    def to_dict(self) -> dict[str, Any]:
        """The fields as plain Python values (JSON-ready)."""
        return asdict(self)


def collapse_margin(
    collapse_sa: Any,
    period: float,
    ductility: float,
    sdc: str = "Dmax",
    design: str = "B",
    test: str = "B",
    model: str = "B",
    censored_above: float | None = None,
) -> CollapseMargin:
    r"""FEMA P695 collapse margin of an archetype from the collapse intensities of its record set.

    CMR = Ŝ_CT/S_MT (Sec. 6.4), ACMR = SSF × CMR (Eq. 7-1), β_TOT (Eq. 7-5), ACMR10 %/20 %
    (Table 7-3), P(collapse | S_MT) = Φ(−ln ACMR/β_TOT) and the check ACMR ≥ ACMR20 % (Sec. 7.5).

    Ŝ_CT is the median of the records' collapse intensities (the mean of the two middle ones for
    an even count). Records that did not collapse are right-censored: they rank above every
    collapse, so the median is still defined while fewer than half of the records are censored;
    otherwise a :class:`~pounding.errors.PoundingInputError` says "CMR undefined".

    Parameters
    ----------
    collapse_sa : array_like, shape (n_records,)
        Collapse intensity Sa(T) [g] of each record (the lowest spectral acceleration at the
        period T at which it caused collapse); ``np.inf`` or NaN for a record that did not
        collapse.
    period : float
        Fundamental period T = C_u T_a [s] (below 0.25 s taken as 0.25 s).
    ductility : float
        Period-based ductility μ_T ≥ 1 (:func:`period_based_ductility`).
    sdc : {"Dmax", "Dmin", "Cmax", "Cmin", "Bmax", "Bmin"}
    design, test, model : {"A", "B", "C", "D"}
        Quality ratings of the design requirements, test data and nonlinear model.
    censored_above : float, optional
        Largest intensity Sa(T) [g] analysed: entries above it count as censored too, and it is
        the level quoted when the CMR is undefined. Without it, inf/NaN entries are taken to lie
        above every finite one.
    """
    t = _period(period)
    sdc = _sdc(sdc)
    mu = _ductility(ductility)
    beta = total_uncertainty(mu, design, test, model)
    s_ct, n, n_c = _median_collapse(collapse_sa, censored_above)
    s_mt = mce_spectral_acceleration(t, sdc)
    cmr = s_ct / s_mt
    ssf = spectral_shape_factor(t, mu, sdc)
    acmr = ssf * cmr
    acmr10 = acceptable_acmr(beta, 0.10)
    acmr20 = acceptable_acmr(beta, 0.20)
    return CollapseMargin(
        period=t,
        sdc=sdc,
        s_mt=s_mt,
        median_collapse_sa=s_ct,
        cmr=cmr,
        ssf=ssf,
        acmr=acmr,
        beta_total=beta,
        acmr10=acmr10,
        acmr20=acmr20,
        p_collapse_mce=_NORMAL.cdf(-math.log(acmr) / beta),
        passes=bool(acmr >= acmr20),
        n_records=n,
        n_censored=n_c,
    )
