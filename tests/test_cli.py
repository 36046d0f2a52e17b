"""The analysis CLI verbs: output, exit codes, one-line errors."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from pounding.cli import app
from pounding.results import open_result

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
runner = CliRunner()


def test_run_prints_summary_and_writes_dataset(tmp_path):
    out = tmp_path / "r.nc"
    res = runner.invoke(app, ["run", str(EXAMPLES / "two_sdof.toml"), "-o", str(out)])
    assert res.exit_code == 0, res.output
    for text in ("T1 [s]", "hunt_crossley", "impacts", "energy balance error", "written"):
        assert text in res.output
    ds = open_result(out)
    assert int(ds["impact_count"].sum()) > 0


def test_run_reports_peaks_with_and_without_contact_by_default(tmp_path):
    # The decision table leads: drift, acceleration, displacement and base shear with contact, in the
    # no-contact run of the same analysis, and their ratio; --no-baseline skips that second run.
    out = tmp_path / "r.nc"
    res = runner.invoke(app, ["run", str(EXAMPLES / "two_sdof.toml"), "-o", str(out)])
    assert res.exit_code == 0, res.output
    lines = res.output.splitlines()
    assert "pounding effect" in lines[2]
    ds = open_result(out)
    b = ds["building"].values[0]
    row = next(line for line in lines if line.split()[:4] == [b, "peak", "drift", "ratio"])
    with_c, without, ratio = (float(x) for x in row.split()[4:7])
    assert with_c == pytest.approx(float(ds["peak_drift_ratio"].sel(building=b).max()), rel=1e-3)
    assert without == pytest.approx(
        float(ds["no_contact_peak_drift_ratio"].sel(building=b).max()), rel=1e-3
    )
    assert ratio == pytest.approx(float(ds["drift_amplification"].sel(building=b)), rel=1e-2)
    res = runner.invoke(
        app, ["run", str(EXAMPLES / "two_sdof.toml"), "--no-baseline", "-o", str(out)]
    )
    assert res.exit_code == 0, res.output
    assert "pounding effect" not in res.output
    assert "drift_amplification" not in open_result(out)


def test_run_bad_case_is_one_line_exit_2(tmp_path):
    case = tmp_path / "bad.toml"
    case.write_text(
        (EXAMPLES / "two_sdof.toml")
        .read_text()
        .replace('law = "hunt_crossley"', 'law = "huntcrossley"')
    )
    res = runner.invoke(app, ["run", str(case)])
    assert res.exit_code == 2
    lines = [ln for ln in res.output.splitlines() if ln.strip()]
    assert len(lines) == 1 and "unknown contact law 'huntcrossley'" in lines[0]
    assert "Traceback" not in res.output


def test_run_missing_file_exit_2(tmp_path):
    res = runner.invoke(app, ["run", str(tmp_path / "none.toml")])
    assert res.exit_code == 2
    assert "no case file" in res.output


def test_laws_lists_every_law_and_alias():
    res = runner.invoke(app, ["laws"])
    assert res.exit_code == 0
    for name in ("linear", "kelvin_approach", "hertz_kelvin", "hertzdamp", "ye", "impact_material"):
        assert name in res.output
    links = res.output.split("coupling link types")[1]
    for name in ("kelvin:", "viscous:", "maxwell:"):
        assert name in links


def test_laws_restitution_json_keys_match_hertz_closed_form():
    # undamped Hertz: δ_max = (5 m v0²/(4k))^(2/5), t_c = 2.943275 δ_max/v0 (Goldsmith 1960)
    m, k, v0 = 1.5e5, 2.75e9, 0.5
    res = runner.invoke(
        app,
        [
            "laws",
            "restitution",
            "--law",
            "hertz",
            "--k",
            str(k),
            "--mass",
            str(m),
            "--v0",
            str(v0),
            "--json",
        ],
    )
    assert res.exit_code == 0, res.output
    out = json.loads(res.output)
    assert set(out) == {
        "e_effective",
        "max_penetration",
        "peak_force",
        "contact_duration",
        "force_duration",
        "overlap_duration",
    }
    d_max = (5 * m * v0**2 / (4 * k)) ** 0.4
    assert out["max_penetration"] == pytest.approx(d_max, rel=1e-4)
    assert out["contact_duration"] == pytest.approx(2.943275 * d_max / v0, rel=1e-3)
    assert out["e_effective"] == pytest.approx(1.0, abs=1e-6)


def test_laws_restitution_kelvin_reports_force_and_overlap_durations():
    # Issue 12 §6: at e = 0.65 the clamped Kelvin force acts 0.0916 s, the overlap lasts 0.1002 s
    # (closed forms in test_calibrate.test_kelvin_force_and_overlap_durations_against_closed_form).
    args = ["laws", "restitution", "--law", "kelvin", "--k", "1e8", "--mass", "1e5", "--v0", "1"]
    res = runner.invoke(app, [*args, "--e", "0.65"])
    assert res.exit_code == 0, res.output
    assert "contact duration       0.09158 s   (force acts, F > 0)" in res.output
    assert "overlap duration       0.1002 s   (penetration > 0)" in res.output
    out = json.loads(runner.invoke(app, [*args, "--e", "0.65", "--json"]).output)
    assert out["contact_duration"] == out["force_duration"]
    assert out["overlap_duration"] / out["force_duration"] == pytest.approx(1.094, abs=1e-3)


def test_laws_restitution_missing_e_is_exit_2():
    res = runner.invoke(
        app, ["laws", "restitution", "--law", "kelvin", "--k", "1e9", "--mass", "1e5", "--v0", "1"]
    )
    assert res.exit_code == 2
    assert "needs e" in res.output


def test_run_isolated_example_prints_base_displacement(tmp_path):
    res = runner.invoke(
        app, ["run", str(EXAMPLES / "base_isolated_moat.toml"), "-o", str(tmp_path / "i.nc")]
    )
    assert res.exit_code == 0, res.output
    assert "peak base (bearing) displacement" in res.output
    assert "energy dissipated by bearing friction" in res.output
    # the friction pendulum's isolated period 2π√(R/g), R = 2.2 m, and the record as analysed:
    # the case scales a 0.25 g record by 1.5 (the summary used to print 0.25 g)
    t_iso = 2 * math.pi * math.sqrt(2.2 / 9.80665)
    assert f"isolated period 2π√(R/g) = {t_iso:.3g} s" in res.output
    assert "(PGA 0.375 g as analysed" in res.output


def test_separation_says_whether_the_cases_gap_suffices(tmp_path):
    # One verdict line per interface: the case's gap against the median exact required gap of the
    # records, with the count of records that pound; estimates that do not apply print n/a.
    from test_separation import CASE_TOML

    case = tmp_path / "case.toml"
    case.write_text(
        CASE_TOML
        + '\n[separation]\nrecords = ["synthetic:kanai-tajimi?seed=1&pga=0.3&duration=5", '
        '"synthetic:kanai-tajimi?seed=2&pga=0.3&duration=5", '
        '"synthetic:kanai-tajimi?seed=3&pga=0.3&duration=5"]\n'
    )
    out = tmp_path / "sep.nc"
    res = runner.invoke(app, ["separation", str(case), "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert "nan" not in res.output
    ds = open_result(out)
    exact = ds["required_gap"].sel(estimate="time_history", interface="A|B").values
    required = float(np.median(exact))
    hits = int((exact > 0.05).sum())
    line = next(ln for ln in res.output.splitlines() if ln.startswith("  verdict A|B"))
    relation = "<" if 0.05 < required else ">="
    assert f"gap 0.050 m {relation} required {required:.3f} m (exact, median of 3 records)" in line
    assert f"{hits} of 3 records" in line
    # the Dataset carries the case's gap and the plots mark it
    assert float(ds["case_gap"].sel(interface="A|B")) == 0.05
    assert ds["case_gap"].attrs["units"] == "m"
    from pounding import plots

    for fig in (plots.required_gaps(ds), plots.pounding_probability(ds)):
        lines = [
            ln for ax in fig.axes for ln in ax.get_lines() if ln.get_label() == "gap in the case"
        ]
        assert lines and all(ln.get_xdata()[0] == 0.05 for ln in lines)


def test_separation_records_keep_the_cases_scale(tmp_path):
    # [ground_motion] scale = 2 applies to the --records suite too; the buildings are linear without
    # contact, so the exact required gaps double (superposition)
    from test_separation import CASE_TOML

    ref = "synthetic:kanai-tajimi?seed=1&pga=0.3&duration=5"
    gaps = []
    for scaled in (False, True):
        text = CASE_TOML
        if scaled:
            text = text.replace("[ground_motion]", "[ground_motion]\nscale = 2.0", 1)
        case = tmp_path / f"case{int(scaled)}.toml"
        case.write_text(text)
        out = tmp_path / f"sep{int(scaled)}.nc"
        res = runner.invoke(app, ["separation", str(case), "--records", ref, "-o", str(out)])
        assert res.exit_code == 0, res.output
        gaps.append(open_result(out)["required_gap"].sel(estimate="time_history").values)
    np.testing.assert_allclose(gaps[1], 2.0 * gaps[0], rtol=1e-9)
