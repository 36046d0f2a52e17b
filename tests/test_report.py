"""Reports: one self-contained HTML file that headless Chromium renders without console errors, a PDF
with the same sections, escaped text, for an analysis and for a study."""

from __future__ import annotations

import dataclasses
import re
import shutil
import subprocess
from pathlib import Path

import matplotlib.image as mpimg
import numpy as np
import pytest
from test_separation import CASE_TOML
from test_studies import ROOT, _base, _small_study
from typer.testing import CliRunner

from pounding.case import case_from_dict
from pounding.cli import app
from pounding.report import build_report, write_report
from pounding.results import save
from pounding.simulate import simulate
from pounding.studies import run_study

HOSTILE = "<script>alert(1)</script>"
ANALYSIS_SECTIONS = ("Executive summary", "Model", "Ground motion", "Results")
STUDY_SECTIONS = (
    "Executive summary",
    "Study",
    "Model",
    "Ground motions",
    "Comparison of contact laws",
    "Time histories",
)

SEPARATION_SECTIONS = (
    "Executive summary",
    "Buildings",
    "Method",
    "Interface A|B",
    "Comparison",
    "Exact gaps per record",
)

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
PDFTOTEXT = shutil.which("pdftotext")
PDFTOPPM = shutil.which("pdftoppm")
needs_chromium = pytest.mark.skipif(
    CHROMIUM is None, reason="headless Chromium (Debian package chromium) is not installed"
)
needs_poppler = pytest.mark.skipif(
    PDFTOTEXT is None or PDFTOPPM is None,
    reason="pdftotext/pdftoppm (Debian package poppler-utils) are not installed",
)


@pytest.fixture(scope="module")
def analysis_report(tmp_path_factory):
    data = _base()
    del data["study"]
    data["building"][0]["name"] = HOSTILE
    data["contact"][0]["left"] = HOSTILE
    ds = simulate(case_from_dict(data), baseline=True)
    out = tmp_path_factory.mktemp("analysis")
    save(ds, out / "result.nc")
    return ds, write_report(ds, out / "report")


@pytest.fixture(scope="module")
def study_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("study")
    study = _small_study()
    study = dataclasses.replace(study, keep_histories=True)
    ds = run_study(study, out / "results.runs", jobs=1)
    save(ds, out / "results.nc")
    return ds, write_report(ds, out / "report", result_path=out / "results.nc")


@pytest.fixture(scope="module")
def separation_report(tmp_path_factory):
    """A separation check over three synthetic records, written by the CLI and reported."""
    out = tmp_path_factory.mktemp("separation")
    case = out / "case.toml"
    case.write_text(
        CASE_TOML
        + """
[separation]
records = [
  "synthetic:kanai-tajimi?seed=1&pga=0.3&duration=5",
  "synthetic:kanai-tajimi?seed=2&pga=0.3&duration=5",
  "synthetic:kanai-tajimi?seed=3&pga=0.3&duration=5",
]
"""
    )
    runner = CliRunner()
    res = runner.invoke(app, ["separation", str(case), "-o", str(out / "sep.nc")])
    assert res.exit_code == 0, res.output
    res = runner.invoke(app, ["report", str(out / "sep.nc"), "-o", str(out / "report")])
    assert res.exit_code == 0, res.output
    from pounding.results import open_result

    return open_result(out / "sep.nc"), [
        out / "report" / "report.html",
        out / "report" / "report.pdf",
    ]


def _html(paths):
    return next(p for p in paths if p.suffix == ".html").read_text()


def _pdf(paths):
    return next(p for p in paths if p.suffix == ".pdf")


@pytest.mark.parametrize("which", ["analysis_report", "study_report"])
def test_html_is_self_contained(request, which):
    _, paths = request.getfixturevalue(which)
    html = _html(paths)
    assert html.startswith("<!DOCTYPE html>")
    assert "<script" not in html.lower()
    # nothing is fetched: no src attributes, no stylesheet or link to another resource
    assert not re.search(r"\ssrc\s*=", html)
    assert not re.search(r"<link\b", html)
    assert not re.search(r"url\(\s*['\"]?(https?:|//)", html)
    assert html.count("<svg") >= 4


