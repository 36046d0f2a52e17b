"""Reports of an analysis, a study or a separation check: one self-contained HTML file and a PDF with
the same content.

:func:`build_report` turns a result Dataset into a :class:`Report` (sections of paragraphs, tables
and figures); :func:`render_html` renders it with the package's Jinja2 template (autoescaped, figures
as inline SVG, no external resources), :func:`render_pdf` with matplotlib's ``PdfPages`` (text and
table pages, then one page per figure). :func:`write_report` does both into a directory.

Sections of an analysis: model (buildings, periods and mode shapes, contacts with nominal and
effective restitution), ground motion (time history, response spectrum, processing chain, intensity
measures), results (displacement histories with impacts, envelopes, contact forces, force–penetration
loops, impacts, energy ledger). A study adds the sweep (axes, failures) and the comparison of the
laws across the axes and records (amplification plots, heat maps, median/dispersion tables). A
separation check (:func:`pounding.separation.separation_analysis`) gives the buildings' modes, the
method, and per interface the required gap of every estimate, the probability of pounding against
the gap and the exact gap of every record.
"""

from __future__ import annotations

import dataclasses
import io
import json
import math
import textwrap
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import jinja2
import matplotlib
import numpy as np
import xarray as xr
from markupsafe import Markup
from matplotlib.backends.backend_pdf import PdfPages
from matplotlib.figure import Figure

from pounding import plots
from pounding._version import __version__
from pounding.contact.calibrate import effective_restitution
from pounding.contact.laws import get_contact_law
from pounding.errors import PoundingInputError
from pounding.ground_motion import INTENSITY_MEASURES, GroundMotion, intensity_measures
from pounding.results import result_kind
from pounding.spectra import response_spectra, response_spectrum
from pounding.units import G

#: Output formats of :func:`write_report`.
FORMATS = ("html", "pdf")
#: Approach speed [m/s] for the effective restitution of a law that saw no impact.
NOMINAL_V0 = 0.5
_NO_CONTACT = "none"
_MAX_ROWS = 40
_RC = {"svg.fonttype": "none", "pdf.fonttype": 42, "font.size": 9, "svg.hashsalt": "pounding"}


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
    title: str
    blocks: list[str | Table | Plot] = dataclasses.field(default_factory=list)

    @property
    def anchor(self) -> str:
        return "".join(c if c.isalnum() else "-" for c in self.title.lower())


@dataclasses.dataclass
class Report:
    title: str
    kind: str  # "analysis", "study" or "separation"
    sections: list[Section]
    meta: list[tuple[str, str]]


# --------------------------------------------------------------------------------------------------
# Formatting helpers
# --------------------------------------------------------------------------------------------------


def _g(value: Any, digits: int = 4) -> str:
    try:
        v = float(value)
    except (TypeError, ValueError):
        return str(value)
    if not math.isfinite(v):
        return "–"
    return f"{v:.{digits}g}"


def _dispersion(values: np.ndarray) -> float:
    """Lognormal dispersion β = standard deviation of ln x over the positive finite values."""
    v = values[np.isfinite(values) & (values > 0)]
    return float(np.std(np.log(v), ddof=1)) if v.size > 1 else float("nan")


def _median(values: np.ndarray) -> float:
    v = values[np.isfinite(values)]
    return float(np.median(v)) if v.size else float("nan")


