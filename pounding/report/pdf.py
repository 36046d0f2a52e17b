"""A report as a PDF with the HTML page's content: text and ruled tables laid out on A4 pages with
matplotlib's ``PdfPages``; each section's figures follow it, two to a page where they fit, each with
its caption beneath it."""

from __future__ import annotations

import textwrap
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.backends.backend_pdf import PdfPages
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from pounding._version import __version__
from pounding.plots import plain_text
from pounding.report.document import _RC, Plot, Report, Table, keep_layout


class _PageWriter:
    """Text and tables laid out top to bottom on A4 pages of a PdfPages."""

    W, H, MARGIN = 8.27, 11.69, 0.6
    #: widest table line [characters]: 6.2 pt monospace across the page
    MAX_CHARS = 135

    def __init__(self, pdf: PdfPages) -> None:
        self.pdf = pdf
        self.fig: Figure | None = None
        self.y = 0.0

    def _page(self) -> None:
        self.flush()
        self.fig = Figure(figsize=(self.W, self.H))
        self.y = self.H - self.MARGIN

    def flush(self) -> None:
        if self.fig is not None:
            self.pdf.savefig(self.fig)
            self.fig = None

    def line(
        self,
        text: str,
        size: float = 9,
        *,
        weight: str = "normal",
        family: str = "sans-serif",
        gap: float = 0.0,
    ) -> None:
        height = size * 1.45 / 72 + gap
        if self.fig is None or self.y - height < self.MARGIN:
            self._page()
        self.y -= height
        self.fig.text(
            self.MARGIN / self.W,
            self.y / self.H,
            plain_text(text),  # user text ($, _, ^) is not mathtext
            fontsize=size,
            weight=weight,
            family=family,
            va="baseline",
        )

    def paragraph(self, text: str) -> None:
        for ln in textwrap.wrap(text, 105) or [""]:
            self.line(ln)
        self.y -= 0.08

    def table(self, table: Table) -> None:
        cols = (
            list(zip(*([table.header] + table.rows), strict=True))
            if table.rows
            else [[h] for h in table.header]
        )
        widths = [min(max(len(str(c)) for c in col), 48) for col in cols]
        # narrow the widest columns until the table fits at a legible size; long cells wrap
        while sum(widths) + 2 * (len(widths) - 1) > self.MAX_CHARS and max(widths) > 12:
            widths[widths.index(max(widths))] -= 1
        total = sum(widths) + 2 * (len(widths) - 1)
        size = min(8.0, (self.W - 2 * self.MARGIN) * 72 / (0.61 * max(total, 1)))

        def emit(row: Sequence[str], **kw: Any) -> None:
            cells = [textwrap.wrap(str(c), w) or [""] for c, w in zip(row, widths, strict=True)]
            for k in range(max(len(c) for c in cells)):
                parts = [
                    (c[k] if k < len(c) else "").ljust(w)
                    for c, w in zip(cells, widths, strict=True)
                ]
                self.line("  ".join(parts).rstrip(), size, family="monospace", **kw)

        width = 0.6 * size / 72 * total  # inches: monospace advance ~0.6 em

        def rule(lw: float) -> None:
            if self.fig is None or self.y - 0.06 < self.MARGIN:
                self._page()
            y = (self.y - 0.045) / self.H
            x0 = self.MARGIN / self.W
            self.fig.add_artist(
                Line2D(
                    [x0, x0 + width / self.W],
                    [y, y],
                    lw=lw,
                    color="black",
                    transform=self.fig.transFigure,
                )
            )
            self.y -= 0.06

        self.y -= 0.06
        rule(0.8)  # top, mid and bottom rules, as in a printed table
        emit(table.header, weight="bold")
        rule(0.5)
        for row in table.rows:
            emit(row)
        rule(0.8)
        if table.caption:
            for ln in textwrap.wrap(table.caption, 120):
                self.line(ln, 7.5)
        self.y -= 0.12


def render_pdf(report: Report, path: str | Path) -> Path:
    """The same content as the HTML: text and tables on A4 pages, one page per figure."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with (
        matplotlib.rc_context(_RC),
        PdfPages(
            path, metadata={"Title": report.title, "Creator": f"pounding {__version__}"}
        ) as pdf,
    ):
        w = _PageWriter(pdf)
        w.line(report.title, 16, weight="bold")
        w.line(f"pounding {report.kind} report", 10, gap=0.05)
        for key, value in report.meta:
            w.line(f"{key}: {value}", 8.5)
        w.y -= 0.15
        for n, sec in enumerate(report.sections, 1):
            if not all(isinstance(b, Plot) for b in sec.blocks):
                # a section of figures only starts on its figure page (which carries the title)
                w.line(f"{n}. {sec.title}", 13, weight="bold", gap=0.15)
            figures: list[Plot] = []
            for b in sec.blocks:
                if isinstance(b, str):
                    w.paragraph(b)
                elif isinstance(b, Table):
                    w.table(b)
                else:
                    figures.append(b)
            if figures:  # figures take pages of their own; text-only sections share pages
                w.flush()
                _figure_pages(pdf, figures, f"{n}. {sec.title}", n)
        w.flush()
    return path


#: Resolution of the figures placed on the PDF's pages [dots per inch].
FIGURE_DPI = 200


def raster(fig: Figure, dpi: float) -> np.ndarray:
    """The figure drawn by Agg at ``dpi`` as RGBA pixels (what ``savefig(format="png")`` would
    encode, without encoding and decoding a PNG). Its layout is kept from then on (see
    :func:`pounding.report.document.keep_layout`)."""
    old = fig.dpi
    canvas = FigureCanvasAgg(fig)
    try:
        fig.set_dpi(dpi)
        with matplotlib.rc_context(_RC):
            canvas.draw()
        image = np.array(canvas.buffer_rgba())
    finally:
        fig.set_dpi(old)
    keep_layout(fig)
    return image


def _figure_pages(pdf: PdfPages, figures: Sequence[Plot], section: str, n: int) -> None:
    """The figures of a section, each with its caption beneath it, as many to an A4 page as fit
    (two of the usual height); a figure taller than the page is scaled down to fit."""
    W, H, M = _PageWriter.W, _PageWriter.H, _PageWriter.MARGIN
    usable_w, usable_h = W - 2 * M, H - 2 * M - 0.3
    page: Figure | None = None
    y = 0.0
    for k, p in enumerate(figures, 1):
        image = raster(p.figure, FIGURE_DPI)
        fw, fh = p.figure.get_size_inches()
        scale = min(1.0, usable_w / fw, (usable_h - 0.6) / fh)
        w, h = fw * scale, fh * scale
        caption = textwrap.wrap(plain_text(f"Figure {n}.{k}: {p.caption}"), 115)
        need = h + 0.2 + 8.5 * 1.45 / 72 * len(caption) + 0.25
        if page is None or y - need < M:
            if page is not None:
                pdf.savefig(page)
            page = Figure(figsize=(W, H))
            page.text(M / W, (H - M) / H, plain_text(section), fontsize=10, weight="bold", va="top")
            y = H - M - 0.3
        ax = page.add_axes(((W - w) / 2 / W, (y - h) / H, w / W, h / H))
        ax.imshow(image, interpolation="none")  # embedded at FIGURE_DPI, not resampled
        ax.set_axis_off()
        y -= h + 0.15
        for ln in caption:
            y -= 8.5 * 1.45 / 72
            page.text(M / W, y / H, ln, fontsize=8.5, va="baseline")
        y -= 0.25
    if page is not None:
        pdf.savefig(page)