def test_report_text_is_escaped(analysis_report):
    _, paths = analysis_report
    html = _html(paths)
    assert HOSTILE not in html
    assert "&lt;script&gt;alert(1)&lt;/script&gt;" in html


def test_analysis_report_sections_and_restitution_table(analysis_report):
    ds, _ = analysis_report
    rep = build_report(ds)
    assert [s.title for s in rep.sections] == list(ANALYSIS_SECTIONS)
    model = rep.sections[1]
    law_table = next(b for b in model.blocks if hasattr(b, "header") and "effective e" in b.header)
    row = law_table.rows[0]
    assert row[0].startswith("hertz") and row[3] == "1 (elastic)"
    # Hertz is elastic: its effective restitution is 1
    assert float(row[4]) == pytest.approx(1.0, abs=1e-3)


def test_analysis_report_leads_with_peaks_with_and_without_contact(analysis_report):
    # The first section: per building the peak drift ratio, floor acceleration, displacement and
    # base shear with contact, without (the run's no-contact baseline) and their ratio.
    ds, _ = analysis_report
    table = build_report(ds).sections[0].blocks[0]
    assert table.header == ["building", "quantity", "with contact", "without", "ratio"]
    name = str(ds["building"].values[1])
    row = next(r for r in table.rows if r[0] == name and r[1] == "peak drift ratio")
    assert float(row[2]) == pytest.approx(
        float(ds["peak_drift_ratio"].sel(building=name).max()), rel=1e-2
    )
    assert float(row[3]) == pytest.approx(
        float(ds["no_contact_peak_drift_ratio"].sel(building=name).max()), rel=1e-2
    )
    assert float(row[4]) == pytest.approx(
        float(ds["drift_amplification"].sel(building=name)), rel=1e-2
    )
    shear = next(r for r in table.rows if r[0] == name and r[1] == "peak base shear [kN]")
    assert float(shear[2]) == pytest.approx(
        float(ds["peak_base_shear"].sel(building=name)) / 1e3, abs=0.5
    )
    assert "largest impact force" in table.caption


def test_study_report_leads_with_the_record_statistics(study_report):
    # The first table of a study report: per law, gap and building the median / 84th / max over
    # the records of the drift and floor-acceleration amplification (ds.pounding.statistics()).
    ds, _ = study_report
    sec = build_report(ds).sections[0]
    assert sec.title == "Executive summary"
    table = next(b for b in sec.blocks if hasattr(b, "header"))
    st = ds.pounding.statistics()
    row = next(r for r in table.rows if r[0] == "hertz")
    gap, building = float(row[1]), row[2]
    at = {"law": "hertz", "gap": gap, "building": building}
    expected = [float(v) for v in st["drift_amplification"].sel(at).values]
    assert [float(v) for v in row[3].split(" / ")] == pytest.approx(expected, abs=0.006)
    assert not any(r[0] == "none" for r in table.rows)
    assert "Largest median drift amplification" in sec.blocks[0]


def test_an_elastic_laws_dissipation_is_shown_as_integration_error(study_report):
    # Hertz dissipates nothing: what the ledger shows for it is the integration's error, which
    # printed as a negative dissipation (-0.165 kJ)
    ds, _ = study_report
    comparison = next(
        s for s in build_report(ds).sections if s.title == "Comparison of contact laws"
    )
    table = comparison.blocks[-1]
    col = table.header.index("dissipated [kJ]")
    hertz = [r for r in table.rows if r[0] == "hertz"]
    assert hertz and all(r[col].startswith("≈0 (") for r in hertz)
    flores = [r for r in table.rows if r[0] == "flores"]
    assert flores and all(float(r[col]) > 0 for r in flores)


