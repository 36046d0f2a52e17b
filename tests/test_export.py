"""Export of result Datasets to CSV and Excel: every table read back equals the Dataset values,
headers carry the CF units, Excel without openpyxl and non-NetCDF ``-o`` paths are refused."""

from __future__ import annotations

import builtins
import importlib.util
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from typer.testing import CliRunner

from pounding.case import case_from_dict
from pounding.cli import app
from pounding.export import export, tables
from pounding.results import open_result, save
from pounding.separation import separation_analysis
from pounding.simulate import simulate
from pounding.studies import run_study, study_from_dict

ROOT = Path(__file__).resolve().parents[1]
PULSE = {"type": "sine_pulse", "amplitude": 0.5, "units": "g", "period": 0.5, "duration": 2.5}
needs_openpyxl = pytest.mark.skipif(
    importlib.util.find_spec("openpyxl") is None, reason="openpyxl (pounding[excel]) not installed"
)


def _case(**study) -> dict:
    """A 2-story and a 3-story building (floor 3 of L is NaN padding), Hertz contacts."""
    data = {
        "title": "export",
        "building": [
            {"name": "L", "n_floors": 2, "period": 0.3, "mass": 1e5},
            {"name": "R", "n_floors": 3, "period": 0.6, "mass": 1e5},
        ],
        "contact": [{"left": "L", "right": "R", "gap": 0.01, "law": "hertz", "k": 2e9, "e": 0.6}],
        "ground_motion": dict(PULSE),
        "analysis": {"output_dt": 0.01},
    }
    if study:
        data["study"] = study
    return data


@pytest.fixture(scope="module")
def analysis(tmp_path_factory) -> xr.Dataset:
    path = tmp_path_factory.mktemp("analysis") / "a.nc"
    save(simulate(case_from_dict(_case()), baseline=True), path)
    return open_result(path)


@pytest.fixture(scope="module")
def study(tmp_path_factory) -> xr.Dataset:
    tmp = tmp_path_factory.mktemp("study")
    s = study_from_dict(_case(law=["none", "hertz"], gap=[0.005, 0.02]), base_dir=ROOT)
    save(run_study(s, tmp / "runs", jobs=1), tmp / "st.nc")
    return open_result(tmp / "st.nc")


@pytest.fixture(scope="module")
def separation(tmp_path_factory) -> xr.Dataset:
    data = _case()
    data["ground_motion"] = {"record": "synthetic:kanai-tajimi?seed=3&pga=0.3&duration=4"}
    path = tmp_path_factory.mktemp("separation") / "s.nc"
    save(separation_analysis(case_from_dict(data)), path)
    return open_result(path)


def _read(tmp_path: Path, ds: xr.Dataset, **kw) -> dict[str, pd.DataFrame]:
    written = export(ds, tmp_path / "out", **kw)
    return {p.stem: pd.read_csv(p) for p in written}


def _close(csv_values, ds_values) -> None:
    np.testing.assert_allclose(np.asarray(csv_values, float), ds_values, rtol=1e-15, atol=0)


def _at(ds: xr.Dataset, name: str, df: pd.DataFrame, dims: list[str]) -> np.ndarray:
    """The Dataset values of ``name`` at each row's coordinates."""
    index = {
        d: xr.DataArray(df[next(c for c in df if c.split(" [")[0] == d)].to_numpy()) for d in dims
    }
    return ds[name].sel(index).values


def test_analysis_peaks_contacts_impacts_energy_round_trip(analysis, tmp_path):
    ds = analysis
    t = _read(tmp_path, ds, histories=None)
    assert sorted(t) == ["contacts", "energy", "impacts", "peaks"]
    peaks = t["peaks"]
    assert len(peaks) == 5  # 2 + 3 real floors, the padded one dropped
    for v, dims in [
        ("peak_displacement", ["building", "floor"]),
        ("peak_absolute_acceleration", ["building", "floor"]),
        ("no_contact_peak_absolute_acceleration", ["building", "floor"]),
        ("floor_acceleration_amplification", ["building", "floor"]),
    ]:
        _close(peaks[f"{v} [{ds[v].attrs['units']}]"], _at(ds, v, peaks, dims))
    for v in ("peak_story_shear", "impact_story_shear", "story_drift_amplification"):
        at_story = ds[v].sel(
            building=xr.DataArray(peaks["building"]), story=xr.DataArray(peaks["floor"])
        )
        _close(peaks[f"{v} [{ds[v].attrs['units']}]"], at_story.values)
    # story i is the story below floor i
    story = ds["peak_drift_ratio"].sel(
        building=xr.DataArray(peaks["building"]), story=xr.DataArray(peaks["floor"])
    )
    _close(peaks["peak_drift_ratio [1]"], story.values)
    _close(t["contacts"]["peak_contact_force [N]"], ds["peak_contact_force"].values)
    _close(t["contacts"]["contact_gap [m]"], ds["contact_gap"].values)
    impacts = t["impacts"]
    assert ds.sizes["impact"] > 0 and len(impacts) == ds.sizes["impact"]
    for v in ("impact_start", "impact_v0", "impact_peak_force", "impact_impulse"):
        _close(impacts[f"{v} [{ds[v].attrs['units']}]"], ds[v].values)
    for term in ds["term"].values:
        _close(t["energy"][f"{term} [J]"], ds["energy"].sel(term=term).values)
    _close(t["energy"]["time [s]"], ds["time"].values)


