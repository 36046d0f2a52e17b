"""Synthetic records: filtered white noise PSDs, envelopes, spectrum-compatible generator."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pounding import records
from pounding.spectra import asce7_spectrum, eurocode8_spectrum, response_spectrum
from pounding.synthetic import (
    clough_penzien_psd,
    filtered_white_noise,
    jennings_envelope,
    kanai_tajimi,
    kanai_tajimi_psd,
    saragoni_hart_envelope,
    spectrum_compatible,
)
from pounding.units import G


def averaged_periodogram(model: str, seeds: int, n: int, dt: float, **params):
    """Two-sided PSD estimate dt/(2πN)|X|² averaged over stationary samples of many seeds."""
    total = 0.0
    for seed in range(seeds):
        gm = filtered_white_noise(
            model, duration=(n - 1) * dt, dt=dt, seed=seed, envelope_name=None, **params
        )
        total = total + np.abs(np.fft.rfft(gm.acceleration)) ** 2 * dt / (2 * np.pi * n)
    return 2 * np.pi * np.fft.rfftfreq(n, dt), total / seeds


@pytest.mark.parametrize("model", ["kanai-tajimi", "clough-penzien"])
def test_sample_psd_of_many_seeds_approaches_the_model_psd(model):
    # Kanai (1957), Tajimi (1960), Clough & Penzien (1975): averaged over 200 seeds and over
    # bands of 32 frequency bins, the periodogram is within 10 % of the model PSD
    # (standard error ≈ 1/sqrt(200·32) ≈ 1.3 %).
    params = {"s0": 0.02, "omega_g": 12.0, "zeta_g": 0.4, "omega_f": 1.2, "zeta_f": 0.6}
    n, dt = 1024, 0.01
    w, estimate = averaged_periodogram(model, 200, n, dt, **params)
    psd = {"kanai-tajimi": kanai_tajimi_psd, "clough-penzien": clough_penzien_psd}[model]
    if model == "kanai-tajimi":
        params = {k: params[k] for k in ("s0", "omega_g", "zeta_g")}
    target = psd(w, **params)
    band = slice(16, 16 + 32 * 8)  # 1 to 26 rad/s... up to ~ 25 Hz
    est = estimate[band].reshape(-1, 32).mean(axis=1)
    tgt = target[band].reshape(-1, 32).mean(axis=1)
    np.testing.assert_allclose(est, tgt, rtol=0.10)


def test_kanai_tajimi_variance_closed_form():
    # σ² = ∫ S dω = π S0 ω_g (1 + 4ζ_g²)/(2ζ_g) for the Kanai-Tajimi PSD over all ω;
    # the record holds the part below the Nyquist frequency, checked numerically
    s0, wg, zg, dt = 0.01, 15.6, 0.6, 0.005
    w = np.linspace(-math.pi / dt, math.pi / dt, 200001)
    resolved = np.trapezoid(kanai_tajimi_psd(w, s0=s0, omega_g=wg, zeta_g=zg), w)
    closed = math.pi * s0 * wg * (1 + 4 * zg**2) / (2 * zg)
    assert resolved < closed and resolved > 0.95 * closed
    var = np.mean(
        [
            np.var(kanai_tajimi(seed=k, duration=20.0, dt=dt, envelope_name=None).acceleration)
            for k in range(40)
        ]
    )
    assert var == pytest.approx(resolved, rel=0.03)


def test_clough_penzien_has_no_low_frequency_content():
    assert clough_penzien_psd([0.0], s0=1.0)[0] == 0.0
    assert kanai_tajimi_psd([0.0], s0=1.0)[0] == pytest.approx(1.0)


def test_same_seed_same_record_and_pga_scaling():
    a = kanai_tajimi(seed=7, duration=5.0, pga=0.3 * G)
    b = kanai_tajimi(seed=7, duration=5.0, pga=0.3 * G)
    c = kanai_tajimi(seed=8, duration=5.0, pga=0.3 * G)
    np.testing.assert_array_equal(a.acceleration, b.acceleration)
    assert not np.allclose(a.acceleration, c.acceleration)
    assert a.pga == pytest.approx(0.3 * G)
    assert a.metadata["parameters"]["seed"] == 7


def test_envelopes():
    # Boore (2003) Eq. 12: the Saragoni-Hart envelope peaks at 1 at ε t_η and equals η at t_η
    t_eta, eps, eta = 20.0, 0.2, 0.05
    t = np.linspace(0, 40, 40001)
    e = saragoni_hart_envelope(t, duration=t_eta, epsilon=eps, eta=eta)
    assert t[np.argmax(e)] == pytest.approx(eps * t_eta, abs=2e-3)
    assert e.max() == pytest.approx(1.0, rel=1e-6)
    assert saragoni_hart_envelope([t_eta], duration=t_eta)[0] == pytest.approx(eta)
    j = jennings_envelope([0.0, 1.0, 2.0, 5.0, 7.0], rise=2.0, strong_end=5.0, decay=0.5)
    np.testing.assert_allclose(j, [0.0, 0.25, 1.0, 1.0, math.exp(-1.0)])
    with pytest.raises(ValueError, match="strong_end"):
        jennings_envelope([0.0], rise=2.0, strong_end=1.0, decay=0.5)


@pytest.mark.parametrize(
    "target",
    [
        eurocode8_spectrum(np.geomspace(0.02, 4, 80), a_g=0.3 * G, ground_type="C"),
        asce7_spectrum(np.geomspace(0.02, 4, 80), s_ds=1.0, s_d1=0.6),
    ],
    ids=["ec8-C", "asce7-Dmax"],
)
def test_spectrum_compatible_meets_the_tolerance_it_reports(target):
    gm = spectrum_compatible(
        target.period.values, target.values, duration=20.0, dt=0.01, seed=1, tolerance=0.1
    )
    achieved = gm.metadata["achieved_tolerance"]
    assert gm.metadata["converged"] and achieved <= 0.1
    control = np.array(gm.metadata["control_periods"])
    psa = response_spectrum(gm, control, 0.05).PSa.values  # the compiled engine, not the filter
    expected = np.interp(control, target.period.values, target.values)
    assert np.max(np.abs(psa / expected - 1)) <= achieved + 2e-3


def test_spectrum_compatible_reports_honestly_when_it_cannot_converge():
    target = eurocode8_spectrum(np.geomspace(0.02, 4, 80), a_g=0.3 * G)
    gm = spectrum_compatible(
        target.period.values, target.values, duration=10.0, seed=1, tolerance=1e-4, max_iterations=3
    )
    assert not gm.metadata["converged"] and gm.metadata["achieved_tolerance"] > 1e-4


def test_spectrum_compatible_input_errors():
    with pytest.raises(ValueError, match="psa"):
        spectrum_compatible([0.1, 1.0], [1.0, -1.0])
    with pytest.raises(ValueError, match="increasing"):
        spectrum_compatible([1.0, 0.1], [1.0, 1.0])
    with pytest.raises(ValueError, match="tolerance"):
        spectrum_compatible([0.1, 1.0], [1.0, 1.0], tolerance=0.0)
    with pytest.raises(ValueError, match="allowed"):
        filtered_white_noise("boore")


def test_shipped_records_are_what_the_generator_makes(tmp_path):
    # ground_motions/README.md: the files are regenerated by ground_motions/make_records.py
    import importlib.util
    from pathlib import Path

    folder = Path(__file__).resolve().parents[1] / "ground_motions"
    spec = importlib.util.spec_from_file_location("make_records", folder / "make_records.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    made = module.make()
    assert sorted(made) == sorted(p.name for p in folder.glob("*.txt"))
    for name, gm in made.items():
        shipped = records.read_record(folder / name)
        assert shipped.dt == gm.dt
        np.testing.assert_allclose(shipped.acceleration, gm.acceleration, rtol=1e-8, atol=1e-9)