def _contact_law_table(rows: list[dict[str, Any]]) -> Table:
    """Nominal and effective restitution of each (law, parameters), one impact at v0 on m̄."""
    out = []
    notes = set()
    for r in rows:
        law = get_contact_law(r["law"])
        v0 = r["v0"]
        source = "observed" if r["observed"] else "nominal"
        e_nom = r.get("e")
        try:
            res = effective_restitution(
                law,
                k=r["k"],
                mass=r["mass"],
                v0=v0,
                e=e_nom if law.has_damping else None,
                n=r.get("n") if law.has_exponent else None,
                a=r.get("a", 0.1),
                delta_m=r.get("delta_m"),
                calibration=r.get("calibration", "nominal"),
            )
            eff = f"{res.e_effective:.3f}"
            extra = [
                _g(res.peak_force / 1e6, 3),
                _g(res.max_penetration * 1e3, 3),
                _g(res.contact_duration * 1e3, 3),
            ]
        except ValueError as exc:
            eff, extra = f"({exc})", ["–", "–", "–"]
        if law.is_bilinear and r.get("delta_m") is None:
            notes.add("bilinear δ_m not recorded: taken as the undamped Hertz δ_max at v0")
        out.append(
            [
                r.get("label", law.name),
                _g(r["k"]),
                _g((r.get("n") or law.default_n) if law.has_exponent else 1.0, 3),
                _g(e_nom, 3) if law.has_damping else "1 (elastic)",
                eff,
                f"{v0:.3g}",
                source,
                *extra,
            ]
        )
    caption = (
        "Effective restitution, peak force, maximum penetration and duration of one free impact of "
        "the effective mass m̄ against a rigid wall at approach speed v0, clamping included; v0 is "
        "the largest observed approach speed (for a study the median over its runs), or a nominal "
        f"{NOMINAL_V0} m/s when the law saw no impact. " + " ".join(sorted(notes))
    )
    return Table(
        [
            "law",
            "k [N/m^n]",
            "n",
            "nominal e",
            "effective e",
            "v0 [m/s]",
            "v0 from",
            "peak force [MN]",
            "max penetration [mm]",
            "duration [ms]",
        ],
        out,
        caption,
    )


def _building_table(ds: xr.Dataset) -> Table:
    rows = []
    for b in ds["building"].values:
        n = int(np.isfinite(ds["floor_mass"].sel(building=b).values).sum())
        periods = ds["natural_period"].sel(building=b).values[:3]
        rows.append(
            [
                str(b),
                str(n),
                _g(np.nanmax(ds["floor_elevation"].sel(building=b).values), 4),
                _g(np.nansum(ds["floor_mass"].sel(building=b).values) / 1e3, 4),
                *(_g(p, 4) for p in periods),
                *(["–"] * (3 - len(periods))),
            ]
        )
    return Table(
        ["building", "floors", "height [m]", "mass [t]", "T1 [s]", "T2 [s]", "T3 [s]"], rows
    )


def _records_of(ds: xr.Dataset) -> list[tuple[str, GroundMotion]]:
    if "record_acceleration" in ds:
        out = []
        for i, name in enumerate(ds["record"].values):
            acc = ds["record_acceleration"].values[i]
            acc = acc[np.isfinite(acc)]
            dt = float(ds["record_dt"].values[i])
            if acc.size >= 2 and math.isfinite(dt):
                meta = {"processing": json.loads(str(ds["record_processing"].values[i]) or "[]")}
                out.append((str(name), GroundMotion(acc, dt, name=str(name), metadata=meta)))
        return out
    dt = float(ds.attrs.get("output_dt", float(ds["time"].values[1] - ds["time"].values[0])))
    meta = {"processing": json.loads(str(ds.attrs.get("record_processing", "[]")) or "[]")}
    name = str(ds.attrs.get("record", "ground motion"))
    return [(name, GroundMotion(ds["ground_acceleration"].values, dt, name=name, metadata=meta))]