def test_separation_report_tables_are_the_datasets_figures(separation_report):
    from pounding.report import _g

    ds, paths = separation_report
    rep = build_report(ds)
    assert rep.kind == "separation"
    assert [s.title for s in rep.sections] == list(SEPARATION_SECTIONS)
    # the executive summary: the case's gap against the exact required gap, records that pound
    (row,) = rep.sections[0].blocks[0].rows
    exact = ds["required_gap"].sel(interface="A|B", estimate="time_history").values
    assert row[:2] == ["A|B", _g(0.05)]
    assert row[2].split(" / ")[0] == _g(float(np.median(exact)), 3)
    assert row[3] == f"{int((exact > 0.05).sum())} of 3"
    assert row[5] == (
        "pounding expected" if 0.05 < np.median(exact) else "no pounding in the median record"
    )
    buildings = rep.sections[1].blocks[0]
    t1 = ds["natural_period"].sel(building="B").isel(mode=0)
    assert buildings.rows[1][:2] == ["B", _g(float(t1))]
    interface = rep.sections[3]
    assert "A:1-B:1, A:2-B:2" in interface.blocks[0]
    table = interface.blocks[1]
    stat = ds["required_gap_statistic"].sel(interface="A|B")
    for row, e in zip(table.rows, ds["estimate"].values, strict=False):
        assert row[0] == str(ds["estimate_label"].sel(estimate=e).item())
        assert row[1] == _g(float(stat.sel(estimate=e, statistic="median")))
        assert row[3] == _g(float(stat.sel(estimate=e, statistic="max")))
    # the last row is the lognormal gap at the target probability
    assert table.rows[-1][1] == _g(float(ds["gap_for_target_probability"].sel(interface="A|B")))
    exact = ds["required_gap"].sel(interface="A|B", estimate="time_history").values
    per_record = rep.sections[-1].blocks[0]
    assert [r[1] for r in per_record.rows] == [_g(float(g)) for g in exact]
    assert len(set(exact)) == 3  # three records, three different exact gaps
    html = _html(paths)
    assert html.count("<svg") == 2 and "<script" not in html.lower()
    assert "pounding separation report" in html


def test_separation_figures_plot_the_dataset(separation_report):
    from pounding import plots

    ds, _ = separation_report
    fig = plots.pounding_probability(ds)
    ax = fig.axes[0]
    lines = {ln.get_label(): ln for ln in ax.get_lines()}
    np.testing.assert_array_equal(
        lines["fraction of records"].get_ydata(), ds["pounding_probability"].sel(interface="A|B")
    )
    np.testing.assert_array_equal(
        lines["lognormal"].get_ydata(), ds["pounding_probability_lognormal"].sel(interface="A|B")
    )
    assert ax.get_xlabel() == "gap [m]" and ax.get_ylabel() == "probability of pounding [-]"
    fig = plots.required_gaps(ds)
    bars = fig.axes[0].patches
    median = ds["required_gap_statistic"].sel(interface="A|B", statistic="median").values
    np.testing.assert_allclose([b.get_width() for b in bars], median)
    assert fig.axes[0].get_xlabel() == "required gap [m]"


def test_study_report_sections(study_report):
    ds, _ = study_report
    rep = build_report(ds)
    assert [s.title for s in rep.sections] == list(STUDY_SECTIONS)


def _chromium(html: Path, tmp_path: Path) -> tuple[np.ndarray, str]:
    shot = tmp_path / "shot.png"
    cmd = [
        CHROMIUM,
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--enable-logging=stderr",
        "--v=0",
        f"--user-data-dir={tmp_path / 'profile'}",
        f"--screenshot={shot}",
        "--window-size=1200,2000",
        html.resolve().as_uri(),
    ]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert shot.is_file(), res.stderr[-2000:]
    return mpimg.imread(shot), res.stderr