def test_analysis_histories_long_round_trip(analysis, tmp_path):
    ds = analysis
    h = _read(tmp_path, ds, names=["histories"], histories="long")["histories"]
    assert list(h.columns) == ["variable", "location", "units", "time [s]", "value"]
    d = h[(h["variable"] == "displacement") & (h["location"] == "R:3")]
    _close(d["value"], ds["displacement"].sel(building="R", floor=3).values)
    _close(d["time [s]"], ds["time"].values)
    assert set(d["units"]) == {"m"}
    f = h[(h["variable"] == "contact_force") & (h["location"] == "0")]
    _close(f["value"], ds["contact_force"].sel(contact=0).values)
    g = h[h["variable"] == "ground_acceleration"]
    _close(g["value"], ds["ground_acceleration"].values)
    # the padded floor 3 of L is no history
    assert not ((h["variable"] == "displacement") & (h["location"] == "L:3")).any()


def test_analysis_histories_wide_round_trip(analysis, tmp_path):
    ds = analysis
    h = _read(tmp_path, ds, names=["histories"], histories="wide")["histories"]
    assert len(h) == ds.sizes["time"]
    _close(h["displacement R:3 [m]"], ds["displacement"].sel(building="R", floor=3).values)
    _close(h["drift_ratio L:2 [1]"], ds["drift_ratio"].sel(building="L", story=2).values)
    _close(
        h["absolute_acceleration L:1 [m/s^2]"],
        ds["absolute_acceleration"].isel(building=0, floor=0),
    )
    _close(h["energy input [J]"], ds["energy"].sel(term="input").values)
    assert "displacement L:3 [m]" not in h


def test_every_numeric_column_header_carries_its_unit(analysis, study, separation):
    for ds in (analysis, study, separation):
        for name, df in tables(ds, histories="wide").items():
            for col in df.columns:
                base = col.split(" [")[0]
                if base in ds.variables and ds[base].attrs.get("units"):
                    assert col == f"{base} [{ds[base].attrs['units']}]", (name, col)
                elif pd.api.types.is_float_dtype(df[col]) and name != "comparison":
                    assert col.endswith("]"), (name, col)


def test_study_summary_one_row_per_combination_round_trip(study, tmp_path):
    ds = study
    t = _read(tmp_path, ds)
    s = t["summary"]
    assert len(s) == ds.sizes["law"] * ds.sizes["gap"] * ds.sizes["record"] == 4
    assert {"law", "gap [m]", "record", "input_energy [J]", "run_status"} <= set(s.columns)
    for v in ("input_energy", "contact_dissipated_energy", "energy_balance_error"):
        _close(s[f"{v} [{ds[v].attrs['units']}]"], _at(ds, v, s, ["law", "gap", "record"]))
    p = t["peaks"]
    _close(
        p["peak_displacement [m]"],
        _at(ds, "peak_displacement", p, ["law", "gap", "record", "building", "floor"]),
    )
    c = t["contacts"]
    assert set(c["law"]) == {"hertz"}  # the no-contact runs have no contact results
    _close(
        c["peak_contact_force [N]"],
        _at(ds, "peak_contact_force", c, ["law", "gap", "record", "contact"]),
    )
    b = t["buildings"]
    _close(
        b["displacement_amplification [1]"],
        _at(ds, "displacement_amplification", b, ["law", "gap", "record", "building"]),
    )


