"""The report of a study (``pounding study``): the sweep (axes, failures), the model, the ground
motions, the comparison of the contact laws across the axes and records (amplification plots, heat
maps, median and lognormal dispersion tables) and the time histories the study kept."""

from __future__ import annotations

import itertools
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from pounding import plots
from pounding._version import __version__
from pounding.contact.laws import get_contact_law
from pounding.report.document import (
    _MAX_ROWS,
    _NO_CONTACT,
    NOMINAL_V0,
    Plot,
    Report,
    Section,
    Table,
    _g,
    _median,
    _value_text,
)
from pounding.report.sections import _ground_motion_section, _model_section, law_warnings


def _dispersion(values: np.ndarray) -> float:
    """Lognormal dispersion β of the positive finite values, maximum likelihood
    (:func:`pounding.separation.fit_lognormal`, divisor n); NaN with fewer than two of them."""
    from pounding.separation import fit_lognormal  # scipy.stats: ~0.5 s, not for other kinds

    v = values[np.isfinite(values) & (values > 0)]
    return fit_lognormal(v).beta if v.size > 1 else float("nan")


def _axes(ds: xr.Dataset) -> list[str]:
    return list(json.loads(ds.attrs.get("axes", "[]")))


def _study_law_rows(ds: xr.Dataset) -> list[dict[str, Any]]:
    params = json.loads(ds.attrs.get("law_parameters", "{}"))
    rows = []
    e_values = list(ds["e"].values) if "e" in ds.dims else [None]
    for law, p in params.items():
        v = ds["max_impact_velocity"]
        if "law" in v.dims:
            v = v.sel(law=law) if law in ds["law"].values else v.isel(law=0) * np.nan
        peak = v.max("contact", skipna=True).values if "contact" in v.dims else v.values
        observed = np.isfinite(peak).any()
        v0 = _median(np.asarray(peak, dtype=float)) if observed else NOMINAL_V0
        for e in e_values:
            row = {
                **p,
                "law": law,
                "mass": p.get("effective_mass"),
                "v0": v0,
                "observed": bool(observed),
            }
            if e is not None:
                row["e"] = float(e)
            row["label"] = law if e is None else f"{law} (e = {float(e):g})"
            rows.append(row)
    return rows


def _comparison_axes(ds: xr.Dataset) -> tuple[str | None, str | None]:
    """(y, x) of the comparison: law against the first numeric axis, when the study has them."""
    axes = [a for a in _axes(ds) if a != "record"]
    numeric = [a for a in axes if a != "law" and ds[a].dtype.kind in "if"]
    y = "law" if "law" in axes else (axes[0] if axes else None)
    x = next((a for a in numeric if a != y), None)
    return y, x


def _dissipated(law: Any, energy: float) -> str:
    """The contacts' dissipated energy [kJ]; for a law without damping (linear, Hertz) only the
    integration's error is left, shown as ≈0 with that figure, never as a negative dissipation."""
    if law is not None and not get_contact_law(str(law)).has_damping and math.isfinite(energy):
        return f"≈0 ({energy / 1e3:+.2g}: integration error)"
    return _g(energy / 1e3, 3)


def _summary_rows(ds: xr.Dataset, group: list[str]) -> Table:
    """Median and dispersion over records (and the other axes) per combination of ``group``."""
    buildings = [str(b) for b in ds["building"].values]
    header = [*group]
    for b in buildings:
        header += [f"amplif. {b}", f"β {b}"]
    header += ["peak force [MN]", "β force", "impacts", "dissipated [kJ]", "failed"]
    rows = []
    laws = [v for v in ds["law"].values if str(v) != _NO_CONTACT] if "law" in ds.dims else None
    sub_ds = ds.sel(law=laws) if laws is not None else ds
    coords = [sub_ds[g].values for g in group]
    for combo in (
        np.array(np.meshgrid(*coords, indexing="ij"), dtype=object).reshape(len(group), -1).T
        if group
        else [()]
    ):
        sel = dict(zip(group, combo, strict=True))
        s = sub_ds.sel(sel) if sel else sub_ds
        row = [_value_text(v) for v in combo]
        for b in buildings:
            amp = s["displacement_amplification"].sel(building=b).values.ravel()
            row += [_g(_median(amp), 3), _g(_dispersion(amp), 2)]
        force = s["peak_contact_force"].max("contact", skipna=True).values.ravel()
        impacts = s["impact_count"].sum("contact", min_count=1).values.ravel()
        row += [
            _g(_median(force) / 1e6, 3),
            _g(_dispersion(force), 2),
            _g(_median(impacts), 3),
            _dissipated(sel.get("law"), _median(s["contact_dissipated_energy"].values.ravel())),
            str(int((s["run_status"].values == "failed").sum())),
        ]
        rows.append(row)
    return Table(
        header,
        rows,
        "Median and dispersion β (lognormal, maximum likelihood: the root mean square of ln x about "
        "its mean) over the records; amplification = "
        "building's peak displacement with contact / without contact.",
    )


