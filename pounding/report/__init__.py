"""Reports of an analysis, a study or a separation check: one self-contained HTML file and a PDF with
the same content.

:func:`build_report` turns a result Dataset into a :class:`Report` (sections of paragraphs, tables
and figures) with the builder of its kind in :data:`REPORT_BUILDERS`; :func:`render_html` renders it
with the package's Jinja2 template (autoescaped, figures as inline SVG, no external resources),
:func:`render_pdf` with matplotlib's ``PdfPages`` (text and table pages, then one page per figure).
:func:`write_report` does both into a directory.

Sections of an analysis: model (buildings, periods and mode shapes, contacts with nominal and
effective restitution), ground motion (time history, response spectrum, processing chain, intensity
measures), results (displacement histories with impacts, envelopes, contact forces, force–penetration
loops, impacts, energy ledger). A study adds the sweep (axes, failures) and the comparison of the
laws across the axes and records (amplification plots, heat maps, median/dispersion tables). A
separation check (:func:`pounding.separation.separation_analysis`) gives the buildings' modes, the
method, and per interface the required gap of every estimate, the probability of pounding against
the gap and the exact gap of every record. Every lognormal β a report prints is the maximum-likelihood
fit of :func:`pounding.separation.fit_lognormal`.

Modules, bottom up: ``document`` (the document model and value text), ``sections`` (shared
sections), ``analysis`` | ``study`` | ``separation`` (one per report kind), ``html`` | ``pdf``
(renderers), ``build`` (the registry and the entry points). This module only re-exports.
"""

from pounding.report.analysis import analysis_report
from pounding.report.build import REPORT_BUILDERS, build_report, write_report
from pounding.report.document import FORMATS, NOMINAL_V0, Plot, Report, Section, Table
from pounding.report.document import _g as _g  # the tests compare cells with it
from pounding.report.html import render_html
from pounding.report.pdf import render_pdf
from pounding.report.separation import separation_report
from pounding.report.study import study_report

__all__ = [
    "FORMATS",
    "NOMINAL_V0",
    "REPORT_BUILDERS",
    "Plot",
    "Report",
    "Section",
    "Table",
    "analysis_report",
    "build_report",
    "render_html",
    "render_pdf",
    "separation_report",
    "study_report",
    "write_report",
]