@needs_chromium
@pytest.mark.parametrize("which", ["analysis_report", "study_report", "separation_report"])
def test_html_opens_in_headless_chromium(request, which, tmp_path):
    _, paths = request.getfixturevalue(which)
    image, log = _chromium(next(p for p in paths if p.suffix == ".html"), tmp_path)
    console = [ln for ln in log.splitlines() if "CONSOLE" in ln or "Uncaught" in ln]
    assert not console, console
    # not blank: the rendered page has text and figures, so its pixels vary
    assert image.std() > 0.05
    assert (image[..., :3].mean(axis=-1) < 0.5).mean() > 0.005


@needs_poppler
@pytest.mark.parametrize(
    ("which", "sections"),
    [
        ("analysis_report", ANALYSIS_SECTIONS),
        ("study_report", STUDY_SECTIONS),
        ("separation_report", SEPARATION_SECTIONS),
    ],
)
def test_pdf_has_the_sections_and_non_blank_pages(request, which, sections, tmp_path):
    _, paths = request.getfixturevalue(which)
    pdf = _pdf(paths)
    text = subprocess.run([PDFTOTEXT, str(pdf), "-"], capture_output=True, text=True, check=True)
    for n, title in enumerate(sections, 1):
        assert f"{n}. {title}" in text.stdout, title
    subprocess.run([PDFTOPPM, "-r", "20", "-png", str(pdf), str(tmp_path / "page")], check=True)
    pages = sorted(tmp_path.glob("page*.png"))
    assert len(pages) >= 3
    for page in pages:
        assert mpimg.imread(page).std() > 0.01, page.name


@needs_poppler
def test_pdf_table_cells_wrap_instead_of_being_cut(separation_report):
    _, paths = separation_report
    text = subprocess.run(
        [PDFTOTEXT, "-layout", str(_pdf(paths)), "-"], capture_output=True, text=True, check=True
    ).stdout
    words = " ".join(text.split())
    # the DDC rows' basis cell (91 characters, cut at 48 before) ends with its reference, which no
    # paragraph of the report repeats
    assert "Penzien 1997)" in words


def test_cli_report_writes_both_formats_and_rejects_bad_input(analysis_report, tmp_path):
    runner = CliRunner()
    result = next(p for p in analysis_report[1]).parent.parent / "result.nc"
    res = runner.invoke(app, ["report", str(result), "-o", str(tmp_path / "r"), "--format", "html"])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "r" / "report.html").is_file()
    assert not (tmp_path / "r" / "report.pdf").exists()
    res = runner.invoke(app, ["report", str(result), "-o", str(tmp_path / "r"), "--format", "docx"])
    assert res.exit_code == 2 and "allowed" in res.output
    res = runner.invoke(app, ["report", str(tmp_path / "none.nc"), "-o", str(tmp_path / "r")])
    assert res.exit_code == 2 and "no result file" in res.output
    assert ROOT.is_dir()


def test_report_of_a_study_whose_contact_runs_all_failed(tmp_path):
    from pounding.studies import study_from_dict

    data = _base(law=["none", "hertz"], gap=[0.005])
    data["analysis"].update(max_iter=1, max_halvings=0)  # Newton cannot converge at an impact
    ds = run_study(study_from_dict(data), tmp_path / "runs", jobs=1)
    assert list(ds["run_status"].values.ravel()) == ["ok", "failed"]
    rep = build_report(ds)
    html = _html(write_report(ds, tmp_path / "report", formats=["html"]))
    assert "ConvergenceError" in html
    assert [s.title for s in rep.sections][:3] == ["Executive summary", "Study", "Model"]
    # no finished contact run: no statistic, shown as a dash, never "nan"
    row = rep.sections[0].blocks[-1].rows[0]
    assert row[3] == "– / – / –" and "nan" not in " ".join(row)


def test_isolated_analysis_report_has_the_bearing_section(tmp_path):
    # issue 7 item 4: hysteresis loops of the bearings and base displacements in the report
    from pathlib import Path

    from pounding.case import load_case
    from pounding.report import build_report, render_html
    from pounding.simulate import simulate

    case = load_case(Path(__file__).resolve().parents[1] / "examples" / "base_isolated_moat.toml")
    ds = simulate(case, duration=4.0)
    report = build_report(ds)
    titles = [s.title for s in report.sections]
    assert "Base isolation" in titles
    section = report.sections[titles.index("Base isolation")]
    assert sum(type(b).__name__ == "Plot" for b in section.blocks) == 2
    html = render_html(report)
    assert "Base isolation" in html and "hysteresis" in html