def _ground_motion_section(ds: xr.Dataset, study: bool) -> Section:
    sec = Section("Ground motion" + ("s" if study else ""))
    recs = _records_of(ds)
    if not study:
        name, gm = recs[0]
        proc = "; ".join(gm.metadata.get("processing", [])) or "none"
        sec.blocks.append(
            f"Record: {name}. Record step {_g(ds.attrs.get('record_dt'))} s; shown on the output "
            f"grid (dt = {_g(gm.dt)} s), from which the spectrum below is computed. Processing "
            f"chain: {proc}."
        )
    rows = []
    for name, gm in recs:
        im = intensity_measures(gm)
        rows.append(
            [
                name,
                _g(gm.dt),
                _g(gm.duration),
                _g(im["pga"] / G, 3),
                _g(im["pgv"], 3),
                _g(im["arias_intensity"], 3),
                _g(im["d5_95"], 3),
                "; ".join(gm.metadata.get("processing", [])) or "none",
            ]
        )
    sec.blocks.append(
        Table(
            [
                "record",
                "dt [s]",
                "duration [s]",
                "PGA [g]",
                "PGV [m/s]",
                "Arias [m/s]",
                "D5-95 [s]",
                "processing",
            ],
            rows,
            "Intensity measures: "
            + ", ".join(
                f"{INTENSITY_MEASURES[k][2]}" for k in ("pga", "pgv", "arias_intensity", "d5_95")
            ),
        )
    )
    if "record_reference" in ds:
        refs = [
            [str(n), str(r)]
            for n, r in zip(ds["record"].values, ds["record_reference"].values, strict=True)
        ]
        sec.blocks.append(Table(["record", "reference"], refs))
    if recs:
        sec.blocks.append(
            Plot(
                plots.ground_motions([(n, gm.acceleration, gm.dt) for n, gm in recs]),
                "Ground acceleration.",
            )
        )
        gms = [gm for _, gm in recs]
        spec = response_spectra(gms) if len(gms) > 1 else response_spectrum(gms[0])
        spec.attrs["damping"] = "5 %"
        t1 = {
            str(b): float(ds["natural_period"].sel(building=b, mode=1))
            for b in ds["building"].values
        }
        sec.blocks.append(
            Plot(
                plots.response_spectra(spec, t1),
                "Elastic pseudo-spectral acceleration, 5 % damping; fundamental periods marked.",
            )
        )
    return sec


def _model_section(
    ds: xr.Dataset, law_rows: list[dict[str, Any]], extra: Sequence[Any] = ()
) -> Section:
    sec = Section("Model")
    names = ", ".join(str(b) for b in ds["building"].values)
    sec.blocks.append(
        f"Shear buildings {names} (listed left to right), floor masses lumped, story stiffnesses in "
        "series; periods with the contacts open."
    )
    sec.blocks.append(_building_table(ds))
    sec.blocks.append(Plot(plots.mode_shapes(ds), "Mode shapes (roof = 1) and natural periods."))
    sec.blocks.extend(extra)
    if law_rows:
        sec.blocks.append(_contact_law_table(law_rows))
    return sec


# --------------------------------------------------------------------------------------------------
# One analysis
# --------------------------------------------------------------------------------------------------


def _analysis_law_rows(ds: xr.Dataset) -> list[dict[str, Any]]:
    impacts = ds.pounding.impacts()
    groups: dict[tuple, dict[str, Any]] = {}
    for c in ds["contact"].values:
        sel = ds.sel(contact=c)
        law = str(sel["contact_law"].item())
        n = float(sel["contact_n"]) if "contact_n" in ds else float("nan")
        e = float(sel["contact_e"]) if "contact_e" in ds else float("nan")
        key = (law, float(sel["contact_k"]), n, e, float(sel["contact_effective_mass"]))
        v0 = impacts.loc[impacts["contact"] == c, "v0"].to_numpy()
        row = groups.setdefault(
            key,
            {
                "law": law,
                "k": key[1],
                "n": None if math.isnan(n) else n,
                "e": None if math.isnan(e) else e,
                "mass": key[4],
                "v": [],
            },
        )
        row["v"].extend(v for v in v0 if math.isfinite(v) and v > 0)
    rows = []
    for row in groups.values():
        observed = bool(row["v"])
        rows.append(
            {
                **row,
                "v0": max(row["v"]) if observed else NOMINAL_V0,
                "observed": observed,
                "label": f"{row['law']} (m̄ = {row['mass']:.4g} kg)",
            }
        )
    return rows


def _contacts_table(ds: xr.Dataset) -> Table:
    imp = ds.pounding.impacts()
    rows = []
    for c in ds["contact"].values:
        sel = ds.sel(contact=c)
        impulse = float(imp.loc[imp["contact"] == c, "impulse"].sum())
        rows.append(
            [
                str(int(c)),
                f"{sel['contact_left'].item()}:{int(sel['contact_left_floor'])}",
                f"{sel['contact_right'].item()}:{int(sel['contact_right_floor'])}",
                str(sel["contact_law"].item()),
                _g(float(sel["contact_gap"]) * 1e3, 4),
                str(int(sel["impact_count"])),
                _g(float(sel["peak_contact_force"]) / 1e6, 4),
                _g(float(sel["peak_penetration"]) * 1e3, 4),
                _g(impulse / 1e3, 4),
            ]
        )
    return Table(
        [
            "contact",
            "left:floor",
            "right:floor",
            "law",
            "gap [mm]",
            "impacts",
            "peak force [MN]",
            "peak penetration [mm]",
            "impulse [kN s]",
        ],
        rows,
        "Peaks are tracked at every integration step.",
    )