def _study_histories(ds: xr.Dataset, store: Path | None) -> Section | None:
    from pounding.studies import histories

    if not int(ds.attrs.get("keep_histories", 0)) or store is None or not store.is_dir():
        return None
    y, x = _comparison_axes(ds)
    sel: dict[str, Any] = {}
    for a in _axes(ds):
        if a == "law":
            continue
        values = ds[a].values
        sel[a] = values.min() if a == x else values[0]
    laws = [str(v) for v in ds["law"].values] if "law" in ds.dims else [None]
    runs = []
    for law in laws:
        s = {**sel, **({"law": law} if law is not None else {})}
        if str(ds["run_status"].sel(s).item()) != "ok":
            continue
        try:
            runs.append((law or "run", histories(ds, store, **s)))
        except (FileNotFoundError, ValueError):
            continue
    if not runs:
        return None
    where = ", ".join(f"{k} = {_value_text(v)}" for k, v in sel.items())
    sec = Section("Time histories")
    sec.blocks.append(f"Decimated time histories kept by the study, at {where}.")
    for b in ds["building"].values:
        sec.blocks.append(Plot(plots.study_histories(runs, str(b)), f"Roof displacement of {b}."))
    with_contact = [(t, r) for t, r in runs if t != _NO_CONTACT and r.sizes.get("contact", 0)]
    if with_contact:
        step = with_contact[0][1].attrs.get("history_dt")
        sec.blocks.append(
            Plot(
                plots.force_penetration(with_contact),
                f"Force–penetration loops per law, gap element with the largest force "
                f"(history step {_g(step)} s).",
            )
        )
    return sec


def _sweep_section(ds: xr.Dataset, axes: list[str]) -> Section:
    """The axes and their values, the parameters set per law and the failed combinations."""
    sweep = Section("Study")
    n_fail = int((ds["run_status"].values == "failed").sum())
    sweep.blocks.append(
        f"{int(ds.attrs.get('combinations', ds['run_status'].size))} combinations of "
        f"{len(axes)} axes, {int(ds.attrs.get('unique_runs', 0))} distinct runs including the "
        f"no-contact baselines; {n_fail} combination(s) failed."
    )
    sweep.blocks.append(
        Table(
            ["axis", "values", "count"],
            [
                [
                    a,
                    ", ".join(_value_text(v) for v in ds[a].values[:12])
                    + (" …" if ds.sizes[a] > 12 else ""),
                    str(ds.sizes[a]),
                ]
                for a in axes
            ],
        )
    )
    law_params = json.loads(ds.attrs.get("law_params", "{}"))
    if law_params:
        sweep.blocks.append(
            Table(
                ["law", "parameters set for it"],
                [
                    [k, ", ".join(f"{p} = {_value_text(v)}" for p, v in d.items())]
                    for k, d in law_params.items()
                ],
            )
        )
    if n_fail:
        bad = np.argwhere(ds["run_status"].values == "failed")[:_MAX_ROWS]
        rows = [
            [
                ", ".join(
                    f"{a}={_value_text(ds[a].values[i])}" for a, i in zip(axes, idx, strict=True)
                ),
                str(ds["run_error"].values[tuple(idx)]),
            ]
            for idx in bad
        ]
        sweep.blocks.append(
            Table(["combination", "error"], rows, f"Failed combinations (first {_MAX_ROWS}).")
        )
    return sweep


def _comparison_section(ds: xr.Dataset) -> Section:
    """Amplification plots, heat maps and the median/dispersion table of the contact laws."""
    comp = Section("Comparison of contact laws")
    y, x = _comparison_axes(ds)
    comp.blocks.append(
        "Amplification = peak with contact / peak of the same record without contact (law "
        "'none'), per building (its largest floor value). Medians over the records and any other "
        "axes; the bands span the 16th to 84th percentiles."
    )
    xs = x or y
    if xs is not None and ds[xs].dtype.kind in "if":
        for var in ("displacement_amplification", "drift_amplification"):
            comp.blocks.append(
                Plot(plots.amplification(ds, var, x=xs), ds[var].attrs["long_name"] + ".")
            )
    if y is not None and x is not None:
        for b in ds["building"].values:
            comp.blocks.append(
                Plot(
                    plots.heatmap(
                        ds,
                        "displacement_amplification",
                        x,
                        y,
                        building=str(b),
                        name="displacement amplification",
                    ),
                    f"Median displacement amplification of building {b}.",
                )
            )
        comp.blocks.append(
            Plot(
                plots.heatmap(
                    ds,
                    "peak_contact_force",
                    x,
                    y,
                    scale=1e-6,
                    units="MN",
                    fmt="{:.2g}",
                    name="peak contact force",
                ),
                "Median peak contact force (largest over the gap elements).",
            )
        )
        impacts = ds["impact_count"].sum("contact", min_count=1)
        impacts.attrs.update(long_name="number of impacts (all gap elements)", units="1")
        comp.blocks.append(
            Plot(
                plots.heatmap(
                    ds.assign(impacts=impacts), "impacts", x, y, fmt="{:.0f}", name="impacts"
                ),
                "Median number of impacts.",
            )
        )
    group = [g for g in (y, x) if g is not None]
    # the table keeps every other axis apart (e.g. elastic and yielding stories): records only
    group += [a for a in _axes(ds) if a not in (*group, "record")]
    comp.blocks.append(_summary_rows(ds, group))
    return comp