MATHTEXT_NAMES = ("A$b_c^d", r"$\undefinedmacro$")


@pytest.fixture(scope="module")
def mathtext_report(tmp_path_factory):
    """Buildings named like matplotlib mathtext (issue 16: an unknown macro failed the report, two
    "$" garbled the label)."""
    data = _base()
    del data["study"]
    for b, name in zip(data["building"], MATHTEXT_NAMES, strict=True):
        b["name"] = name
    data["contact"][0].update(left=MATHTEXT_NAMES[0], right=MATHTEXT_NAMES[1])
    ds = simulate(case_from_dict(data))
    return ds, write_report(ds, tmp_path_factory.mktemp("mathtext") / "report")


def test_report_of_a_building_named_like_mathtext_draws_the_name_as_written(mathtext_report):
    from pounding.report.html import _svg

    ds, paths = mathtext_report
    assert [p.name for p in paths] == ["report.html", "report.pdf"]
    model = next(s for s in build_report(ds).sections if s.title == "Model")
    modes = next(b for b in model.blocks if hasattr(b, "figure"))
    svg = str(_svg(modes.figure))
    for name in MATHTEXT_NAMES:
        assert f"building {name}" in svg
    assert "A$b_c^d" in _html(paths)


@needs_poppler
def test_pdf_of_a_building_named_like_mathtext_prints_the_name_as_written(mathtext_report):
    _, paths = mathtext_report
    text = subprocess.run(
        [PDFTOTEXT, str(_pdf(paths)), "-"], capture_output=True, text=True, check=True
    ).stdout
    assert "Shear buildings A$b_c^d, $\\undefinedmacro$" in text


def test_report_dispatches_through_the_registry(analysis_report, monkeypatch):
    from pounding.report import REPORT_BUILDERS, Report

    assert set(REPORT_BUILDERS) == {"analysis", "study", "separation", "fragility"}
    ds, _ = analysis_report
    stub = Report("stub", "analysis", [], [])
    monkeypatch.setitem(REPORT_BUILDERS, "analysis", lambda ds, store: stub)
    assert build_report(ds) is stub


def test_study_dispersion_is_the_maximum_likelihood_lognormal_fit(study_report):
    # one lognormal fit (issue 14 item 4): the report's β is separation.fit_lognormal's, divisor n
    from pounding.report import _g
    from pounding.separation import fit_lognormal

    ds, _ = study_report
    rep = build_report(ds)
    comparison = next(s for s in rep.sections if s.title == "Comparison of contact laws")
    table = comparison.blocks[-1]
    assert "lognormal, maximum likelihood" in table.caption
    group = table.header[:2]
    assert group == ["law", "gap"]
    col = table.header.index("β L")
    row = table.rows[0]
    sel = {"law": row[0], "gap": float(row[1])}
    amp = ds["displacement_amplification"].sel(building="L", **sel).values.ravel()
    amp = amp[np.isfinite(amp) & (amp > 0)]
    assert amp.size == 2  # two records
    beta = fit_lognormal(amp).beta
    assert row[col] == _g(beta, 2)
    # ML for two values: |ln a1 - ln a2| / 2, the sample standard deviation's 1/sqrt(2)
    ln = np.log(amp)
    assert beta == pytest.approx(abs(ln[0] - ln[1]) / 2)
    assert beta == pytest.approx(np.std(ln, ddof=1) / np.sqrt(2))


