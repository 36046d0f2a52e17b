"""The report of a separation check (``pounding separation``): the buildings' modes, the method,
per interface the required gap of every estimate and the lognormal fit of the exact gaps, the
probability of pounding against the gap, and the exact gap of every record."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import xarray as xr

from pounding import plots
from pounding._version import __version__
from pounding.report.document import _MAX_ROWS, Plot, Report, Section, Table, _g


def _interface_section(f: dict[str, Any], s: dict[str, Any]) -> Section:
    """Required gaps of every estimate and the lognormal fit of one interface ``f`` of the
    summary ``s``."""
    sec = Section(f"Interface {f['name']}")
    sec.blocks.append(f"Facing pairs: {', '.join(f['pairs'])}.")
    sec.blocks.append(
        Table(
            ["required gap", "median [m]", "84th percentile [m]", "largest [m]", "basis"],
            [
                [
                    str(r["label"]),
                    _g(r["median"]),
                    "–" if math.isnan(r["p84"]) else _g(r["p84"]),
                    "–" if math.isnan(r["max"]) else _g(r["max"]),
                    str(r["basis"]),
                ]
                for r in f["table"]
            ],
            "Statistics over the records; an estimate a record cannot give is left out of them.",
        )
    )
    ln = f["lognormal"]
    sec.blocks.append(
        "Fit of the exact gaps (lognormal, maximum likelihood): "
        f"median {_g(ln['median'])} m, β {_g(ln['beta'], 3)}, "
        f"{_g(100 * ln['fraction'], 3)} % of the records approach at all; gap with "
        f"P(pounding) = {_g(s['target_probability'], 3)}: {_g(ln['gap_for_target'])} m."
    )
    return sec


def _executive_section(ds: xr.Dataset, s: dict[str, Any]) -> Section:
    """Per interface: the case's gap against the exact required gap over the records, the share
    of records that pound at it, the gap of the target probability, and the verdict."""
    sec = Section("Executive summary")
    rows = []
    for f in s["interfaces"]:
        exact = [g for g in f["exact_gaps"] if math.isfinite(g)]
        st = ds["required_gap_statistic"].sel(interface=f["name"], estimate="time_history")
        stat = {k: float(st.sel(statistic=k)) for k in ("median", "p84", "max")}
        gap = float(ds["case_gap"].sel(interface=f["name"])) if "case_gap" in ds else math.nan
        if math.isfinite(gap) and exact:
            hits = sum(g > gap for g in exact)
            verdict = (
                "pounding expected" if gap < stat["median"] else "no pounding in the median record"
            )
            share = f"{hits} of {len(exact)}"
        else:
            verdict, share = "n/a (no gap in the case)", "–"
        rows.append(
            [
                f["name"],
                _g(gap) if math.isfinite(gap) else "–",
                " / ".join(
                    "–" if math.isnan(stat[k]) else _g(stat[k], 3) for k in ("median", "p84", "max")
                ),
                share,
                _g(f["lognormal"]["gap_for_target"], 3),
                verdict,
            ]
        )
    sec.blocks.append(
        Table(
            [
                "interface",
                "gap in the case [m]",
                "required gap, exact [m] median / 84th / max",
                "records that pound",
                f"gap for P = {_g(s['target_probability'], 3)} [m]",
                "verdict",
            ],
            rows,
            "Exact required gap: the largest approach of the facing floors without contact, per "
            "record; a record pounds when it exceeds the case's gap. Verdict: the case's gap against "
            "the median over the records.",
        )
    )
    return sec


def separation_report(ds: xr.Dataset, store: Path | None = None) -> Report:
    """The report of a separation check (from :func:`pounding.separation.separation_analysis`);
    ``store`` is not used."""
    from pounding.separation import separation_summary  # scipy.stats: ~0.5 s, only for this kind

    s = separation_summary(ds)
    n_modes = min(3, ds.sizes["mode"])
    period = ds["natural_period"]
    zeta = ds["modal_damping_ratio"]
    bld = Section("Buildings")
    bld.blocks.append(
        Table(
            ["building", *[f"T{m} [s]" for m in range(1, n_modes + 1)], "ζ1 [-]"],
            [
                [
                    str(b),
                    *[_g(float(period.sel(building=b).isel(mode=m))) for m in range(n_modes)],
                    _g(float(zeta.sel(building=b).isel(mode=0)), 3),
                ]
                for b in ds["building"].values
            ],
            "Natural periods and the first mode's damping ratio (modes beyond a building's own "
            "floors are empty).",
        )
    )
    method = Section("Method")
    records = s["records"]
    shown = ", ".join(records[:10]) + (
        f" and {len(records) - 10} more" if len(records) > 10 else ""
    )
    method.blocks.append(
        f"{len(records)} record{'s' if len(records) != 1 else ''}: {shown}. Exact gaps: time "
        f"histories without contact ({s['method']}, dt {_g(s['dt'])} s), the largest approach of "
        "facing floors over every integration step. Spectral and code estimates: "
        f"{s['spectrum']}. Probability of pounding: the fraction of records whose exact gap "
        "exceeds a given gap, and a lognormal fit of the exact gaps (maximum likelihood; Lin & "
        f"Weng 2001) read at the target probability {_g(s['target_probability'], 3)}."
    )
    sections = [_executive_section(ds, s), bld, method]
    sections += [_interface_section(f, s) for f in s["interfaces"]]
    figures = Section("Comparison")
    figures.blocks.append(
        Plot(
            plots.required_gaps(ds),
            "Required separation of every estimate: median over the records (bar), 84th percentile "
            "and largest (markers), and the lognormal gap at the target probability (dashed).",
        )
    )
    figures.blocks.append(
        Plot(
            plots.pounding_probability(ds),
            "Probability of pounding against the clear gap: fraction of records (steps) and "
            "lognormal fit.",
        )
    )
    gaps = Table(
        ["record", *[f"{f['name']} [m]" for f in s["interfaces"]]],
        [
            [rec, *[_g(f["exact_gaps"][i]) for f in s["interfaces"]]]
            for i, rec in enumerate(records[:_MAX_ROWS])
        ],
        "The largest approach of the facing floors of each interface without contact"
        + (f"; first {_MAX_ROWS} of {len(records)} records." if len(records) > _MAX_ROWS else "."),
    )
    sections.append(figures)
    sections.append(Section("Exact gaps per record", [gaps]))
    meta = [
        ("records", str(len(records))),
        ("method", s["method"]),
        ("dt", f"{_g(s['dt'])} s"),
        ("target probability of pounding", _g(s["target_probability"], 3)),
        ("pounding", str(ds.attrs.get("pounding_version", __version__))),
    ]
    return Report(s["title"] or "Separation distance", "separation", sections, meta)
