"""The report of one analysis (``pounding run``): the model, the ground motion, the results
(displacement histories with impacts, envelopes, contact forces, force–penetration loops, impacts,
energy ledger) and, for isolated buildings, the base isolation."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from pounding import plots
from pounding._version import __version__
from pounding.report.document import _MAX_ROWS, NOMINAL_V0, Plot, Report, Section, Table, _g
from pounding.report.sections import _ground_motion_section, _model_section, law_warnings


def _analysis_law_rows(ds: xr.Dataset) -> list[dict[str, Any]]:
    impacts = ds.pounding.impacts()
    groups: dict[tuple, dict[str, Any]] = {}
    for c in ds["contact"].values:
        sel = ds.sel(contact=c)
        law = str(sel["contact_law"].item())
        n = float(sel["contact_n"]) if "contact_n" in ds else float("nan")
        e = float(sel["contact_e"]) if "contact_e" in ds else float("nan")
        # results written before these were recorded take the defaults
        a = float(sel["contact_a"]) if "contact_a" in ds else 0.1
        delta_m = float(sel["contact_delta_m"]) if "contact_delta_m" in ds else math.nan
        calibration = (
            str(sel["contact_calibration"].item()) if "contact_calibration" in ds else "nominal"
        )
        # NaN != NaN: a key holding one never matched, so equal contacts got a row each
        key = tuple(
            None if isinstance(x, float) and math.isnan(x) else x
            for x in (law, float(sel["contact_k"]), n, e, float(sel["contact_effective_mass"]),
                      a, delta_m, calibration)
        )  # fmt: skip
        v0 = impacts.loc[impacts["contact"] == c, "v0"].to_numpy()
        row = groups.setdefault(
            key,
            {
                "law": law,
                "k": key[1],
                "n": None if math.isnan(n) else n,
                "e": None if math.isnan(e) else e,
                "mass": key[4],
                "a": a,
                "delta_m": None if math.isnan(delta_m) else delta_m,
                "calibration": calibration,
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
                plots.contact_end(ds, c, "left"),
                plots.contact_end(ds, c, "right"),
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


def _impacts_table(ds: xr.Dataset) -> Table:
    """The first impacts: start, end, approach speed, peaks, impulse and rebound/approach."""
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
            _g(r.rebound_ratio, 3),
            _g(r.nominal_e, 3) if r.nominal_e == r.nominal_e else "1 (elastic)",
        ]
        for r in imp.head(_MAX_ROWS).itertuples()
    ]
    cap = (
        f"First {_MAX_ROWS} of {len(imp)} impacts."
        if len(imp) > _MAX_ROWS
        else f"{len(imp)} impacts."
    )
    cap += (
        " Rebound/approach: the ratio of the separation to the approach speed in the structure "
        "(other floors and modes push and pull: it may exceed 1); law's e: the restitution the law "
        "is set to (its single-impact value is in the Model section)."
    )
    return Table(
        [
            "contact",
            "start [s]",
            "end [s]",
            "v0 [m/s]",
            "peak force [MN]",
            "max penetration [mm]",
            "impulse [kN s]",
            "rebound/approach",
            "law's e",
        ],
        rows,
        cap,
    )


def _results_section(ds: xr.Dataset, contacts: Table | None) -> Section:
    """Peaks per building, histories, envelopes, contacts and impacts, energy ledger."""
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
                "peak base shear [kN]",
            ],
            [
                [
                    name,
                    _g(b["T1"]),
                    _g(b["peak_displacement"]),
                    _g(b["peak_drift_ratio"]),
                    _g(b["peak_absolute_acceleration"]),
                    _g(b["peak_base_shear"] / 1e3),
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
    res.blocks.append(
        Plot(
            plots.shear_envelopes(ds),
            "Peak story shear over the height"
            + (
                ", with contact (solid) and without (dashed)"
                if "no_contact_peak_story_shear" in ds
                else ""
            )
            + "; from the equilibrium of the floors above (output steps).",
        )
    )
    if "floor_spectrum" in ds:
        res.blocks.append(
            Plot(
                plots.floor_spectra(ds),
                "Floor response spectra: 5 % damped pseudo-spectral acceleration of the absolute "
                "floor acceleration, the demand on non-structural components.",
            )
        )
    if contacts:
        res.blocks.append(contacts)
        res.blocks.append(
            Plot(
                plots.contact_forces(ds),
                "Contact force histories of the gap elements that closed (at most six, the largest), "
                "zoomed on the impacts; ▼ the exact peak of each impact, tracked at every step.",
            )
        )
        res.blocks.append(
            Plot(
                plots.force_penetration([(str(ds["contact_law"].values[0]), ds)]),
                "Force–penetration loop of the impact with the largest force, at the integration "
                "steps through it (at most 48 points kept, closure to separation).",
            )
        )
        res.blocks.append(_impacts_table(ds))
    res.blocks.append(
        Plot(
            plots.energy(ds),
            f"Energy ledger; balance error {100 * s['energy_balance_error']:.3g} % of the input energy.",
        )
    )
    return res


def _fmt(value: float, digits: int) -> str:
    """``digits`` significant digits, or whole units when ``digits`` is 0 (forces in kN)."""
    return f"{value:.0f}" if digits == 0 and math.isfinite(value) else _g(value, digits or 4)


def _executive_section(ds: xr.Dataset, law_rows: list[dict[str, Any]]) -> Section:
    """The numbers an engineer decides on first: per building the peak drift ratio, absolute floor
    acceleration and base shear, with contact and (when the run has its no-contact baseline)
    without, their ratio and the story shear the impacts add; the largest impact force; then the
    run's warnings (drift beyond the limit, a law whose effective e misses its nominal e)."""
    sec = Section("Executive summary")
    s = ds.pounding.summary()
    baseline = all("no_contact" in b for b in s["buildings"].values())
    if baseline:
        header = ["building", "quantity", "with contact", "without", "ratio"]
        rows = []
        for name, b in s["buildings"].items():
            nc = b["no_contact"]
            for label, key, scale, digits in (
                ("peak drift ratio", "peak_drift_ratio", 1.0, 3),
                ("peak abs. acceleration [m/s²]", "peak_absolute_acceleration", 1.0, 3),
                ("peak displacement [m]", "peak_displacement", 1.0, 3),
                ("peak base shear [kN]", "peak_base_shear", 1e-3, 0),
            ):
                w, wo = b[key] * scale, nc[key] * scale
                rows.append(
                    [name, label, _fmt(w, digits), _fmt(wo, digits), _g(w / wo if wo else None, 3)]
                )
            added = _fmt(b["max_impact_story_shear"] / 1e3, 0)
            rows.append([name, "story shear added [kN]", added, "", ""])
        note = (
            "With contact: this analysis; without: the same analysis with no contacts. Story shear "
            "added: the largest over the stories of the peak story shear with contact minus without."
        )
    else:
        header = [
            "building",
            "peak drift ratio",
            "peak abs. acceleration [m/s²]",
            "peak base shear [kN]",
        ]
        rows = [
            [
                name,
                _g(b["peak_drift_ratio"], 3),
                _g(b["peak_absolute_acceleration"], 3),
                _g(b["peak_base_shear"] / 1e3, 4),
            ]
            for name, b in s["buildings"].items()
        ]
        note = "No no-contact baseline in this result (run without --no-baseline to compare)."
    contacts = s["contacts"]
    if contacts:
        worst = max(contacts, key=lambda c: c["peak_force"])
        n_imp = sum(c["impacts"] for c in contacts)
        note += (
            f" {n_imp} impacts; largest impact force {_g(worst['peak_force'] / 1e6, 4)} MN at "
            f"{worst['left']}–{worst['right']} ({worst['law']}, gap {_g(worst['gap'] * 1e3, 4)} mm)."
        )
    sec.blocks.append(Table(header, rows, note))
    # results made before the run checked its laws' restitution: the report's own check
    checked = any("rebounds at e =" in w for w in s["warnings"])
    for warning in [*s["warnings"], *([] if checked else law_warnings(law_rows))]:
        sec.blocks.append(warning if warning.startswith("Warning") else f"Warning: {warning}")
    return sec