def test_separation_report_names_its_lognormal_fit(separation_report):
    ds, paths = separation_report
    rep = build_report(ds)
    interface = rep.sections[3]
    fit = next(b for b in interface.blocks if isinstance(b, str) and "β" in b)
    assert "(lognormal, maximum likelihood)" in fit
    from pounding.report import _g
    from pounding.separation import fit_lognormal

    exact = ds["required_gap"].sel(interface="A|B", estimate="time_history").values
    beta = fit_lognormal(exact).beta
    assert beta == pytest.approx(float(ds["lognormal_beta"].sel(interface="A|B")))
    assert f"β {_g(beta, 3)}" in fit


def test_a_law_whose_effective_e_misses_its_nominal_one_is_flagged():
    # Lankarani–Nikravesh at e = 0.65 rebounds at 0.775 in a free impact (independent DOP853 solve):
    # the report says so and names the fix; Hunt–Crossley with calibration = "exact" is not flagged.
    from pounding.contact.calibrate import effective_restitution
    from pounding.report.sections import _contact_law_table

    row = {"law": "lankarani_nikravesh", "k": 2.75e9, "mass": 1.5e5, "v0": 0.5, "observed": True}
    table = _contact_law_table([{**row, "e": 0.65}])
    e_eff = effective_restitution("lankarani_nikravesh", k=2.75e9, mass=1.5e5, v0=0.5, e=0.65)
    assert f"effective e of {e_eff.e_effective:.3f} for the nominal 0.65" in table.caption
    assert 'calibration = "exact"' in table.caption
    exact = {**row, "law": "hunt_crossley", "e": 0.65, "calibration": "exact"}
    assert "Warning" not in _contact_law_table([exact]).caption


@pytest.mark.parametrize(("calibration", "flagged"), [("nominal", True), ("exact", False)])
def test_analysis_report_flags_the_restitution_of_the_law_as_run(calibration, flagged):
    # the result records each contact's calibration (contact_calibration), so the report's
    # single-impact check uses the law as it ran
    import tomllib

    data = tomllib.loads((ROOT / "examples" / "three_vs_eight_story.toml").read_text())
    data["contact"][0].update(law="lankarani_nikravesh", calibration=calibration)
    ds = simulate(case_from_dict(data))
    assert set(ds["contact_calibration"].values) == {calibration}
    # the run's summary warns too (the CLI prints it): its free impact through the compiled loop
    # against the independent DOP853 one of effective_restitution at the same speed
    warned = [w for w in ds.pounding.summary()["warnings"] if "rebounds at e =" in w]
    assert bool(warned) is flagged
    if flagged:
        from pounding.contact.calibrate import effective_restitution

        v0 = float(warned[0].split(" m/s")[0].split()[-1])
        e_loop = float(warned[0].split("rebounds at e = ")[1].split()[0])
        mass = float(ds["contact_effective_mass"].max())
        ref = effective_restitution("lankarani_nikravesh", k=2.75e9, mass=mass, v0=v0, e=0.65)
        assert e_loop == pytest.approx(ref.e_effective, abs=1.5e-3)
    model = next(s for s in build_report(ds).sections if s.title == "Model")
    table = next(b for b in model.blocks if hasattr(b, "header") and "effective e" in b.header)
    assert ("Warning: lankarani_nikravesh" in table.caption) is flagged
    # the three contacts share one law and m̄: one row, at the largest speed any of them saw
    assert len(table.rows) == 1 and table.rows[0][6] == "observed"
    assert float(table.rows[0][5]) == pytest.approx(float(ds["impact_v0"].max()), rel=1e-3)
    # and the executive summary, the first section, carries it once with the run's other warnings
    executive = build_report(ds).sections[0]
    notes = [b for b in executive.blocks if isinstance(b, str) and "lankarani_nikravesh" in b]
    assert len(notes) == int(flagged)


def test_executive_summary_flags_drift_beyond_the_limit():
    # examples/two_sdof.toml: 6.7 % drift from elastic stories (the default limit is 2 %)
    import tomllib

    data = tomllib.loads((ROOT / "examples" / "two_sdof.toml").read_text())
    notes = [b for b in build_report(simulate(case_from_dict(data))).sections[0].blocks]
    assert any(isinstance(n, str) and "building B: peak drift ratio" in n for n in notes)
    data["output"] = {"drift_limit": 0.5}
    notes = build_report(simulate(case_from_dict(data))).sections[0].blocks
    assert not any(isinstance(n, str) and "drift" in n for n in notes)


