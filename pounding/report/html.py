"""A report as one self-contained HTML page: the package's Jinja2 template (autoescaped), inline CSS
and figures as inline SVG, no script and no external resource."""

from __future__ import annotations

import io
from pathlib import Path
from typing import Any

import jinja2
import matplotlib
from markupsafe import Markup
from matplotlib.figure import Figure

from pounding._version import __version__
from pounding.report.document import _RC, Report, Table, keep_layout


def _svg(fig: Figure) -> Markup:
    buf = io.StringIO()
    with matplotlib.rc_context(_RC):
        fig.savefig(buf, format="svg", metadata={"Date": None})
    keep_layout(fig)
    text = buf.getvalue()
    text = text[text.index("<svg") :]  # drop the XML prolog and DOCTYPE
    return Markup(text)  # matplotlib escapes the figure's text itself


def _is_numeric(text: Any) -> bool:
    try:
        float(str(text))
    except ValueError:
        return str(text) == "–"
    return True


def _environment() -> jinja2.Environment:
    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(Path(__file__).parent / "templates"),
        autoescape=True,
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
    )
    env.tests["numeric"] = _is_numeric
    return env


def render_html(report: Report) -> str:
    """One self-contained HTML page: inline CSS and SVG, no script, no external resource."""
    blocks = []
    for sec in report.sections:
        items = []
        for b in sec.blocks:
            if isinstance(b, str):
                items.append({"type": "text", "text": b})
            elif isinstance(b, Table):
                items.append({"type": "table", "table": b})
            else:
                items.append({"type": "figure", "svg": _svg(b.figure), "caption": b.caption})
        blocks.append({"title": sec.title, "anchor": sec.anchor, "items": items})
    return (
        _environment()
        .get_template("report.html.j2")
        .render(report=report, sections=blocks, version=__version__)
    )