def _isolation_section(ds: xr.Dataset) -> Section | None:
    """Peak base displacements, base slab histories and bearing loops of the isolated buildings."""
    isolated = plots.isolated_buildings(ds)
    if not isolated:
        return None
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
    return iso


def _columns_section(ds: xr.Dataset) -> Section | None:
    """Peak shear of every column struck between floors, against its capacity."""
    if "peak_column_shear" not in ds:
        return None
    sec = Section("Floor-to-column impacts")
    names = ds["building"].values
    rows = []
    for q in range(ds.sizes["column"]):
        sel = ds.isel(column=q)
        capacity = float(sel["column_capacity"])
        shear = np.abs(sel["column_shear"]).max("time").values
        rows.append(
            [
                str(names[int(sel["column_building"])]),
                str(int(sel["column_story"])),
                _g(float(sel["column_elevation"]), 4),
                _g(float(sel["column_xi"]), 3),
                _g(shear[0] / 1e3),
                _g(shear[1] / 1e3),
                _g(float(sel["peak_column_drift_shear"]) / 1e3),
                _g(capacity / 1e3) if math.isfinite(capacity) else "–",
                "EXCEEDED"
                if int(sel["column_capacity_exceeded"])
                else "ok"
                if math.isfinite(capacity)
                else "–",
            ]
        )
    header = ["building", "story", "impact at [m]", "ξ = a/h", "peak shear below [kN]",
              "peak shear above [kN]", "story share k_c δ [kN]", "capacity [kN]",
              "check"]  # fmt: skip
    sec.blocks.append(
        Table(
            header,
            rows,
            "A slab strikes the neighbour's column between its floors (Karayannis & Favvata 2005): "
            "the struck column line is split at the impact point into two segments (k_c/ξ below, "
            "k_c/η above); the shear in the short segment is the demand that decides a short-column "
            "shear failure. The story share is what the column would carry were it not struck "
            "between floors (k_c times the story drift).",
        )
    )
    sec.blocks.append(
        Plot(
            plots.column_shears(ds),
            "Shear of the struck columns' segments below and above the impact point.",
        )
    )
    return sec