def _report_words(report) -> set[str]:
    """Every word of a report's text: title, header lines, section titles, paragraphs, table
    headers, cells and captions, figure captions."""
    texts = [report.title, *(f"{k} {v}" for k, v in report.meta)]
    for sec in report.sections:
        texts.append(sec.title)
        for b in sec.blocks:
            if isinstance(b, str):
                texts.append(b)
            elif hasattr(b, "header"):
                texts += [*b.header, *(c for row in b.rows for c in row), b.caption]
            else:
                texts.append(b.caption)
    return _words(" ".join(texts))


def _words(text: str) -> set[str]:
    return set(re.findall(r"[A-Za-z0-9]+", text))


@needs_poppler
@pytest.mark.parametrize("which", ["analysis_report", "study_report", "separation_report"])
def test_html_and_pdf_of_a_report_carry_the_same_content(request, which):
    import html as html_lib

    ds, paths = request.getfixturevalue(which)
    words = _report_words(build_report(ds))
    page = html_lib.unescape(re.sub(r"<[^>]+>", " ", _html(paths)))
    pdf = subprocess.run(
        [PDFTOTEXT, "-layout", str(_pdf(paths)), "-"], capture_output=True, text=True, check=True
    ).stdout
    assert len(words) > 100
    assert words - _words(page) == set()
    assert words - _words(pdf) == set()


@needs_poppler
def test_pdf_figures_sit_with_their_captions_two_to_a_page(analysis_report):
    ds, paths = analysis_report
    pdf = str(_pdf(paths))
    images = subprocess.run(["pdfimages", "-list", pdf], capture_output=True, text=True).stdout
    per_page: dict[int, int] = {}
    for line in images.splitlines()[2:]:
        per_page[int(line.split()[0])] = per_page.get(int(line.split()[0]), 0) + 1
    n_figures = sum(1 for s in build_report(ds).sections for b in s.blocks if hasattr(b, "figure"))
    assert sum(per_page.values()) == n_figures
    assert max(per_page.values()) <= 2 and list(per_page.values()).count(2) >= 2
    for page, count in per_page.items():
        text = subprocess.run(
            [PDFTOTEXT, "-f", str(page), "-l", str(page), pdf, "-"],
            capture_output=True,
            text=True,
        ).stdout
        # each figure's caption is on its page, at full resolution
        assert len(re.findall(r"Figure \d+\.\d+:", text)) == count, page
    assert re.search(r"\s(1[5-9]\d|2\d\d)\s+(1[5-9]\d|2\d\d)\s", images)  # x-ppi, y-ppi ~200


def test_yielding_analysis_report_has_the_story_section_with_its_numbers():
    # issue 15 item 4: ductility, residual drift, hysteretic energy and damage per story, and the
    # hysteresis loops of the most ductile stories
    from pathlib import Path

    from pounding.case import load_case
    from pounding.report import build_report, render_html
    from pounding.simulate import simulate

    example = Path(__file__).resolve().parents[1] / "examples" / "three_vs_eight_yielding.toml"
    ds = simulate(load_case(example))
    report = build_report(ds)
    titles = [s.title for s in report.sections]
    section = report.sections[titles.index("Yielding stories")]
    table = next(b for b in section.blocks if type(b).__name__ == "Table")
    assert table.header[:6] == ["building", "story", "model", "F_y [kN]", "δ_y [mm]",
                                "peak ductility"]  # fmt: skip
    assert [r[0] for r in table.rows] == ["A", "A", "A"]
    mu = float(ds.story_ductility.sel(building="A", story=1))
    assert table.rows[0][5] == f"{mu:.3g}"
    assert sum(type(b).__name__ == "Plot" for b in section.blocks) == 1
    assert "Yielding stories" in render_html(report)
