"""Figures label themselves from CF attributes and draw the numbers of the Dataset."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from matplotlib.figure import Figure
from test_studies import ROOT, _small_study

from pounding import plots
from pounding.case import load_case
from pounding.simulate import simulate


@pytest.fixture(scope="module")
def analysis():
    return simulate(load_case(ROOT / "examples" / "two_sdof.toml"))


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    from pounding.studies import run_study

    return run_study(_small_study(), tmp_path_factory.mktemp("plots") / "runs", jobs=1)


def test_label_from_cf_attributes():
    da = xr.DataArray([1.0], attrs={"long_name": "peak drift ratio", "units": "1"})
    assert plots.label(da) == "peak drift ratio [-]"
    da.attrs["units"] = "m/s^2"
    assert plots.label(da) == "peak drift ratio [m/s^2]"
    assert plots.label(da, "acc", units="g") == "acc [g]"
    assert plots.label(xr.DataArray([1.0], name="x")) == "x"


def test_envelopes_are_labelled_and_draw_the_peaks(analysis):
    fig = plots.envelopes(analysis)
    ax_disp, ax_drift = fig.axes[:2]
    assert ax_disp.get_xlabel() == plots.label(analysis["peak_displacement"])
    assert ax_drift.get_xlabel() == plots.label(analysis["peak_drift_ratio"])
    first = analysis["building"].values[0]
    n = int(np.isfinite(analysis["floor_elevation"].sel(building=first)).sum())
    x = ax_disp.lines[0].get_xdata()
    np.testing.assert_array_equal(x[1:], analysis["peak_displacement"].sel(building=first)[:n])


def test_analysis_figures_build(analysis):
    for make in (
        plots.mode_shapes,
        plots.displacement_histories,
        plots.contact_forces,
        plots.energy,
    ):
        fig = make(analysis)
        assert isinstance(fig, Figure) and fig.axes
    fig = plots.force_penetration([("law", analysis)])
    line = fig.axes[0].lines[0]
    # the loop starts and ends open (zero force); drawn from the integration steps, it reaches
    # the impact's exact peak force, above the output grid's sampled one
    y = np.asarray(line.get_ydata())
    assert y[0] == 0 and y[-1] == pytest.approx(0.0, abs=1e-9)
    assert y.max() == pytest.approx(float(analysis["impact_peak_force"].max()) / 1e6, rel=1e-2)
    assert y.max() >= float(analysis["contact_force"].max()) / 1e6
    assert fig.axes[0].get_ylabel() == "contact force [MN]"  # long_name from the attrs


def test_amplification_plot_draws_the_median_over_records(study):
    fig = plots.amplification(study, "displacement_amplification", x="gap")
    ax = fig.axes[0]  # first building
    lines = {ln.get_label(): ln for ln in ax.lines if ln.get_label() in ("hertz", "flores")}
    expected = (
        study["displacement_amplification"]
        .sel(law="flores", building=study["building"].values[0])
        .median("record")
    )
    np.testing.assert_allclose(lines["flores"].get_ydata(), expected.values)
    assert ax.get_xlabel() == plots.label(study["gap"])


def test_heatmap_cells_are_medians(study):
    fig = plots.heatmap(study, "peak_contact_force", "gap", "law", scale=1e-6, fmt="{:.6g}")
    texts = [float(t.get_text()) for t in fig.axes[0].texts]
    expected = (
        study["peak_contact_force"].max("contact").sel(law=["hertz", "flores"]).median("record")
        * 1e-6
    )
    np.testing.assert_allclose(texts, expected.values.ravel(), rtol=1e-5)


def test_bearing_hysteresis_is_labelled_from_cf_attributes():
    from pathlib import Path

    from pounding import plots
    from pounding.case import load_case
    from pounding.simulate import simulate

    case = load_case(Path(__file__).resolve().parents[1] / "examples" / "base_isolated_moat.toml")
    ds = simulate(case, duration=3.0)
    assert plots.isolated_buildings(ds) == ["A"]
    fig = plots.bearing_hysteresis(ds)
    ax = fig.axes[0]
    assert "[m]" in ax.get_xlabel() and "[N]" in ax.get_ylabel()
    assert 0.0 < plots.friction_share(ds) < 1.0


def test_shear_envelopes_and_floor_spectra_draw_the_datasets_values():
    import tomllib

    from pounding.case import case_from_dict

    data = tomllib.loads((ROOT / "examples" / "three_vs_eight_story.toml").read_text())
    data["output"] = {"floor_spectra": "roof"}
    ds = simulate(case_from_dict(data), baseline=True)
    fig = plots.shear_envelopes(ds)
    ax = fig.axes[0]
    assert ax.get_xlabel() == "peak story shear [MN]"
    with_b, without_b = ax.lines[2], ax.lines[3]  # building B, with and without contact
    assert without_b.get_linestyle() == "--" and without_b.get_label() == "B no contact"
    np.testing.assert_allclose(
        with_b.get_xdata()[::2], ds["peak_story_shear"].sel(building="B") / 1e6
    )
    np.testing.assert_allclose(
        without_b.get_xdata()[::2], ds["no_contact_peak_story_shear"].sel(building="B") / 1e6
    )
    fig = plots.floor_spectra(ds)
    (roof_a, roof_b) = fig.axes[0].lines
    assert roof_a.get_label() == "A floor 3" and roof_b.get_label() == "B floor 8"
    np.testing.assert_array_equal(
        roof_b.get_ydata(), ds["floor_spectrum"].sel(building="B", floor=8)
    )


def test_amplification_without_the_axis_draws_a_bar_per_law_and_no_empty_legend(study):
    one_gap = study.isel(gap=0)
    fig = plots.amplification(one_gap, "displacement_amplification", x="gap")
    name = study["building"].values[0]
    heights = {p.get_x(): p.get_height() for p in fig.axes[0].patches}
    expected = one_gap["displacement_amplification"].sel(building=name).median("record")
    expected = expected.drop_sel(law="none", errors="ignore")  # the baseline: no bar
    np.testing.assert_allclose(sorted(heights.values()), sorted(expected.values))
    assert all(ax.get_legend() is None for ax in fig.axes)


def test_amplification_heatmap_diverges_about_one_with_symmetric_limits(study):
    # ratios to the no-contact run: a diverging map centred on 1, limits 1 - d and 1 + d
    fig = plots.heatmap(study, "drift_amplification", "gap", "law", building="L")
    image = fig.axes[0].images[0]
    norm = image.norm
    assert image.get_cmap().name == "RdBu_r"
    assert norm.vmin + norm.vmax == pytest.approx(2.0)  # 1 - d and 1 + d
    values = study["drift_amplification"].sel(building="L", law=["hertz", "flores"])
    med = values.median("record").values
    assert norm.vmin <= med.min() and med.max() <= norm.vmax
    # a force is no ratio: a sequential map
    fig = plots.heatmap(study, "peak_contact_force", "gap", "law")
    assert fig.axes[0].images[0].get_cmap().name == "viridis"


def test_displacement_histories_of_a_tall_row_draw_the_roof_and_the_most_struck_floors():
    # twelve contact floors would be twelve lines: the panel keeps the roof and the floors whose
    # contacts carried the largest forces, coloured by height
    from pounding.ground_motion import harmonic
    from pounding.structure import ShearBuilding
    from pounding.system import Contact, assemble

    a = ShearBuilding.uniform("A", 12, period=1.2, mass=3e5)
    b = ShearBuilding.uniform("B", 12, period=0.7, mass=3e5)
    system = assemble([a, b], [Contact("A", "B", gap=0.01, law="hertz", k=2.75e9)])
    ds = simulate(system, harmonic(amplitude=3.0, period=1.0, duration=3.0, dt=0.01))
    fig = plots.displacement_histories(ds)
    ax = fig.axes[0]
    drawn = [ln.get_label() for ln in ax.lines if not ln.get_label().startswith("_")]
    assert len(drawn) == plots.MAX_HISTORY_FLOORS and "floor 12" in drawn
    force = ds["peak_contact_force"].values
    floors = ds["contact_left_floor"].values
    ranked = [int(f) for f in floors[np.argsort(-force)] if f != 12]
    top = set(ranked[: plots.MAX_HISTORY_FLOORS - 1])
    assert {f"floor {f}" for f in top} <= set(drawn)


def test_contact_forces_are_in_mn_zoomed_on_the_impacts_with_exact_peaks(analysis):
    fig = plots.contact_forces(analysis)
    ax = fig.axes[0]
    history, peaks = ax.get_lines()
    np.testing.assert_allclose(history.get_ydata(), analysis["contact_force"].isel(contact=0) / 1e6)
    assert ax.get_ylabel() == "force [MN]"
    # the peaks tracked at every step, at least the sampled ones
    np.testing.assert_allclose(peaks.get_ydata(), analysis["impact_peak_force"].values / 1e6)
    assert np.all(peaks.get_xdata() >= analysis["impact_start"].values)
    lo, hi = ax.get_xlim()
    start, end = float(analysis["impact_start"].min()), float(analysis["impact_end"].max())
    assert lo == pytest.approx(max(0.0, start - plots.IMPACT_MARGIN))
    assert hi == pytest.approx(min(float(analysis["time"][-1]), end + plots.IMPACT_MARGIN))
