"""Sections every report kind shares: the buildings and contact laws of the model, and the ground
motions (intensity measures, time histories, response spectra)."""

from __future__ import annotations

import functools
import json
import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import xarray as xr

from pounding import plots
from pounding.contact.calibrate import effective_restitution
from pounding.contact.laws import get_contact_law
from pounding.errors import PoundingInputError
from pounding.ground_motion import INTENSITY_MEASURES, GroundMotion, intensity_measures
from pounding.report.document import NOMINAL_V0, Plot, Section, Table, _g
from pounding.simulate import E_MISMATCH  # the run's own check: one threshold
from pounding.spectra import response_spectra, response_spectrum
from pounding.units import G


@functools.lru_cache(maxsize=256)
def _impact_of(law: str, k: float, mass: float, v0: float, e: Any, n: Any, a: float,
               delta_m: Any, calibration: str, bumper: Any = None) -> Any:  # fmt: skip
    return effective_restitution(
        law, k=k, mass=mass, v0=v0, e=e, n=n, a=a, delta_m=delta_m, calibration=calibration,
        bumper=bumper,
    )  # fmt: skip


def _single_impact(r: dict[str, Any]) -> Any:
    """One free impact of the row's law (cached: the table and the warnings both need it)."""
    law = get_contact_law(r["law"])
    if law.is_filler:
        raise PoundingInputError("a filler touches both faces from rest: no free impact")
    bumper = (
        tuple(float(r[key]) for key in ("thickness", "k_rubber", "e_rubber"))
        + (float(r.get("crush", 1.0)),)
        if law.is_bumper
        else None
    )
    return _impact_of(
        law.name,
        float(r["k"]),
        float(r["mass"]),
        float(r["v0"]),
        r.get("e") if law.has_damping else None,
        r.get("n") if law.has_exponent else None,
        float(r.get("a", 0.1)),
        r.get("delta_m"),
        r.get("calibration", "nominal"),
        bumper,
    )


def law_warnings(rows: list[dict[str, Any]]) -> list[str]:
    """A warning per law whose single-impact restitution misses its nominal e by more than
    :data:`E_MISMATCH`, with what to set instead."""
    found = set()
    for r in rows:
        law = get_contact_law(r["law"])
        e_nom = r.get("e")
        if not (law.has_damping and e_nom) or law.is_bumper or law.is_filler:
            continue  # a bumper's or filler's rebound is its layer's, not one e's
        try:
            e_eff = _single_impact(r).e_effective
        except ValueError:
            continue
        if abs(e_eff - e_nom) > E_MISMATCH * e_nom:
            fix = (
                "a delta_m consistent with the observed penetration"
                if law.is_bilinear
                else 'calibration = "exact"'
            )
            found.add(
                f"Warning: {law.name} gives an effective e of {e_eff:.3f} for the nominal "
                f"{e_nom:g} ({100 * (e_eff / e_nom - 1):+.0f} %): set {fix} to get the e you mean."
            )
    return sorted(found)


def _contact_law_table(rows: list[dict[str, Any]]) -> Table:
    """Nominal and effective restitution of each (law, parameters), one impact at v0 on m̄."""
    out = []
    notes = set(law_warnings(rows))
    for r in rows:
        law = get_contact_law(r["law"])
        v0 = r["v0"]
        source = "observed" if r["observed"] else "nominal"
        e_nom = r.get("e")
        try:
            res = _single_impact(r)
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