def _foundation_section(ds: xr.Dataset) -> Section | None:
    """Soil springs, flexible-base periods and the foundation's peak sway and rocking of every
    building on soil, and how its roof displacement splits between them."""
    names = plots.soil_buildings(ds)
    if not names:
        return None
    sec = Section("Soil flexibility")
    rows = []
    for name in names:
        sel = ds.sel(building=name)
        height = float(np.nanmax(sel["floor_elevation"].values))
        rocking = float(sel["peak_foundation_rocking"])
        rows.append(
            [
                name,
                _g(float(sel["natural_period"].values[0]), 4),
                _g(float(sel["flexible_base_period"]), 4),
                _g(float(sel["soil_sway_stiffness"]) / 1e6),
                _g(float(sel["soil_rocking_stiffness"]) / 1e9),
                _g(float(sel["peak_foundation_sway"]) * 1e3),
                _g(rocking * 1e3),
                _g(rocking * height * 1e3),
            ]
        )
    header = ["building", "T1 fixed base [s]", "T̃1 on soil [s]", "K_x [MN/m]", "K_θ [GN m/rad]",
              "peak sway [mm]", "peak rocking [mrad]", "rocking at roof [mm]"]  # fmt: skip
    sec.blocks.append(
        Table(
            header,
            rows,
            "Rigid surface footing on a homogeneous half-space: static springs (Gazetas 1991) and "
            "cone dashpots (Wolf 1994), frequency independent; the drifts in this report are the "
            "stories' own deformation, without the rigid rocking.",
        )
    )
    sec.blocks.append(
        Plot(
            plots.foundation_motion(ds),
            "Roof displacement of each building on soil and its parts: foundation sway, rigid "
            "rocking (H θ) and the stories' deformation.",
        )
    )
    return sec