def _analysis_report(ds: xr.Dataset) -> Report:
    contacts = _contacts_table(ds) if ds.sizes.get("contact", 0) else None
    model = _model_section(
        ds,
        _analysis_law_rows(ds) if contacts else [],
        [Table(contacts.header[:5], [r[:5] for r in contacts.rows])] if contacts else [],
    )
    res = Section("Results")
    s = ds.pounding.summary()
    res.blocks.append(
        Table(
            [
                "building",
                "T1 [s]",
                "peak displacement [m]",
                "peak drift ratio [-]",
                "peak absolute acceleration [m/s²]",
            ],
            [
                [
                    name,
                    _g(b["T1"]),
                    _g(b["peak_displacement"]),
                    _g(b["peak_drift_ratio"]),
                    _g(b["peak_absolute_acceleration"]),
                ]
                for name, b in s["buildings"].items()
            ],
        )
    )
    res.blocks.append(
        Plot(
            plots.displacement_histories(ds),
            "Floor displacements relative to the ground; ▼ marks the start of each impact on that floor.",
        )
    )
    res.blocks.append(
        Plot(
            plots.envelopes(ds),
            "Peak displacement and peak inter-story drift ratio over the height.",
        )
    )
    if contacts:
        res.blocks.append(contacts)
        res.blocks.append(
            Plot(
                plots.contact_forces(ds), "Contact force histories of the gap elements that closed."
            )
        )
        res.blocks.append(
            Plot(
                plots.force_penetration([(str(ds["contact_law"].values[0]), ds)]),
                "Force–penetration loop of the gap element with the largest force (output grid).",
            )
        )
        imp = ds.pounding.impacts()
        rows = [
            [
                str(int(r.contact)),
                _g(r.start, 5),
                _g(r.end, 5),
                _g(r.v0, 4),
                _g(r.peak_force / 1e6, 4),
                _g(r.max_penetration * 1e3, 4),
                _g(r.impulse / 1e3, 4),
                _g(r.restitution, 3),
            ]
            for r in imp.head(_MAX_ROWS).itertuples()
        ]
        cap = (
            f"First {_MAX_ROWS} of {len(imp)} impacts."
            if len(imp) > _MAX_ROWS
            else f"{len(imp)} impacts."
        )
        res.blocks.append(
            Table(
                [
                    "contact",
                    "start [s]",
                    "end [s]",
                    "v0 [m/s]",
                    "peak force [MN]",
                    "max penetration [mm]",
                    "impulse [kN s]",
                    "rebound/approach",
                ],
                rows,
                cap,
            )
        )
    res.blocks.append(
        Plot(
            plots.energy(ds),
            f"Energy ledger; balance error {100 * s['energy_balance_error']:.3g} % of the input energy.",
        )
    )
    sections = [model, _ground_motion_section(ds, study=False), res]
    isolated = plots.isolated_buildings(ds)
    if isolated:
        iso = Section("Base isolation")
        peak = ds["peak_base_displacement"]
        iso.blocks.append(
            Table(
                ["building", "peak base displacement [m]"],
                [[b, _g(float(peak.sel(building=b)))] for b in isolated],
                f"Energy dissipated by bearing friction: {100 * plots.friction_share(ds):.3g} % of the "
                "input energy at the end of the record.",
            )
        )
        iso.blocks.append(
            Plot(
                plots.base_displacements(ds),
                "Base slab (bearing) displacement relative to the ground.",
            )
        )
        iso.blocks.append(
            Plot(
                plots.bearing_hysteresis(ds),
                "Bearing hysteresis loops: friction force (and friction plus the pendulum's restoring "
                "force) against the base displacement.",
            )
        )
        sections.append(iso)
    meta = [
        ("record", str(ds.attrs.get("record", ""))),
        ("method", str(ds.attrs.get("method", ""))),
        ("dt", f"{_g(ds.attrs.get('dt'))} s"),
        ("output dt", f"{_g(ds.attrs.get('output_dt'))} s"),
        ("pounding", str(ds.attrs.get("pounding_version", __version__))),
    ]
    return Report(str(ds.attrs.get("title") or "Pounding analysis"), "analysis", sections, meta)


