"""The document model of a report: sections of paragraphs, tables and figures, and the text of the
values a page shows.

A report kind builds a :class:`Report`; :mod:`pounding.report.html` and :mod:`pounding.report.pdf`
render it. Nothing here knows which kind of result it came from.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np
from matplotlib.figure import Figure

#: Output formats of :func:`pounding.report.write_report`.
FORMATS = ("html", "pdf")
#: Approach speed [m/s] for the effective restitution of a law that saw no impact.
NOMINAL_V0 = 0.5
#: The study's contact law of the no-contact baseline runs.
_NO_CONTACT = "none"
#: Longest table of rows (impacts, failures, records) a report prints.
_MAX_ROWS = 40
#: matplotlib settings of every report figure: text kept as text in SVG, TrueType in PDF, stable ids.
_RC = {"svg.fonttype": "none", "pdf.fonttype": 42, "font.size": 9, "svg.hashsalt": "pounding"}


def keep_layout(fig: Figure) -> None:
    """Keep the positions the figure's layout engine found when it was last drawn: the same
    figure is drawn for the HTML (SVG) and the PDF (raster), and constrained layout's search is
    a third of a drawing's cost. Positions are fractions of the figure, the same at any dpi."""
    fig.set_layout_engine("none")


@dataclasses.dataclass
class Table:
    """A table: header, rows of cells (strings) and an optional caption (a note under it)."""

    header: list[str]
    rows: list[list[str]]
    caption: str = ""


@dataclasses.dataclass
class Plot:
    """A figure with its caption."""

    figure: Figure
    caption: str = ""


@dataclasses.dataclass
class Section:
    """A titled section: paragraphs (``str``), :class:`Table` and :class:`Plot` blocks in order."""

    title: str
    blocks: list[str | Table | Plot] = dataclasses.field(default_factory=list)

    @property
    def anchor(self) -> str:
        return "".join(c if c.isalnum() else "-" for c in self.title.lower())


@dataclasses.dataclass
class Report:
    """A report: its title, its kind (a key of ``REPORT_BUILDERS``), sections and header lines."""

    title: str
    kind: str  # "analysis", "study" or "separation"
    sections: list[Section]
    meta: list[tuple[str, str]]


def _g(value: Any, digits: int = 4) -> str:
    """``value`` to ``digits`` significant digits; "–" for NaN or infinity, ``str`` for text."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        return str(value)
    if not math.isfinite(v):
        return "–"
    return f"{v:.{digits}g}"


def _value_text(v: Any) -> str:
    """An axis value as a table shows it (floats in ``g`` format)."""
    return f"{v:g}" if isinstance(v, (float, np.floating)) else str(v)


def _median(values: np.ndarray) -> float:
    """Median of the finite values; NaN when there are none."""
    v = values[np.isfinite(values)]
    return float(np.median(v)) if v.size else float("nan")