def _stories_section(ds: xr.Dataset) -> Section | None:
    """Ductility, residual drift, hysteretic energy and damage of every yielding story, and the
    loops of the most ductile ones."""
    names = plots.yielding_buildings(ds)
    if not names:
        return None
    sec = Section("Yielding stories")
    rows = []
    damage = "park_ang_damage" in ds
    for name in names:
        sel = ds.sel(building=name)
        for i, model in enumerate(sel["story_model"].values):
            if str(model) in ("", "elastic"):
                continue
            row = [
                name,
                str(int(sel["story"].values[i])),
                str(model),
                _g(float(sel["yield_force"].values[i]) / 1e3),
                _g(float(sel["yield_drift"].values[i]) * 1e3),
                _fmt(float(sel["story_ductility"].values[i]), 3),
                _fmt(float(sel["residual_drift_ratio"].values[i]), 3),
                _g(float(sel["hysteretic_energy"].values[i]) / 1e3),
            ]
            if damage:
                row.append(_fmt(float(sel["park_ang_damage"].values[i]), 3))
            rows.append(row)
    header = ["building", "story", "model", "F_y [kN]", "δ_y [mm]", "peak ductility",
              "residual drift ratio", "hysteretic energy [kJ]"]  # fmt: skip
    if damage:
        header.append("Park-Ang damage")
    total = float(ds["energy"].sel(term="hysteretic").dropna("time")[-1])
    inp = float(ds["energy"].sel(term="input").dropna("time")[-1])
    share = f"{100 * total / inp:.3g} %" if inp > 0 else "n/a"
    sec.blocks.append(
        Table(
            header,
            rows,
            "Peak ductility = peak drift / yield drift; residual drift at the end of the analysis "
            f"(extend the duration for a free-vibration tail). The stories dissipated {share} of "
            "the input energy.",
        )
    )
    sec.blocks.append(
        Plot(
            plots.story_hysteresis(ds),
            "Story hysteresis loops: spring (restoring) force, without damping, against drift, for "
            "the most ductile stories.",
        )
    )
    return sec


def analysis_report(ds: xr.Dataset, store: Path | None = None) -> Report:
    """The report of an analysis (from :func:`pounding.simulate`); ``store`` is not used."""
    contacts = _contacts_table(ds) if ds.sizes.get("contact", 0) else None
    law_rows = _analysis_law_rows(ds) if contacts else []
    model = _model_section(
        ds,
        law_rows,
        [Table(contacts.header[:5], [r[:5] for r in contacts.rows])] if contacts else [],
    )
    sections = [
        _executive_section(ds, law_rows),
        model,
        _ground_motion_section(ds, study=False),
        _results_section(ds, contacts),
    ]
    extras = (_stories_section(ds), _isolation_section(ds), _foundation_section(ds),
              _columns_section(ds))  # fmt: skip
    for extra in extras:
        if extra is not None:
            sections.append(extra)
    meta = [
        ("record", str(ds.attrs.get("record", ""))),
        ("method", str(ds.attrs.get("method", ""))),
        ("dt", f"{_g(ds.attrs.get('dt'))} s"),
        ("output dt", f"{_g(ds.attrs.get('output_dt'))} s"),
        ("pounding", str(ds.attrs.get("pounding_version", __version__))),
    ]
    return Report(str(ds.attrs.get("title") or "Pounding analysis"), "analysis", sections, meta)