def test_separation_comparison_and_probability_round_trip(separation, tmp_path):
    ds = separation
    t = _read(tmp_path, ds)
    comp = t["comparison"]
    rows = comp[comp["estimate"] != "lognormal_target"]
    assert len(rows) > 0 and len(t["probability"]) > 0  # the comparisons below are not vacuous
    stat = ds["required_gap_statistic"].sel(
        interface=xr.DataArray(rows["interface"]), estimate=xr.DataArray(rows["estimate"])
    )
    for s in ("median", "p84", "max"):
        _close(rows[f"{s} [m]"], stat.sel(statistic=s).values)
    prob = t["probability"]
    _close(prob["gap [m]"], ds["gap"].values)
    _close(prob["pounding_probability [1]"], ds["pounding_probability"].isel(interface=0).values)


@needs_openpyxl
def test_xlsx_one_sheet_per_table_round_trip(analysis, study, tmp_path):
    for ds, name in ((analysis, "a"), (study, "st")):
        path = tmp_path / f"{name}.xlsx"
        export(ds, path, histories="wide")
        sheets = pd.read_excel(path, sheet_name=None)
        expected = tables(ds, histories="wide")
        assert list(sheets) == list(expected)
        for key, df in expected.items():
            got = sheets[key]
            assert list(got.columns) == list(df.columns)
            for col in df.columns:
                if pd.api.types.is_float_dtype(df[col]):
                    _close(got[col], df[col].to_numpy())


def test_excel_without_openpyxl_says_how_to_install(analysis, tmp_path, monkeypatch):
    real = builtins.__import__

    def no_openpyxl(name, *args, **kwargs):
        if name == "openpyxl" or name.startswith("openpyxl."):
            raise ImportError("No module named 'openpyxl'")
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_openpyxl)
    with pytest.raises(ImportError, match=r"pip install 'pounding\[excel\]'"):
        export(analysis, tmp_path / "x.xlsx")
    result_path = tmp_path / "a.nc"
    save(analysis, result_path)
    res = CliRunner().invoke(app, ["export", str(result_path), "-o", str(tmp_path / "y.xlsx")])
    assert res.exit_code == 2
    assert res.output.strip() == "error: Excel export needs openpyxl: pip install 'pounding[excel]'"
    assert not (tmp_path / "y.xlsx").exists()


@pytest.mark.parametrize("verb", ["run", "study", "separation"])
@pytest.mark.parametrize("out", ["out.csv", "out.xlsx", "out"])
def test_o_other_than_nc_is_refused_before_anything_runs(verb, out, tmp_path):
    # the case file does not exist: the refusal comes before it is read
    res = CliRunner().invoke(app, [verb, str(tmp_path / "missing.toml"), "-o", out])
    assert res.exit_code == 2
    assert res.output.strip() == (
        f"error: -o {out}: results are written as NetCDF (.nc); use `pounding export` for csv/xlsx"
    )


def test_cli_export_directory_and_unknown_table(analysis, tmp_path):
    path = tmp_path / "a.nc"
    save(analysis, path)
    runner = CliRunner()
    res = runner.invoke(
        app, ["export", str(path), "-o", str(tmp_path / "csv"), "--histories", "wide"]
    )
    assert res.exit_code == 0, res.output
    assert sorted(p.name for p in (tmp_path / "csv").iterdir()) == [
        "contacts.csv",
        "energy.csv",
        "histories.csv",
        "impacts.csv",
        "peaks.csv",
    ]
    res = runner.invoke(app, ["export", str(path), "-o", str(tmp_path / "x"), "--table", "peak"])
    assert res.exit_code == 2
    assert res.output.strip() == (
        "error: table: 'peak' is not a table of the analysis result; "
        "allowed: peaks, contacts, impacts, energy, histories"
    )
    one = tmp_path / "peaks.csv"
    res = runner.invoke(app, ["export", str(path), "-o", str(one), "--table", "peaks"])
    assert res.exit_code == 0, res.output
    assert list(pd.read_csv(one)["floor"]) == [1, 2, 1, 2, 3]
    res = runner.invoke(app, ["export", str(path), "-o", str(tmp_path / "all.csv")])
    assert res.exit_code == 2 and "one --table" in res.output


def test_result_kind_tells_the_three_results_apart(analysis, study, separation):
    from pounding.results import result_kind

    assert [result_kind(d) for d in (analysis, study, separation)] == [
        "analysis",
        "study",
        "separation",
    ]
    with pytest.raises(ValueError, match="none of an analysis"):
        tables(xr.Dataset({"x": ("t", [1.0])}))
