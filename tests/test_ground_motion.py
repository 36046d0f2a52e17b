"""Ground-motion processing steps and intensity measures against closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pounding.ground_motion import (
    INTENSITY_MEASURES,
    PROCESSING_STEPS,
    GroundMotion,
    arias_intensity,
    bandpass,
    baseline_correct,
    cumulative_absolute_velocity,
    free_vibration_tail,
    ground_displacement,
    ground_velocity,
    harmonic,
    intensity_measures,
    mean_period,
    predominant_period,
    process,
    remove_mean,
    resample,
    scale_to_pga,
    scale_to_sa,
    significant_duration,
    sine_pulse,
    taper,
    trim_significant,
    zero_pad,
)
from pounding.spectra import response_spectrum
from pounding.units import G


def sine(amp=2.0, freq=2.0, duration=10.0, dt=0.001) -> GroundMotion:
    t = np.arange(0.0, duration + dt / 2, dt)
    return GroundMotion(amp * np.sin(2 * np.pi * freq * t), dt, name="sine")


# --- integration and intensity measures ---------------------------------------------------


def test_sine_pulse_pgv_pgd_closed_form():
    # a_g = A sin(2πt/T) for one period: v = A T/(2π)(1 - cos), peak A T/π at T/2;
    # u(T) = A T²/(2π), constant afterwards (velocity back to zero)
    amp, period = 3.0, 0.5
    gm = sine_pulse(amplitude=amp, period=period, duration=2.0, dt=0.001)
    im = intensity_measures(gm)
    assert im["pgv"] == pytest.approx(amp * period / math.pi, rel=1e-4)  # sampled sine
    assert im["pgd"] == pytest.approx(amp * period**2 / (2 * math.pi), rel=1e-4)
    assert ground_velocity(gm)[-1] == pytest.approx(0.0, abs=1e-5)


def test_integration_is_exact_for_linear_acceleration():
    # a = c t: v = c t²/2, u = c t³/6 exactly for a piecewise-linear record
    c, dt = 1.7, 0.05
    gm = GroundMotion(c * dt * np.arange(41), dt)
    t = gm.time
    np.testing.assert_allclose(ground_velocity(gm), c * t**2 / 2, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(ground_displacement(gm), c * t**3 / 6, rtol=1e-12, atol=1e-14)


def test_arias_cav_durations_of_a_steady_sine():
    # Arias (1970): I_a = π/(2g) ∫a² dt = π/(2g) A² D/2 over whole cycles;
    # CAV = ∫|a| dt = 2 A D/π; the Husid curve is a straight line so D5-95 ≈ 0.9 D
    amp, duration = 2.0, 10.0
    gm = sine(amp=amp, duration=duration)
    assert arias_intensity(gm) == pytest.approx(math.pi / (2 * G) * amp**2 * duration / 2, rel=1e-4)
    assert cumulative_absolute_velocity(gm) == pytest.approx(2 * amp * duration / math.pi, rel=1e-4)
    assert significant_duration(gm) == pytest.approx(0.9 * duration, rel=2e-3)
    assert significant_duration(gm, end=0.75) == pytest.approx(0.7 * duration, rel=2e-3)


def test_cav_exact_across_sign_changes():
    # triangle [0, 1, -1, 0] at dt = 1: |a| integrates to 0.5 + 2*(0.25) + 0.5 = 1.5
    gm = GroundMotion([0.0, 1.0, -1.0, 0.0], 1.0)
    assert cumulative_absolute_velocity(gm) == pytest.approx(1.5)


def test_periods_of_a_harmonic():
    gm = sine(freq=2.0, duration=20.0, dt=0.005)
    assert predominant_period(gm) == pytest.approx(0.5, rel=1e-3)
    assert mean_period(gm) == pytest.approx(0.5, rel=2e-2)


def test_intensity_measures_keys_units_and_pga_time():
    gm = GroundMotion([0.0, 0.1, -0.5, 0.2, 0.0], 0.01)
    im = intensity_measures(gm)
    assert set(im) == set(INTENSITY_MEASURES)
    assert im["pga"] == 0.5 and im["pga_time"] == pytest.approx(0.02)
    assert all(units for _, units, _ in INTENSITY_MEASURES.values())
    zero = intensity_measures(GroundMotion([0.0, 0.0, 0.0], 0.01))
    assert math.isnan(zero["d5_95"])


# --- processing -----------------------------------------------------------------------------


def test_baseline_correction_removes_a_polynomial_drift_exactly():
    # a = c0 + c1 t gives a cubic displacement, which a degree-3 fit removes entirely
    t = np.arange(0, 10.001, 0.01)
    gm = GroundMotion(0.05 + 0.02 * t, 0.01)
    corrected = baseline_correct(gm, order=3)
    assert np.max(np.abs(corrected.acceleration)) < 1e-9
    assert corrected.metadata["processing"] == [
        "baseline correction: degree-3 polynomial fitted on displacement"
    ]


def test_baseline_correction_leaves_no_residual_velocity_drift():
    # Boore & Bommer (2005): a record ending with a residual velocity v_r has a displacement that grows
    # like v_r t. The corrected record must not drift: a step in velocity (a short acceleration pulse
    # with non-zero area) leaves the displacement bounded instead of ending far from zero.
    dt = 0.01
    a = np.zeros(2001)
    a[100:110] = 1.0  # Δv = 0.1 m/s, then a constant-velocity drift of 0.1 m/s × ~19 s
    gm = GroundMotion(a, dt)
    assert ground_displacement(gm)[-1] > 1.8
    d = ground_displacement(baseline_correct(gm, order=3))
    # least squares over the record: the end sits near the fitted curve, an order below v_r t
    assert abs(d[-1]) < 0.1 * ground_displacement(gm)[-1]


def test_baseline_correction_keeps_signal_and_kills_offset():
    # the correction is linear and annihilates a constant offset (quadratic displacement); a motion
    # that starts and ends at rest, d(t) = sin²(πt/T) sin(ωt), has no baseline and is kept
    dt, T, w = 0.01, 20.0, 2 * np.pi
    t = np.arange(0.0, T + dt / 2, dt)
    d = np.sin(np.pi * t / T) ** 2 * np.sin(w * t)
    acc = np.gradient(np.gradient(d, dt), dt)
    acc[0] = 0.0
    gm = GroundMotion(acc, dt)
    drifted = gm.replace(acceleration=gm.acceleration + 0.03)
    corrected = baseline_correct(drifted, order=2)
    np.testing.assert_allclose(
        corrected.acceleration, baseline_correct(gm, order=2).acceleration, atol=1e-9
    )
    np.testing.assert_allclose(
        corrected.acceleration, gm.acceleration, atol=2e-3 * np.abs(acc).max()
    )


def test_remove_mean():
    gm = GroundMotion([1.0, 2.0, 3.0], 0.1)
    out = remove_mean(gm)
    np.testing.assert_allclose(out.acceleration, [-1.0, 0.0, 1.0])
    assert gm.acceleration[0] == 1.0  # the input is unchanged


def test_bandpass_keeps_the_band_and_removes_the_rest():
    dt = 0.005
    t = np.arange(0, 40, dt)
    inside = np.sin(2 * np.pi * 2.0 * t)
    gm = GroundMotion(inside + np.sin(2 * np.pi * 0.02 * t) + np.sin(2 * np.pi * 60.0 * t), dt)
    out = bandpass(gm, low=0.2, high=25.0, order=4)
    middle = slice(len(t) // 4, 3 * len(t) // 4)
    np.testing.assert_allclose(out.acceleration[middle], inside[middle], atol=0.02)
    with pytest.raises(ValueError, match="high"):
        bandpass(gm, low=0.1, high=150.0)
    with pytest.raises(ValueError, match="low"):
        bandpass(gm, low=30.0, high=25.0)


def test_taper_pad_tail_resample():
    gm = GroundMotion(np.ones(101), 0.01)
    tapered = taper(gm, fraction=0.1)
    assert tapered.acceleration[0] == 0.0 and tapered.acceleration[50] == 1.0
    assert tapered.acceleration[-1] == 0.0
    assert tapered.acceleration[-2] == pytest.approx(0.5 * (1 - math.cos(math.pi / 10)))
    padded = zero_pad(gm, before=0.05, after=0.1)
    assert padded.npts == 101 + 5 + 10 and padded.acceleration[:5].sum() == 0.0
    tail = free_vibration_tail(gm, duration=1.0)
    assert tail.duration == pytest.approx(2.0) and tail.acceleration[-1] == 0.0
    fine = resample(gm.replace(acceleration=np.linspace(0, 1, 101)), dt=0.0025)
    assert fine.dt == 0.0025 and fine.npts == 401
    np.testing.assert_allclose(fine.acceleration, np.linspace(0, 1, 401), atol=1e-12)
    coarse = resample(sine(freq=1.0, duration=10.0, dt=0.001), dt=0.02)
    np.testing.assert_allclose(
        coarse.acceleration[50:-50], 2.0 * np.sin(2 * np.pi * coarse.time[50:-50]), atol=1e-3
    )


def test_trim_significant_keeps_the_strong_part():
    dt = 0.01
    acc = np.zeros(3001)
    acc[1000:2001] = np.sin(2 * np.pi * 5 * dt * np.arange(1001))  # strong phase 10-20 s
    gm = GroundMotion(acc, dt)
    out = trim_significant(gm, start=0.05, end=0.95)
    assert out.duration == pytest.approx(9.0, abs=0.05)
    assert out.metadata["start_time"] == pytest.approx(10.5, abs=0.05)
    assert arias_intensity(out) == pytest.approx(0.9 * arias_intensity(gm), rel=0.01)


def test_scaling_to_pga_and_to_spectral_acceleration():
    gm = harmonic(amplitude=1.0, period=0.3, duration=5.0, dt=0.01)
    assert scale_to_pga(gm, pga=0.4 * G).pga == pytest.approx(0.4 * G)
    scaled = scale_to_sa(gm, sa=5.0, period=1.0, damping=0.05)
    psa = response_spectrum(scaled, [1.0], 0.05).PSa.item()  # the compiled engine
    assert psa == pytest.approx(5.0, rel=1e-6)
    assert "PSa(1 s, 0.05)" in scaled.metadata["processing"][-1]


def test_processing_chain_is_recorded_in_order():
    gm = sine(duration=4.0, dt=0.01)
    out = process(process(process(gm, "remove_mean"), "taper", fraction=0.05), "scale_pga", pga=1.0)
    chain = out.metadata["processing"]
    assert len(chain) == 3 and chain[0].startswith("removed mean") and "taper" in chain[1]
    assert "processing" not in gm.metadata
    with pytest.raises(ValueError, match="remove_mean"):
        process(gm, "detrend")
    assert set(PROCESSING_STEPS) >= {"baseline", "bandpass", "trim", "scale_sa"}


@pytest.mark.parametrize(
    ("step", "params", "field"),
    [
        ("baseline", {"order": 1}, "order"),
        ("taper", {"fraction": 0.7}, "fraction"),
        ("taper", {"side": "middle"}, "side"),
        ("zero_pad", {"before": -1.0}, "before"),
        ("resample", {"dt": 0.0}, "dt"),
        ("trim", {"start": 0.9, "end": 0.1}, "start"),
        ("scale_pga", {"pga": -1.0}, "pga"),
        ("scale_sa", {"sa": 1.0, "period": 1.0, "damping": 1.5}, "damping"),
    ],
)
def test_bad_processing_parameters_name_the_field(step, params, field):
    with pytest.raises(ValueError, match=field):
        process(sine(duration=2.0, dt=0.01), step, **params)


@settings(max_examples=30, deadline=None)
@given(
    st.lists(st.floats(-10, 10), min_size=3, max_size=60),
    st.floats(0.1, 10.0),
)
def test_measures_scale_with_the_record(values, factor):
    # PGA, PGV, PGD and CAV scale linearly, Arias intensity quadratically; durations not at all
    gm = GroundMotion(values, 0.01)
    scaled = gm.scaled(factor)
    a, b = intensity_measures(gm), intensity_measures(scaled)
    for key in ("pga", "pgv", "pgd", "cav"):
        assert b[key] == pytest.approx(factor * a[key], rel=1e-9, abs=1e-12)
    assert b["arias_intensity"] == pytest.approx(
        factor**2 * a["arias_intensity"], rel=1e-9, abs=1e-15
    )