# --------------------------------------------------------------------------------------------------
# Separation checks
# --------------------------------------------------------------------------------------------------


def _separation_report(ds: xr.Dataset) -> Report:
    from pounding.separation import separation_summary

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
    sections = [bld, method]
    for f in s["interfaces"]:
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
            f"Lognormal fit of the exact gaps: median {_g(ln['median'])} m, β {_g(ln['beta'], 3)}, "
            f"{_g(100 * ln['fraction'], 3)} % of the records approach at all; gap with "
            f"P(pounding) = {_g(s['target_probability'], 3)}: {_g(ln['gap_for_target'])} m."
        )
        sections.append(sec)
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


# --------------------------------------------------------------------------------------------------
# Studies
# --------------------------------------------------------------------------------------------------


def _axes(ds: xr.Dataset) -> list[str]:
    return list(json.loads(ds.attrs.get("axes", "[]")))


def _value_text(v: Any) -> str:
    return f"{v:g}" if isinstance(v, (float, np.floating)) else str(v)


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
            _g(_median(s["contact_dissipated_energy"].values.ravel()) / 1e3, 3),
            str(int((s["run_status"].values == "failed").sum())),
        ]
        rows.append(row)
    return Table(
        header,
        rows,
        "Median and lognormal dispersion β (standard deviation of ln x) over the records and any "
        "other axes; amplification = building's peak displacement with contact / without contact.",
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


def _study_report(ds: xr.Dataset, store: Path | None) -> Report:
    axes = _axes(ds)
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
    model = _model_section(ds, _study_law_rows(ds))
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
    comp.blocks.append(_summary_rows(ds, group))
    sections = [sweep, model, _ground_motion_section(ds, study=True), comp]
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


def build_report(ds: xr.Dataset, *, store: str | Path | None = None) -> Report:
    """The report of an analysis (from :func:`pounding.simulate`), a study, or a separation check
    (from :func:`pounding.separation.separation_analysis`).

    ``store`` is the study's run store (default the one recorded in the Dataset) for the kept
    time histories.
    """
    try:
        kind = result_kind(ds)
    except ValueError as exc:
        raise PoundingInputError(f"report: {exc}") from None
    with matplotlib.rc_context(_RC):
        if kind == "study":
            path = Path(store) if store is not None else Path(ds.attrs.get("store", ""))
            return _study_report(ds, path if str(path) else None)
        if kind == "separation":
            return _separation_report(ds)
        return _analysis_report(ds)


# --------------------------------------------------------------------------------------------------
# Rendering
# --------------------------------------------------------------------------------------------------


def _svg(fig: Figure) -> Markup:
    buf = io.StringIO()
    with matplotlib.rc_context(_RC):
        fig.savefig(buf, format="svg", metadata={"Date": None})
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
            text,
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

        emit(table.header, weight="bold", gap=0.05)
        for row in table.rows:
            emit(row)
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
            w.line(f"{n}. {sec.title}", 13, weight="bold", gap=0.15)
            figures: list[Plot] = []
            for b in sec.blocks:
                if isinstance(b, str):
                    w.paragraph(b)
                elif isinstance(b, Table):
                    w.table(b)
                else:
                    figures.append(b)
                    for ln in textwrap.wrap(f"Figure {n}.{len(figures)}: {b.caption}", 115):
                        w.line(ln, 8.5)
            if figures:  # figures take pages of their own; text-only sections share pages
                w.flush()
            for k, p in enumerate(figures, 1):
                fig = p.figure
                fig.suptitle(f"{n}. {sec.title} - figure {n}.{k}", fontsize=9, x=0.02, ha="left")
                pdf.savefig(fig)
                fig.suptitle("")
        w.flush()
    return path


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
