"""The report kinds by name, and the entry points that pick one: :func:`build_report` chooses the
builder of :data:`REPORT_BUILDERS` by :func:`pounding.results.result_kind`, :func:`write_report` also
renders the HTML page and the PDF."""

from __future__ import annotations

import warnings
from collections.abc import Callable, Sequence
from pathlib import Path

import matplotlib
import xarray as xr

from pounding.errors import PoundingInputError
from pounding.report.analysis import analysis_report
from pounding.report.document import _RC, FORMATS, Report
from pounding.report.fragility import fragility_report
from pounding.report.html import render_html
from pounding.report.pdf import render_pdf
from pounding.report.separation import separation_report
from pounding.report.study import study_report
from pounding.results import result_kind

#: Report builder of each result kind: ``builder(ds, store) -> Report``; ``store`` is a study's run
#: store (None: the one the Dataset records), which the other kinds ignore.
REPORT_BUILDERS: dict[str, Callable[[xr.Dataset, Path | None], Report]] = {
    "analysis": analysis_report,
    "study": study_report,
    "separation": separation_report,
    "fragility": fragility_report,
}


def report_kind(ds: xr.Dataset) -> str:
    """The report kind of a result: :func:`pounding.results.result_kind`, and ``"fragility"`` for a
    study with an ``im_level`` axis (an incremental dynamic analysis)."""
    kind = result_kind(ds)
    ida = "im_level" in ds.dims or "ida_run" in ds.dims
    return "fragility" if kind == "study" and ida else kind


def build_report(ds: xr.Dataset, *, store: str | Path | None = None) -> Report:
    """The report of an analysis (from :func:`pounding.simulate`), a study, or a separation check
    (from :func:`pounding.separation.separation_analysis`).

    ``store`` is the study's run store (default the one recorded in the Dataset) for the kept
    time histories.
    """
    try:
        kind = report_kind(ds)
    except ValueError as exc:
        raise PoundingInputError(f"report: {exc}") from None
    with matplotlib.rc_context(_RC):
        return REPORT_BUILDERS[kind](ds, Path(store) if store is not None else None)


def write_report(
    ds: xr.Dataset,
    output: str | Path,
    *,
    formats: Sequence[str] = FORMATS,
    result_path: str | Path | None = None,
) -> list[Path]:
    """Write ``report.html`` and/or ``report.pdf`` into the directory ``output``.

    ``result_path`` (the result file) locates a study's run store when it was moved with it.
    """
    bad = [f for f in formats if f not in FORMATS]
    if bad:
        raise PoundingInputError(
            f"report format(s) {', '.join(bad)}; allowed: {', '.join(FORMATS)}"
        )
    store = None
    if result_kind(ds) == "study":
        recorded = Path(str(ds.attrs.get("store", "")))
        if not recorded.is_dir() and result_path is not None:
            from pounding.studies import default_store

            recorded = default_store(result_path)
        store = recorded
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        rep = build_report(ds, store=store)
    out = Path(output)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    if "html" in formats:
        page = out / "report.html"
        page.write_text(render_html(rep), encoding="utf-8")
        written.append(page)
    if "pdf" in formats:
        written.append(render_pdf(rep, out / "report.pdf"))
    return written
