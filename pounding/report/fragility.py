"""The report of an incremental dynamic analysis (``pounding ida``): the fragility of each limit
state with and without pounding (executive summary, curves with bootstrap bands, the fits), the IDA
curves, the analysis and its assumptions, the model and the records."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import xarray as xr

from pounding import plots
from pounding._version import __version__
from pounding.fragility import no_contact, variants
from pounding.report.document import _NO_CONTACT, Plot, Report, Section, Table, _g
from pounding.report.sections import _model_section

#: Bootstrap resamples of the report's fits (90 % intervals).
N_BOOT = 500


def _limit_states(ds: xr.Dataset) -> list[str | float]:
    return list(json.loads(ds.attrs.get("limit_states", '["collapse"]')))


def _name(fr: xr.Dataset, at: dict[str, int]) -> list[str]:
    cells = []
    for d, i in at.items():
        v = fr[d].values[i]
        if no_contact(fr, at) and d != "law":
            cells.append("–")
        else:
            cells.append(f"{v:g}" if isinstance(v, float | np.floating) else str(v))
    return cells


def _headers(fr: xr.Dataset, dims: list[str]) -> list[str]:
    """Column titles of the variant axes, with their units."""
    return [
        f"{d} [{fr[d].attrs['units']}]" if fr[d].attrs.get("units", "1") != "1" else d for d in dims
    ]


def _fit_table(fr: xr.Dataset) -> Table:
    dims = [d for d in fr["fragility_median"].dims if d != "limit_state"]
    selections = variants(fr, dims)
    header = [
        "limit state",
        *_headers(fr, dims),
        "median [g]", "90 % interval [g]", "β", "with / without contact", "note",
    ]  # fmt: skip
    rows = []
    for limit in fr["limit_state"].values:
        sel = fr.sel(limit_state=limit)
        for at in selections:
            one = sel.isel(at)
            ratio = (
                float(one["pounding_median_ratio"]) if "pounding_median_ratio" in one else math.nan
            )
            interval = (
                f"{_g(float(one['fragility_median_low']), 3)}–"
                f"{_g(float(one['fragility_median_high']), 3)}"
                if "fragility_median_low" in one
                else "–"
            )
            rows.append(
                [
                    str(limit),
                    *_name(fr, at),
                    _g(float(one["fragility_median"]), 3),
                    interval,
                    _g(float(one["fragility_beta"]), 2),
                    _g(ratio, 3),
                    str(one["fit_note"].values),
                ]
            )
    return Table(
        header,
        rows,
        "Lognormal fragility P = Φ(ln(IM/θ)/β), θ the median capacity; "
        f"{fr.attrs.get('method', '')}; intervals: {N_BOOT} bootstrap resamples. "
        "with / without contact = median with the variant's contacts over the median of the same "
        "records without contact (below 1: pounding lowers the capacity).",
    )


def _executive(fr: xr.Dataset) -> list[str]:
    """The lead sentence per limit state: the variant whose contacts lower the median most."""
    if "pounding_median_ratio" not in fr:
        return []
    lines = []
    for limit in fr["limit_state"].values:
        ratio = fr["pounding_median_ratio"].sel(limit_state=limit)
        if not int(ratio.notnull().sum()):
            continue
        flat = int(np.nanargmin(ratio.values))
        at = dict(zip(ratio.dims, np.unravel_index(flat, ratio.shape), strict=True))
        worst = float(ratio.values.ravel()[flat])
        without = float(
            fr["fragility_median"].sel(limit_state=limit, law=_NO_CONTACT).values.ravel()[0]
        )
        with_ = float(fr["fragility_median"].sel(limit_state=limit).isel(at))
        where = ", ".join(f"{d} {fr[d].values[i]}" for d, i in at.items())
        if worst < 1.0:
            lines.append(
                f"{limit}: pounding lowers the median capacity most at {where}: "
                f"{_g(with_, 3)} g instead of {_g(without, 3)} g ({100 * (1 - worst):.0f} % lower)."
            )
        else:
            lines.append(
                f"{limit}: no variant lowers the median capacity below the no-contact "
                f"{_g(without, 3)} g."
            )
    return lines


def _pounding_table(fr: xr.Dataset) -> Table | None:
    """The fraction of the records that pound at each level, per variant with contacts."""
    if "pounding_probability" not in fr:
        return None
    prob = fr["pounding_probability"]
    dims = [d for d in prob.dims if d != "im_level"]
    rows = []
    for at in variants(fr, dims):
        if no_contact(fr, at):
            continue
        rows.append([*_name(fr, at), *(f"{100 * v:.0f} %" for v in prob.isel(at).values)])
    if not rows:
        return None
    header = [*_headers(fr, dims), *(f"{_g(v, 3)} g" for v in fr["im_level"].values)]
    return Table(header, rows, "Probability of pounding: the share of the records with at least "
                 "one impact at each intensity level.")  # fmt: skip


def _records_table(ds: xr.Dataset) -> Table:
    rows = []
    hunt = "ida_run" in ds.dims
    # per record: target levels and scale factors of its runs (every variant)
    level = ds["ida_level"] if hunt else ds["im_level"].broadcast_like(ds["scale_factor"])
    scale = ds["scale_factor"] if "scale_factor" in ds else None
    for r, name in enumerate(ds["record"].values):
        ref = str(ds["record_reference"].values[r]) if "record_reference" in ds else ""
        im, sf = math.nan, "–"
        if scale is not None:
            s = scale.isel(record=r).values.ravel()
            lv = level.isel(record=r).values.ravel()
            ok = np.isfinite(s) & (s > 0) & np.isfinite(lv)
            if ok.any():
                im = float(lv[ok][0] / s[ok][0])
                sf = f"{_g(s[ok].min(), 3)}–{_g(s[ok].max(), 3)}"
        if "record_im" in ds:
            im = float(ds["record_im"].values[r])
        rows.append([str(name), ref, _g(im, 3), sf])
    return Table(["record", "reference", "IM as recorded [g]", "scale factors"], rows[:60])


def _capacity_table(ds: xr.Dataset) -> Table | None:
    """Per variant of an IDA: the collapse intensities bracketed, their median and the records
    censored."""
    if "collapse_im" not in ds:
        return None
    dims = [d for d in ds["collapse_im"].dims if d != "record"]
    rows = []
    for at in variants(ds, dims):
        cap = ds["collapse_im"].isel(at).values
        width = (ds["collapse_im"] - ds["collapse_im_lower"]).isel(at).values
        found = np.isfinite(cap)
        rows.append(
            [
                *_name(ds, at),
                f"{int(found.sum())} of {cap.size}",
                _g(float(np.median(np.where(found, cap, np.inf))), 3)
                if 2 * found.sum() > cap.size
                else "–",
                _g(float(np.nanmax(width)), 2) if found.any() else "–",
                _g(float(np.nanmin(ds["im_max_run"].isel(at).values[~found])), 3)
                if (~found).any()
                else "–",
            ]
        )
    hunt = json.loads(ds.attrs.get("hunt", "{}"))
    return Table(
        [*_headers(ds, dims), "records with a capacity", "median [g]", "widest bracket [g]",
         "lowest censoring level [g]"],
        rows,
        f"Collapse capacities ({hunt.get('limit_state', 'collapse')}): the lowest level "
        "reaching it, the bracket to the highest level below that did not, and the records "
        "without one (censored at their highest run); the median counts them above all others.",
    )  # fmt: skip


def fragility_report(ds: xr.Dataset, store: Path | None = None) -> Report:
    """The report of an IDA (a study Dataset with ``im_level`` and ``record`` axes)."""
    limits = _limit_states(ds)
    fr = ds.pounding.fragility(limits, n_boot=N_BOOT)
    im = json.loads(ds.attrs.get("intensity_measure", "{}"))
    hunt = "ida_run" in ds.dims
    label = (ds["ida_level"] if hunt else ds["im_level"]).attrs.get("long_name", "intensity")
    analysis = json.loads(ds.attrs.get("analysis", "{}"))
    collapse = float(analysis.get("collapse_drift") or 0.1)
    n_rec = ds.sizes["record"]
    n_lev = ds.sizes["ida_run"] if hunt else ds.sizes["im_level"]
    failed = int((ds["run_status"] == "failed").sum())
    summary = Section("Executive summary")
    summary.blocks.extend(_executive(fr))
    summary.blocks.append(_fit_table(fr))
    curves = Section("Fragility curves")
    observed = (
        "each record's capacity as the empirical distribution (markers)"
        if hunt
        else f"the fraction of the {n_rec} records that reached it at each level (markers)"
    )
    curves.blocks.append(
        f"Probability of reaching each limit state against {label}: {observed} and the fitted "
        "lognormal curve with its pointwise 90 % bootstrap band, per variant (any building)."
    )
    capacities = _capacity_table(ds)
    if capacities is not None:
        summary.blocks.append(capacities)
    curves.blocks.append(Plot(plots.fragility_curves(fr), "Fragility curves."))
    pounding = _pounding_table(fr)
    if pounding is not None:
        curves.blocks.append(pounding)
    ida = Section("IDA curves")
    for b in ds["building"].values:
        ida.blocks.append(
            Plot(
                plots.ida_curves(ds, str(b)),
                f"Largest peak story drift ratio of building {b} against {label}: one line per "
                f"record, the median over the records; a collapse is drawn at the collapse drift "
                f"{100 * collapse:g} % (dotted).",
            )
        )
    method = Section("Analysis")
    if hunt:
        h = json.loads(ds.attrs.get("hunt", "{}"))
        levels = (
            f"{n_rec} records traced by hunt-and-fill (Vamvatsikos & Cornell 2004): first "
            f"{_g(h.get('first'), 3)} g, steps {_g(h.get('step'), 3)} g growing by "
            f"{_g(h.get('step_increase'), 3)} g until {h.get('limit_state')}, then bisection to "
            f"{_g(h.get('tolerance'), 3)} g and filling of the widest gaps below, at most "
            f"{h.get('max_runs')} runs per record and {_g(h.get('max_level'), 3)} g (a failed run "
            "counts as collapse); capacities of other drift limits are read off each record's "
            "IDA curve, linear between its runs"
        )
    else:
        levels = (
            f"{n_rec} records × {n_lev} levels of {label} "
            f"({', '.join(_g(v, 3) for v in ds['im_level'].values)} g)"
        )
    measure = im.get("measure", "")
    scaled = (
        "the records normalised by their PGV (NM = median PGV / PGV) and scaled together so that "
        f"the set's median {measure} is the level (FEMA P695 Sec. 6.2)"
        if ds.attrs.get("scaling") == "set"
        else f"each record scaled by SF = IM_target / IM(record) (intensity measure {measure}, "
        "exact for it)"
    )
    method.blocks.append(
        f"Incremental dynamic analysis (Vamvatsikos & Cornell 2002): {levels}, {scaled}, "
        f"for every variant{'' if hunt else ' and without contact'}. Collapse: a building "
        "with yielding stories "
        f"or P-Δ whose story drift ratio passes {collapse:g}, or with an IMK story whose energy "
        "capacity is spent, where the analysis stops (a Newton failure past that drift or at that "
        "story counts as collapse); a collapsed run reaches every drift limit state. "
        f"{failed} run(s) failed and are left out. Fits: {fr.attrs.get('method', '')}; "
        f"elastic buildings cannot collapse, so their collapse fragility is that of the others."
    )
    method.blocks.append(_records_table(ds))
    sections = [summary, curves, ida, method, _model_section(ds, [])]
    meta = [
        ("records × levels", f"{n_rec} × {'up to ' if hunt else ''}{n_lev}"),
        ("intensity", f"{label} [g]"),
        ("pounding", str(ds.attrs.get("pounding_version", __version__))),
    ]
    return Report(str(ds.attrs.get("title") or "Fragility"), "fragility", sections, meta)