def _percent(fraction: float) -> str:
    """A fraction as a whole percentage ("–" where no run finished)."""
    return f"{100 * fraction:.0f} %" if np.isfinite(fraction) else "–"


def _trio(values: np.ndarray) -> str:
    """median / 84th / max to two decimals ("–" where no run finished)."""
    return " / ".join(f"{v:.2f}" if np.isfinite(v) else "–" for v in values)


def _executive_section(ds: xr.Dataset, law_rows: list[dict[str, Any]]) -> Section | None:
    """Record-to-record statistics of the amplifications per combination of the other axes and
    building (``ds.pounding.statistics()``), led by the largest median drift amplification."""
    if "record" not in ds.dims or "drift_amplification" not in ds:
        return None
    st = ds.pounding.statistics()
    sec = Section("Executive summary")
    axes = list(st["pounding_fraction"].dims) if "pounding_fraction" in st else []
    drift = st["drift_amplification"].sel(statistic="median")
    if "law" in drift.dims:
        drift = drift.where(drift["law"] != "none")
    if int(drift.notnull().sum()):
        at = {
            d: drift[d].values[i]
            for d, i in zip(
                drift.dims,
                np.unravel_index(int(np.argmax(drift.fillna(-1).values)), drift.shape),
                strict=True,
            )
        }
        where = ", ".join(f"{d} = {_value_text(v)}" for d, v in at.items() if d != "building")
        acc = float(st["acceleration_amplification"].sel(statistic="median", **at))
        sec.blocks.append(
            f"Largest median drift amplification over the {ds.sizes['record']} record(s): "
            f"{float(drift.sel(at)):.2f} for building {at['building']} ({where}); floor "
            f"acceleration there: median {acc:.2f}."
        )
    header = [
        *(
            f"{a} [{ds[a].attrs['units']}]" if ds[a].attrs.get("units", "1") != "1" else a
            for a in axes
        ),
        "building",
        "drift ampl. median / 84th / max",
        "floor acc. ampl. median / 84th / max",
        "runs that pound",
        "impact force [MN] median / 84th",
    ]
    rows = []
    for combo in itertools.product(*(st[a].values for a in axes)):
        sel = dict(zip(axes, combo, strict=True))
        if sel.get("law") == "none":
            continue
        for b in st["building"].values:
            at = {**sel, "building": b}
            force = st["peak_impact_force"].sel(sel).values[:2] / 1e6
            rows.append(
                [
                    *(_value_text(v) for v in combo),
                    str(b),
                    _trio(st["drift_amplification"].sel(at).values),
                    _trio(st["acceleration_amplification"].sel(at).values),
                    _percent(float(st["pounding_fraction"].sel(sel))),
                    " / ".join(_g(f, 3) for f in force),
                ]
            )
    cap = (
        "Amplification = peak with contact / without (the same record and scale, law 'none'); "
        "statistics over the records (84th: empirical percentile); a scale axis is never pooled."
    )
    if len(rows) > 2 * _MAX_ROWS:
        cap += f" First {2 * _MAX_ROWS} of {len(rows)} rows; all in ds.pounding.statistics()."
        rows = rows[: 2 * _MAX_ROWS]
    sec.blocks.append(Table(header, rows, cap))
    sec.blocks.extend(law_warnings(law_rows))
    return sec


def study_report(ds: xr.Dataset, store: Path | None = None) -> Report:
    """The report of a study (from :func:`pounding.studies.run_study`); ``store`` is its run store
    (default the one recorded in the Dataset) for the kept time histories."""
    if store is None and str(ds.attrs.get("store", "")):
        store = Path(ds.attrs["store"])
    axes = _axes(ds)
    law_rows = _study_law_rows(ds)
    executive = _executive_section(ds, law_rows)
    sections = [
        *([executive] if executive else []),
        _sweep_section(ds, axes),
        _model_section(ds, law_rows),
        _ground_motion_section(ds, study=True),
        _comparison_section(ds),
    ]
    hist = _study_histories(ds, store)
    if hist is not None:
        sections.append(hist)
    analysis = json.loads(ds.attrs.get("analysis", "{}"))
    meta = [
        ("axes", ", ".join(f"{a} ({ds.sizes[a]})" for a in axes)),
        ("method", str(analysis.get("method", ""))),
        ("pounding", str(ds.attrs.get("pounding_version", __version__))),
    ]
    return Report(str(ds.attrs.get("title") or "Pounding study"), "study", sections, meta)
