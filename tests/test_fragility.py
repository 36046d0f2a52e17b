"""Lognormal fragility fitting (Baker 2015) and the intensity measures that scale records: reference
fits, recovery of known parameters from synthetic data, equality with a direct optimisation written
here, bootstrap standard errors, and the measures against their definitions."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import optimize, stats

from pounding import PoundingInputError
from pounding.ground_motion import GroundMotion, sine_pulse
from pounding.risk import IntensityMeasure, bootstrap, fit_ida, fit_stripes
from pounding.spectra import response_spectrum


def test_stripes_fit_of_the_reference_example():
    # x = (1, 1.5, 2), 54 analyses each, 2, 25, 43 collapses → θ = 1.5725, β = 0.2700
    fit = fit_stripes([1.0, 1.5, 2.0], [54, 54, 54], [2, 25, 43])
    assert fit.median == pytest.approx(1.5725, abs=5e-5)
    assert fit.beta == pytest.approx(0.2700, abs=5e-5)
    assert fit.method == "stripes_mle" and fit.n == 162


def test_ida_moments_of_the_reference_example():
    # ln θ = mean ln x, β = std(ln x, ddof = 1): θ = 1.0954, β = 0.4334
    fit = fit_ida([0.6, 0.8, 1.0, 1.2, 1.5, 2.0])
    assert fit.median == pytest.approx(1.0954, abs=5e-5)
    assert fit.beta == pytest.approx(0.4334, abs=5e-5)
    assert fit.probability(fit.median) == pytest.approx(0.5)


def _synthetic(theta: float, beta: float, n_records: int, seed: int) -> np.ndarray:
    return theta * np.exp(beta * np.random.default_rng(seed).standard_normal(n_records))


def test_stripes_fit_recovers_a_known_fragility_from_200_records_and_10_stripes():
    theta, beta = 0.8, 0.4
    capacity = _synthetic(theta, beta, 200, seed=3)
    levels = theta * np.exp(beta * np.linspace(-2.0, 2.0, 10))
    reached = (capacity[None, :] <= levels[:, None]).sum(axis=1)
    fit = fit_stripes(levels, np.full(10, 200), reached)
    assert abs(fit.median / theta - 1.0) < 0.03
    assert abs(fit.beta / beta - 1.0) < 0.10


def test_stripes_fit_equals_a_direct_binomial_likelihood_maximisation():
    levels = np.array([0.2, 0.4, 0.6, 0.8, 1.0, 1.3])
    n = np.array([40, 40, 40, 40, 40, 40])
    z = np.array([0, 3, 11, 22, 30, 37])

    def nll(q):
        p = stats.norm.cdf(np.log(levels / q[0]) / q[1])
        return -np.sum(stats.binom.logpmf(z, n, np.clip(p, 1e-300, 1.0 - 1e-16)))

    ref = optimize.minimize(nll, [0.7, 0.5], method="L-BFGS-B", bounds=[(0.05, 5), (0.05, 3)],
                            options=dict(ftol=1e-15, gtol=1e-12))  # fmt: skip
    fit = fit_stripes(levels, n, z)
    assert fit.median == pytest.approx(ref.x[0], rel=1e-5)
    assert fit.beta == pytest.approx(ref.x[1], rel=1e-4)


def test_truncated_ida_fit_equals_a_direct_censored_likelihood_maximisation():
    capacity = _synthetic(1.0, 0.5, 60, seed=11)
    x_max = 1.4
    data = np.where(capacity <= x_max, capacity, np.inf)
    reached = data[np.isfinite(data)]
    n_out = int(np.isinf(data).sum())
    assert 5 < n_out < 30

    def nll(q):
        mu, b = q
        ll = stats.norm.logpdf(np.log(reached), mu, b).sum() - np.log(reached).sum()
        return -(ll + n_out * stats.norm.logsf(np.log(x_max), mu, b))

    ref = optimize.minimize(nll, [0.0, 0.4], method="L-BFGS-B", bounds=[(-3, 3), (0.05, 3)],
                            options=dict(ftol=1e-15, gtol=1e-12))  # fmt: skip
    fit = fit_ida(data, censored_above=x_max)
    assert fit.method == "truncated_mle"
    assert math.log(fit.median) == pytest.approx(ref.x[0], abs=1e-5)
    assert fit.beta == pytest.approx(ref.x[1], rel=1e-4)
    # ignoring the censored records would bias the median low
    assert fit.median > fit_ida(reached).median * 1.05


def test_bootstrap_standard_error_of_the_median_is_beta_over_root_n():
    theta, beta, n = 1.2, 0.45, 80
    capacity = _synthetic(theta, beta, n, seed=5)
    fit = bootstrap(fit_ida(capacity), capacity, n_boot=2000, level=0.9, seed=1)
    se = np.log(fit.samples[:, 0]).std()
    assert se == pytest.approx(fit.beta / math.sqrt(n), rel=0.15)
    assert fit.median_ci[0] < fit.median < fit.median_ci[1]
    assert fit.beta_ci[0] < fit.beta < fit.beta_ci[1]
    lo, hi = fit.band([fit.median])
    assert lo[0] < 0.5 < hi[0]


def test_parametric_stripe_bootstrap_brackets_the_fit():
    fit = fit_stripes([1.0, 1.5, 2.0], [54, 54, 54], [2, 25, 43])
    boot = bootstrap(fit, stripes=([1.0, 1.5, 2.0], [54, 54, 54], [2, 25, 43]), n_boot=300)
    assert boot.median_ci[0] < 1.5725 < boot.median_ci[1]
    assert boot.median_ci[1] / boot.median_ci[0] < 1.2


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: fit_ida([1.0, -2.0]), "capacities[1] = -2.0; allowed: intensities > 0"),
        (lambda: fit_ida([1.0, np.inf, np.inf]), "1 of 3 records reached"),
        (lambda: fit_ida([1.0, 2.0, np.inf]), "give censored_above"),
        (lambda: fit_stripes([1.0, 2.0], [10, 10], [10, 10]), "every analysis reached"),
        (lambda: fit_stripes([1.0, 2.0], [10], [1, 2]), "2 levels, 1 analysis counts"),
        # none, then 2 of 3, then all: the likelihood grows as β → 0 (a step at the median)
        (lambda: fit_stripes([0.5, 1.0, 1.5], [3, 3, 3], [0, 2, 3]), "dispersion cannot be"),
        (lambda: IntensityMeasure("sa_t1"), "allowed: pga, sa, sa_avg"),
        (
            lambda: IntensityMeasure("sa"),
            "period = None; allowed: a number >= 1e-05 and <= 100 [s]",
        ),
        # an IDA's im period of 1e300 s divided by zero in the spectrum's oscillator (fuzzed)
        (
            lambda: IntensityMeasure("sa", period=1e300),
            "period = 1e+300; allowed: a number >= 1e-05",
        ),
        (
            lambda: IntensityMeasure("sa_avg", period_low=1e-300, period_high=1.0),
            "period_low = 1e-300; allowed: a number >= 1e-05 and <= 100 [s]",
        ),
    ],
)
def test_bad_fragility_and_intensity_input_is_refused_naming_the_field(call, message):
    with pytest.raises(PoundingInputError) as err:
        call()
    assert message in str(err.value)


def test_intensity_measures_match_their_definitions_on_the_spectrum():
    gm = sine_pulse(amplitude=3.0, period=0.7, duration=6.0, dt=0.005)
    assert IntensityMeasure("pga").of(gm) == pytest.approx(np.abs(gm.acceleration).max())
    spectrum = response_spectrum(gm, [0.5], 0.05)
    sa = IntensityMeasure("sa", period=0.5)
    assert sa.of(gm) == pytest.approx(float(spectrum.PSa.sel(period=0.5)), rel=1e-12)
    avg = IntensityMeasure("sa_avg", period_low=0.1, period_high=1.5, n_periods=10)
    psa = response_spectrum(gm, avg.periods, 0.05).PSa.values
    assert avg.of(gm) == pytest.approx(float(np.exp(np.log(psa).mean())), rel=1e-12)
    assert avg.periods[0] == pytest.approx(0.1) and avg.periods[-1] == pytest.approx(1.5)


def test_scaling_a_record_to_a_target_intensity_is_exact_for_every_measure():
    gm = sine_pulse(amplitude=2.0, period=0.4, duration=5.0, dt=0.004)
    for im in (
        IntensityMeasure("pga"),
        IntensityMeasure("sa", period=0.8),
        IntensityMeasure.for_periods("sa_avg", [0.3, 1.0]),
    ):
        sf = im.scale_factor(gm, 4.0)
        scaled = GroundMotion(sf * gm.acceleration, gm.dt)
        assert im.of(scaled) == pytest.approx(4.0, rel=1e-10), im.measure
    avg = IntensityMeasure.for_periods("sa_avg", [0.3, 1.0])
    assert (avg.period_low, avg.period_high) == pytest.approx((0.06, 3.0))
