"""Figures of pounding results and studies, labelled from the CF attributes of the Dataset.

Every function takes a Dataset (from :func:`pounding.simulate`, :func:`pounding.studies.run_study` or,
for :func:`required_gaps` and :func:`pounding_probability`, :func:`pounding.separation.separation_analysis`)
and returns a :class:`matplotlib.figure.Figure` without touching pyplot's global state, so figures can
be made in any thread or process and saved in any format (the reports use SVG and PDF). Axis labels
are ``long_name [units]`` of the plotted variable (:func:`label`), as xarray's own plots do.
"""

from __future__ import annotations

import json
import math
import warnings
from collections.abc import Sequence

import numpy as np
import xarray as xr
from matplotlib import cm
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from pounding.units import G

#: Width of a report figure [in].
WIDTH = 7.5
_NO_CONTACT = "none"


def label(da: xr.DataArray, name: str | None = None, *, units: str | None = None) -> str:
    """``long_name [units]`` from a variable's CF attributes (``[-]`` for dimensionless)."""
    text = name or da.attrs.get("long_name") or str(da.name or "")
    unit = units if units is not None else da.attrs.get("units")
    if unit in (None, ""):
        return text
    return f"{text} [{'-' if unit == '1' else unit}]"


def plain_text(text: object) -> str:
    """``text`` with every ``$`` escaped, so that matplotlib draws it as written and never parses
    it as mathtext (a building called ``$x_1$``, ``A$b_c^d`` or ``$\\undefined$``)."""
    return str(text).replace("$", r"\$")


def _figure(height: float, ncols: int = 1, nrows: int = 1, **kw) -> tuple[Figure, np.ndarray]:
    fig = Figure(figsize=(WIDTH, height), layout="constrained")
    axes = fig.subplots(nrows, ncols, squeeze=False, **kw)
    return fig, axes


def _median(da: xr.DataArray, keep: Sequence[str]) -> xr.DataArray:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return da.median([d for d in da.dims if d not in keep], skipna=True, keep_attrs=True)


def _buildings(ds: xr.Dataset) -> list[str]:
    return [str(b) for b in ds["building"].values]


def _n_floors(ds: xr.Dataset, building: str) -> int:
    return int(np.isfinite(ds["floor_elevation"].sel(building=building).values).sum())


# --------------------------------------------------------------------------------------------------
# Model and ground motion
# --------------------------------------------------------------------------------------------------


def mode_shapes(ds: xr.Dataset, n_modes: int = 3) -> Figure:
    """Mode shapes (roof = 1) over the floor elevation, one panel per building, periods in the legend."""
    names = _buildings(ds)
    fig, axes = _figure(3.2, ncols=len(names), sharey=True)
    for ax, name in zip(axes[0], names, strict=True):
        n = _n_floors(ds, name)
        z = np.concatenate(([0.0], ds["floor_elevation"].sel(building=name).values[:n]))
        for m in range(1, min(n_modes, n) + 1):
            phi = ds["mode_shape"].sel(building=name, mode=m).values[:n]
            period = float(ds["natural_period"].sel(building=name, mode=m))
            ax.plot(
                np.concatenate(([0.0], phi)),
                z,
                marker="o",
                ms=3,
                label=f"mode {m}: T = {period:.3g} s",
            )
        ax.axvline(0.0, color="0.6", lw=0.8)
        ax.set_title(f"building {plain_text(name)}")
        ax.set_xlabel(label(ds["mode_shape"]))
        ax.legend(fontsize="small")
    axes[0, 0].set_ylabel(label(ds["floor_elevation"]))
    return fig


def ground_motions(
    records: Sequence[tuple[str, np.ndarray, float]], *, max_records: int = 6
) -> Figure:
    """Ground acceleration [g] of records given as (name, acceleration [m/s²], dt [s])."""
    shown = list(records)[:max_records]
    fig, axes = _figure(1.2 + 1.3 * len(shown), nrows=len(shown), sharex=True)
    for ax, (name, acc, dt) in zip(axes[:, 0], shown, strict=True):
        acc = np.asarray(acc)
        acc = acc[np.isfinite(acc)]
        ax.plot(dt * np.arange(acc.size), acc / G, lw=0.7)
        ax.set_title(plain_text(name), fontsize="small", loc="left")
        ax.set_ylabel("a_g [g]")
    axes[-1, 0].set_xlabel("time [s]")
    if len(records) > len(shown):
        fig.suptitle(f"first {len(shown)} of {len(records)} records", fontsize="small")
    return fig


def response_spectra(spectra: xr.Dataset, periods: dict[str, float] | None = None) -> Figure:
    """Pseudo-spectral acceleration [g] of one or more records, with the buildings' periods marked."""
    fig, axes = _figure(3.4)
    ax = axes[0, 0]
    psa = spectra["PSa"]
    if "record" in psa.dims:
        for name in psa["record"].values:
            ax.plot(spectra["period"], psa.sel(record=name) / G, lw=0.9, label=plain_text(name))
        if psa.sizes["record"] > 1:
            ax.plot(spectra["period"], psa.median("record") / G, color="k", lw=2, label="median")
    else:
        ax.plot(spectra["period"], psa / G, lw=1.0)
    for name, t in (periods or {}).items():
        ax.axvline(t, color="0.4", ls=":", lw=1)
        ax.annotate(
            f"T1 {plain_text(name)}",
            (t, 1),
            xycoords=("data", "axes fraction"),
            rotation=90,
            va="top",
            ha="right",
            fontsize="small",
        )
    ax.set_xscale("log")
    ax.set_xlabel(label(spectra["period"]))
    damping = spectra.attrs.get("damping", None)
    ax.set_ylabel(label(psa, "pseudo-spectral acceleration", units="g"))
    if damping is not None:
        ax.set_title(f"damping {damping}", fontsize="small")
    if "record" in psa.dims and psa.sizes["record"] <= 8:
        ax.legend(fontsize="x-small")
    ax.grid(True, which="both", alpha=0.3)
    return fig


# --------------------------------------------------------------------------------------------------
# One analysis
# --------------------------------------------------------------------------------------------------


def contact_end(ds: xr.Dataset, c: int, side: str) -> str:
    """ "B:2" for floor 2 of B at one end of contact c, "B:c2" for the column of B's story 2 struck
    between floors."""
    from pounding.system import end_label  # only for this label: plots otherwise reads Datasets

    sel = ds.sel(contact=c)
    column = f"contact_{side}_column"
    struck = int(sel[column]) if column in ds.coords else -1
    return end_label(str(sel[f"contact_{side}"].item()), int(sel[f"contact_{side}_floor"]), struck)


def _contact_name(ds: xr.Dataset, c: int) -> str:
    sel = ds.sel(contact=c)
    text = f"{contact_end(ds, c, 'left')}–{contact_end(ds, c, 'right')}"
    if "contact_law" in ds.coords:
        text += f" ({sel['contact_law'].item()})"
    return plain_text(text)


def isolated_buildings(ds: xr.Dataset) -> list[str]:
    """Buildings on isolation bearings whose base response is in the Dataset (not all NaN)."""
    if "base_displacement" not in ds or "friction_force" not in ds:
        return []
    return [
        name
        for name in _buildings(ds)
        if np.isfinite(ds["base_displacement"].sel(building=name).values).any()
    ]


def soil_buildings(ds: xr.Dataset) -> list[str]:
    """Buildings on a flexible base (soil springs) whose foundation response is in the Dataset."""
    if "foundation_sway" not in ds:
        return []
    return [
        name
        for name in _buildings(ds)
        if np.isfinite(ds["foundation_sway"].sel(building=name).values).any()
    ]


def _floor_history(ds: xr.Dataset, building: str, floor: int) -> xr.DataArray:
    """Displacement history of a floor; floor 0 is the base slab of an isolated building."""
    if floor == 0:
        return ds["base_displacement"].sel(building=building)
    return ds["displacement"].sel(building=building, floor=floor)


def displacement_histories(ds: xr.Dataset) -> Figure:
    """Displacement of each building's roof and contact floors over time, impacts marked.

    A contact at floor 0 (the base slab of an isolated building) draws the slab's displacement.
    """
    names = _buildings(ds)
    fig, axes = _figure(1.4 + 1.9 * len(names), nrows=len(names), sharex=True)
    u = ds["displacement"]
    starts = ds["impact_start"].values if "impact_start" in ds else np.array([])
    which = ds["impact_contact"].values if "impact_contact" in ds else np.array([], dtype=int)
    for ax, name in zip(axes[:, 0], names, strict=True):
        n = _n_floors(ds, name)
        floors = _struck_floors(ds, name, n)
        for k, f in enumerate(sorted(floors, reverse=True)):
            uf = _floor_history(ds, name, f)
            text = "base slab" if f == 0 else f"floor {f}"
            # colour by height when many floors are drawn (dark low, light high)
            colour = cm.viridis(0.85 * f / max(n, 1)) if len(floors) > 4 else f"C{k}"
            line = ax.plot(ds["time"], uf, lw=0.8, label=text, color=colour)
            # an impact marked on the floor it hits, at its start
            for c in ds["contact"].values:
                sides = [
                    s
                    for s in ("left", "right")
                    if ds[f"contact_{s}"].values[c] == name
                    and int(ds[f"contact_{s}_floor"].values[c]) == f
                ]
                if not sides:
                    continue
                t = starts[which == c]
                if t.size:
                    y = np.interp(t, ds["time"].values, uf.values)
                    ax.plot(t, y, "v", ms=4, color=line[0].get_color(), mec="k", mew=0.4)
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.set_title(f"building {plain_text(name)} (▼ impact)", fontsize="small", loc="left")
        ax.set_ylabel(label(u, "displacement"))
        ax.legend(fontsize="x-small", ncol=4, loc="upper right")
    axes[-1, 0].set_xlabel(label(ds["time"]))
    return fig


#: Most floors a displacement history panel draws (the roof and the most struck contact floors).
MAX_HISTORY_FLOORS = 6


def _struck_floors(ds: xr.Dataset, name: str, n: int) -> set[int]:
    """The roof and the contact floors of ``name``; beyond MAX_HISTORY_FLOORS, the roof and the
    floors whose contacts carried the largest forces (a ten-storey row would draw ten lines)."""
    force: dict[int, float] = {}
    for c in ds["contact"].values:
        for side in ("left", "right"):
            if ds[f"contact_{side}"].values[c] == name:
                f = int(ds[f"contact_{side}_floor"].values[c])
                peak = (
                    float(ds["peak_contact_force"].values[c]) if "peak_contact_force" in ds else 0.0
                )
                force[f] = max(force.get(f, 0.0), peak if math.isfinite(peak) else 0.0)
    ranked = [f for f in sorted(force, key=lambda f: -force[f]) if f != n]
    return {n, *ranked[: MAX_HISTORY_FLOORS - 1]}


def shear_envelopes(ds: xr.Dataset) -> Figure:
    """Peak story shear [MN] over the height of every building, with contact (solid) and, when the
    result has its no-contact baseline, without (dashed)."""
    fig, axes = _figure(3.6)
    ax = axes[0, 0]
    sets = [("peak_story_shear", "-", "")]
    if "no_contact_peak_story_shear" in ds:
        sets.append(("no_contact_peak_story_shear", "--", " no contact"))
    for k, name in enumerate(_buildings(ds)):
        n = _n_floors(ds, name)
        z = np.concatenate(([0.0], ds["floor_elevation"].sel(building=name).values[:n]))
        for var, ls, tag in sets:
            shear = ds[var].sel(building=name).values[:n] / 1e6
            ax.plot(np.repeat(shear, 2), np.repeat(z, 2)[1:-1], ls, color=f"C{k}",
                    label=plain_text(f"{name}{tag}"))  # fmt: skip
    ax.set_xlabel("peak story shear [MN]")
    ax.set_ylabel(label(ds["floor_elevation"]) if "floor_elevation" in ds else "elevation [m]")
    ax.set_xlim(left=0.0)
    ax.legend(fontsize="x-small")
    ax.grid(True, alpha=0.3)
    return fig


def floor_spectra(ds: xr.Dataset) -> Figure:
    """Floor response spectra (``floor_spectrum``): PSa of each chosen floor against the period."""
    fig, axes = _figure(3.4)
    ax = axes[0, 0]
    frs = ds["floor_spectrum"]
    for name in _buildings(ds):
        for floor in frs.sel(building=name).dropna("floor", how="all")["floor"].values:
            ax.plot(ds["period"].values, frs.sel(building=name, floor=floor).values,
                    label=plain_text(f"{name} floor {int(floor)}"))  # fmt: skip
    ax.set_xscale("log")
    ax.set_xlabel(label(ds["period"]))
    damping = 100 * float(ds.attrs.get("floor_spectra_damping", 0.05))
    ax.set_ylabel(f"PSa, {damping:g} % damping [m/s²]")
    ax.legend(fontsize="x-small")
    ax.grid(True, which="both", alpha=0.3)
    return fig


def envelopes(
    ds: xr.Dataset, other: xr.Dataset | None = None, names: tuple[str, str] = ("", "")
) -> Figure:
    """Peak displacement and peak drift ratio over the height of every building.

    With ``other`` (e.g. the no-contact run) both are drawn, labelled by ``names``.
    """
    fig, axes = _figure(3.6, ncols=2, sharey=True)
    sets = [(ds, names[0], "-")] + ([(other, names[1], "--")] if other is not None else [])
    for data, tag, ls in sets:
        for name in _buildings(data):
            n = _n_floors(data, name)
            z = data["floor_elevation"].sel(building=name).values[:n]
            disp = data["peak_displacement"].sel(building=name).values[:n]
            drift = data["peak_drift_ratio"].sel(building=name).values[:n]
            text = plain_text(f"{name} {tag}".strip())
            # at z = 0: the ground, or the sliding base slab of an isolated building
            base = (
                float(data["peak_base_displacement"].sel(building=name))
                if "peak_base_displacement" in data
                else math.nan
            )
            axes[0, 0].plot(
                np.concatenate(([base if math.isfinite(base) else 0.0], disp)),
                np.concatenate(([0.0], z)),
                ls,
                marker="o",
                ms=3,
                label=text,
            )
            zz = np.repeat(np.concatenate(([0.0], z)), 2)[1:-1]
            axes[0, 1].plot(np.repeat(drift, 2), zz, ls, label=text)
    axes[0, 0].set_xlabel(label(ds["peak_displacement"]))
    axes[0, 1].set_xlabel(label(ds["peak_drift_ratio"]))
    axes[0, 0].set_ylabel(
        label(ds["floor_elevation"]) if "floor_elevation" in ds else "elevation [m]"
    )
    for ax in axes[0]:
        ax.set_xlim(left=0.0)
        ax.legend(fontsize="x-small")
        ax.grid(True, alpha=0.3)
    return fig


def _active_contacts(ds: xr.Dataset) -> list[int]:
    peak = ds["contact_force"].max("time").values if "contact_force" in ds else []
    return [int(c) for c, p in zip(ds["contact"].values, peak, strict=False) if p > 0]


#: Contact-force panels drawn at most (the elements with the largest forces); time kept around
#: the impacts on either side [s].
MAX_FORCE_PANELS, IMPACT_MARGIN = 6, 0.25


def impact_window(ds: xr.Dataset, margin: float = IMPACT_MARGIN) -> tuple[float, float] | None:
    """The time span [s] from the first impact's start to the last one's end, widened by
    ``margin`` on each side and kept within the record; None without impacts."""
    if not ds.sizes.get("impact", 0):
        return None
    t = ds["time"].values
    start = float(np.nanmin(ds["impact_start"].values))
    ends = ds["impact_end"].values
    end = float(np.nanmax(ends)) if np.isfinite(ends).any() else float(t[-1])
    return max(float(t[0]), start - margin), min(float(t[-1]), end + margin)


def _peak_times(ds: xr.Dataset, c: int, mine: np.ndarray) -> np.ndarray:
    """Where to draw each impact's exact peak: the output sample of largest force inside the
    impact, or its middle when no sample falls inside (an impact shorter than the output step)."""
    t = ds["time"].values
    f = ds["contact_force"].sel(contact=c).values
    out = []
    for start, end in zip(
        ds["impact_start"].values[mine], ds["impact_end"].values[mine], strict=True
    ):
        end = t[-1] if not np.isfinite(end) else end
        inside = np.flatnonzero((t >= start) & (t <= end))
        out.append(t[inside[np.argmax(f[inside])]] if inside.size else 0.5 * (start + end))
    return np.asarray(out, dtype=float)


def contact_forces(ds: xr.Dataset) -> Figure:
    """Contact force [MN] over time of the gap elements that closed (the MAX_FORCE_PANELS with the
    largest forces), zoomed on the span of the impacts, each impact's exact peak marked."""
    active = _active_contacts(ds) or [int(c) for c in ds["contact"].values[:1]]
    if len(active) > MAX_FORCE_PANELS:
        peak = ds["peak_contact_force"]
        active = sorted(active, key=lambda c: -float(peak.sel(contact=c)))[:MAX_FORCE_PANELS]
        active.sort()
    fig, axes = _figure(1.2 + 1.5 * len(active), nrows=max(1, len(active)), sharex=True)
    window = impact_window(ds)
    for ax, c in zip(axes[:, 0], active, strict=False):
        ax.plot(ds["time"], ds["contact_force"].sel(contact=c) / 1e6, lw=0.8)
        if ds.sizes.get("impact", 0):
            mine = ds["impact_contact"].values == c
            ax.plot(_peak_times(ds, c, mine), ds["impact_peak_force"].values[mine] / 1e6, "v",
                    ms=3.5, color="C3", label="peak of each impact (every step)")  # fmt: skip
        ax.set_title(f"contact {c}: {_contact_name(ds, c)}", fontsize="small", loc="left")
        ax.set_ylabel(label(ds["contact_force"], "force", units="MN"))
        ax.set_ylim(bottom=0.0)
    if window is not None:
        axes[0, 0].set_xlim(*window)
    axes[-1, 0].set_xlabel(label(ds["time"]))
    if ds.sizes.get("impact", 0):
        axes[0, 0].legend(fontsize="x-small", loc="upper right")
    return fig


def _largest_impact(ds: xr.Dataset) -> tuple[int, slice] | None:
    """Gap element and output samples of the impact with the largest force (None: no impact)."""
    active = _active_contacts(ds)
    if not active:
        return None
    c = max(active, key=lambda k: float(ds["contact_force"].sel(contact=k).max()))
    f = ds["contact_force"].sel(contact=c).values
    d = ds["penetration"].sel(contact=c).values
    i = int(np.argmax(f))
    inside = (f > 0) | (d > 0)
    lo, hi = i, i
    while lo > 0 and inside[lo - 1]:
        lo -= 1
    while hi < f.size - 1 and inside[hi + 1]:
        hi += 1
    return c, slice(max(lo - 1, 0), min(hi + 2, f.size))


def _impact_path(ds: xr.Dataset) -> tuple[int, float, np.ndarray, np.ndarray] | None:
    """(gap element, start time, penetration, force) of the impact with the largest force, at the
    integration steps the result kept (``impact_path_*``); None without them or without impacts."""
    if "impact_path_force" not in ds or not ds.sizes.get("impact", 0):
        return None
    i = int(np.nanargmax(ds["impact_peak_force"].values))
    d = ds["impact_path_penetration"].values[i]
    f = ds["impact_path_force"].values[i]
    kept = np.isfinite(d) & np.isfinite(f)
    if kept.sum() < 2:
        return None
    c = int(ds["impact_contact"].values[i])
    return c, float(ds["impact_start"].values[i]), d[kept], f[kept]


def force_penetration(runs: Sequence[tuple[str, xr.Dataset]], *, title: str = "") -> Figure:
    """Force–penetration loop of the strongest impact of each (label, Dataset).

    Drawn from the impact's integration steps when the result kept them (``impact_path_force``:
    analyses), else from the stored samples (output grid or kept histories), from the sample
    before the gap closes to the one after it opens; the peaks in the tables are exact, tracked
    at every integration step.
    """
    fig, axes = _figure(3.6)
    ax = axes[0, 0]
    labels = ("penetration [mm]", "contact force [MN]")
    for text, ds in runs:
        labels = (
            label(ds["penetration"], "penetration", units="mm"),
            label(ds["contact_force"], units="MN"),
        )
        path = _impact_path(ds)
        if path is not None:
            c, t0, d, f = path
        else:
            found = _largest_impact(ds)
            if found is None:
                continue
            c, window = found
            d = np.maximum(ds["penetration"].sel(contact=c).values[window], 0.0)
            f = ds["contact_force"].sel(contact=c).values[window]
            t0 = float(ds["time"].values[window][0])
        ax.plot(
            d * 1e3,
            f / 1e6,
            marker=".",
            ms=3,
            lw=1.0,
            label=plain_text(f"{text} (contact {c}, t = {t0:.2f} s)"),
        )
    ax.set_xlabel(labels[0])
    ax.set_ylabel(labels[1])
    ax.set_xlim(left=0.0)
    ax.set_ylim(bottom=0.0)
    ax.grid(True, alpha=0.3)
    if title:
        ax.set_title(plain_text(title), fontsize="small")
    if ax.lines:
        ax.legend(fontsize="x-small")
    return fig


def friction_share(ds: xr.Dataset) -> float:
    """Energy dissipated by bearing friction at the end of the record / input energy then [-].

    0 for a result without the ``friction_dissipated`` term or with no input.
    """
    e = ds["energy"]
    if "friction_dissipated" not in e["term"].values:
        return 0.0
    total = float(e.sel(term="input").values[-1])
    lost = float(e.sel(term="friction_dissipated").values[-1])
    return lost / total if total > 0.0 and math.isfinite(lost) else 0.0


def energy(ds: xr.Dataset) -> Figure:
    """The energy ledger over time: input energy against the sum of the other terms."""
    fig, axes = _figure(3.4)
    ax = axes[0, 0]
    e = ds["energy"]
    # terms that stay zero (no friction, no links, average acceleration) would only crowd the legend
    terms = [
        str(t)
        for t in e["term"].values
        if str(t) != "input" and bool(np.any(e.sel(term=t).values != 0.0))
    ]
    parts = np.stack([e.sel(term=t).values for t in terms])
    ax.stackplot(ds["time"].values, np.clip(parts, 0.0, None) / 1e3, labels=terms, alpha=0.8)
    ax.plot(ds["time"], e.sel(term="input") / 1e3, color="k", lw=1.2, label="input")
    err = ds.attrs.get("energy_balance_error")
    title = [] if err is None else [f"energy balance error {100 * float(err):.3g} % of the input"]
    share = friction_share(ds)
    if share > 0.0:
        title.append(f"bearing friction dissipated {100 * share:.3g} % of the input")
    if title:
        ax.set_title("; ".join(title), fontsize="small")
    ax.set_xlabel(label(ds["time"]))
    ax.set_ylabel(label(e, units="kJ"))
    ax.legend(fontsize="x-small", loc="upper left")
    return fig


# --------------------------------------------------------------------------------------------------
# Base isolation
# --------------------------------------------------------------------------------------------------


def _moat_gaps(ds: xr.Dataset, building: str) -> list[tuple[int, float]]:
    """(gap element, signed base displacement [m] at which the slab reaches a wall)."""
    out = []
    for c in ds["contact"].values:
        left, right = str(ds["contact_left"].values[c]), str(ds["contact_right"].values[c])
        gap = float(ds["contact_gap"].values[c])
        if left == building and int(ds["contact_left_floor"].values[c]) == 0 and right == "wall":
            out.append((int(c), gap))  # wall on the right: reached at u_b = +g
        if right == building and int(ds["contact_right_floor"].values[c]) == 0 and left == "wall":
            out.append((int(c), -gap))  # wall on the left: reached at u_b = -g
    return out


def _bearing_title(ds: xr.Dataset, building: str) -> str:
    sel = ds.sel(building=building)
    text = f"building {building}: {sel['base_type'].item()}, {sel['friction_law'].item()}"
    radius = float(sel["base_radius"]) if "base_radius" in ds else math.nan
    if math.isfinite(radius):
        text += f", R = {radius:.3g} m"
    return plain_text(text)


def base_displacements(ds: xr.Dataset) -> Figure:
    """Base slab (bearing) displacement over time of every isolated building.

    Moat walls (wall contacts at floor 0) are drawn at ±gap with the starts of their impacts;
    the intervals where the bearings stick are shaded.
    """
    names = isolated_buildings(ds)
    fig, axes = _figure(1.4 + 1.9 * max(1, len(names)), nrows=max(1, len(names)), sharex=True)
    t = ds["time"].values
    starts = ds["impact_start"].values if "impact_start" in ds else np.array([])
    which = ds["impact_contact"].values if "impact_contact" in ds else np.array([], dtype=int)
    for ax, name in zip(axes[:, 0], names, strict=False):
        ub = ds["base_displacement"].sel(building=name)
        ax.plot(t, ub, lw=0.8, color="C0", label="base slab")
        stuck = ds["stick"].sel(building=name).values == 1.0
        if stuck.any():
            ax.fill_between(
                t,
                0,
                1,
                where=stuck,
                transform=ax.get_xaxis_transform(),
                color="0.85",
                step="mid",
                label="bearings stuck",
            )
        for k, (c, edge) in enumerate(_moat_gaps(ds, name)):
            ax.axhline(edge, color="C3", ls="--", lw=0.9, label="moat wall" if k == 0 else None)
            hit = starts[which == c]
            if hit.size:
                ax.plot(hit, np.interp(hit, t, ub.values), "v", ms=4, color="C3", mec="k", mew=0.4)
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.set_title(_bearing_title(ds, name) + " (▼ impact)", fontsize="small", loc="left")
        ax.set_ylabel(label(ub, "base displacement"))
        ax.legend(fontsize="x-small", ncol=3, loc="upper right")
    axes[-1, 0].set_xlabel(label(ds["time"]))
    return fig


def foundation_motion(ds: xr.Dataset) -> Figure:
    """Roof displacement of every building on soil split into the foundation's sway u_0, its
    rocking H θ at the roof, and the stories' deformation, over time."""
    names = soil_buildings(ds)
    fig, axes = _figure(1.4 + 1.9 * max(1, len(names)), nrows=max(1, len(names)), sharex=True)
    t = ds["time"].values
    for ax, name in zip(axes[:, 0], names, strict=False):
        sel = ds.sel(building=name)
        roof = int(np.flatnonzero(np.isfinite(sel["floor_elevation"].values))[-1])
        height = float(sel["floor_elevation"].values[roof])
        total = sel["displacement"].isel(floor=roof).values
        sway = sel["foundation_sway"].values
        rocking = height * sel["foundation_rocking"].values
        ax.plot(t, total, lw=0.9, color="k", label="roof (total)")
        ax.plot(t, sway, lw=0.8, color="C0", label="foundation sway u₀")
        ax.plot(t, rocking, lw=0.8, color="C1", label=f"rocking H θ (H = {height:.3g} m)")
        ax.plot(t, total - sway - rocking, lw=0.8, color="C2", label="story deformations")
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.set_title(plain_text(f"building {name} on soil"), fontsize="small", loc="left")
        ax.set_ylabel("displacement [m]")
        ax.legend(fontsize="x-small", ncol=2, loc="upper right")
    axes[-1, 0].set_xlabel(label(ds["time"]))
    return fig


def column_shears(ds: xr.Dataset) -> Figure:
    """Shear of each struck column's two segments over time, with its capacity and the starts of
    the impacts on it."""
    n = ds.sizes.get("column", 0)
    fig, axes = _figure(1.4 + 1.8 * max(1, n), nrows=max(1, n), sharex=True)
    t = ds["time"].values
    starts = ds["impact_start"].values if "impact_start" in ds else np.array([])
    which = ds["impact_contact"].values if "impact_contact" in ds else np.array([], dtype=int)
    names = ds["building"].values
    for q, ax in enumerate(axes[:n, 0]):
        sel = ds.isel(column=q)
        for s, color in ((0, "C0"), (1, "C1")):
            ax.plot(t, sel["column_shear"].values[:, s] / 1e6, lw=0.8, color=color,
                    label=f"segment {sel['segment'].values[s]}")  # fmt: skip
        capacity = float(sel["column_capacity"])
        if np.isfinite(capacity):
            for sign in (1, -1):
                ax.axhline(sign * capacity / 1e6, color="C3", ls="--", lw=0.9,
                           label="capacity" if sign > 0 else None)  # fmt: skip
        struck = [c for c in range(ds.sizes.get("contact", 0))
                  if q in (int(ds["contact_left_column"][c]), int(ds["contact_right_column"][c]))]  # fmt: skip
        hit = starts[np.isin(which, struck)]
        if hit.size:
            ax.plot(hit, np.zeros_like(hit), "v", ms=4, color="C3", mec="k", mew=0.4)
        building = str(names[int(sel["column_building"])])
        ax.set_title(plain_text(f"{building} story {int(sel['column_story'])}, struck at "
                                f"{float(sel['column_elevation']):.3g} m (▼ impact)"),
                     fontsize="small", loc="left")  # fmt: skip
        ax.set_ylabel("shear [MN]")
        ax.legend(fontsize="x-small", ncol=3, loc="upper right")
    axes[-1, 0].set_xlabel(label(ds["time"]))
    return fig


def bearing_hysteresis(ds: xr.Dataset) -> Figure:
    """Hysteresis loops of the isolation bearings: friction force against base displacement.

    One panel per isolated building. A friction pendulum also shows its total lateral force
    f + (W/R) u_b, the friction plus the pendulum's restoring force [1]_. The title gives the
    loop's area ∮ f du_b (trapezoidal over the stored samples), the energy the bearings dissipated.

    References
    ----------
    .. [1] Zayas, V.A., Low, S.S., Mahin, S.A. (1990). A simple pendulum technique for achieving
       seismic isolation. Earthquake Spectra 6(2), 317-333. https://doi.org/10.1193/1.1585573
    """
    names = isolated_buildings(ds)
    fig, axes = _figure(3.4, ncols=max(1, len(names)), sharey=True)
    for ax, name in zip(axes[0], names, strict=False):
        sel = ds.sel(building=name)
        u = sel["base_displacement"].values
        f = sel["friction_force"].values
        ax.plot(u, f, lw=0.8, color="C0", label="friction f")
        radius = float(sel["base_radius"]) if "base_radius" in ds else math.nan
        if math.isfinite(radius):
            w = float(sel["base_normal_force"])
            ax.plot(u, f + w / radius * u, lw=0.6, color="C1", alpha=0.8, label="f + (W/R) u_b")
        ok = np.isfinite(u) & np.isfinite(f)
        area = float(np.trapezoid(f[ok], u[ok])) if ok.sum() > 1 else math.nan
        ax.set_title(
            f"{_bearing_title(ds, name)}\n∮ f du_b = {area / 1e3:.4g} kJ", fontsize="small"
        )
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.axvline(0.0, color="0.6", lw=0.6)
        ax.set_xlabel(label(sel["base_displacement"]))
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize="x-small", loc="upper left")
    axes[0, 0].set_ylabel(label(ds["friction_force"], "bearing force"))
    return fig


def yielding_buildings(ds: xr.Dataset) -> list[str]:
    """Names of the buildings with a hysteretic story model (none without ``story_model``)."""
    if "story_model" not in ds:
        return []
    models = ds["story_model"]
    return [
        str(b)
        for b in ds["building"].values
        if any(m not in ("", "elastic") for m in models.sel(building=b).values)
    ]


def story_hysteresis(ds: xr.Dataset, n_stories: int = 3) -> Figure:
    """Story hysteresis loops: spring (restoring) force against drift of the ``n_stories`` most
    ductile stories of each building with yielding stories, one panel per building. The legend
    gives each story's peak ductility μ and its hysteretic energy E_h."""
    names = yielding_buildings(ds)
    fig, axes = _figure(3.4, ncols=max(1, len(names)))
    for ax, name in zip(axes[0], names, strict=False):
        sel = ds.sel(building=name)
        mu = sel["story_ductility"].values
        order = [
            int(i) for i in np.argsort(np.nan_to_num(mu, nan=-1.0))[::-1] if np.isfinite(mu[i])
        ]
        for j, i in enumerate(order[:n_stories]):
            story = int(sel["story"].values[i])
            x = sel["drift"].isel(story=i).values * 1e3
            f = sel["story_spring_force"].isel(story=i).values / 1e3
            e_h = float(sel["hysteretic_energy"].isel(story=i)) / 1e3
            ax.plot(x, f, lw=0.7, color=f"C{j}",
                    label=f"story {story}: μ = {mu[i]:.3g}, E_h = {e_h:.3g} kJ")  # fmt: skip
        fy = float(np.nanmax(sel["yield_force"].values)) / 1e3
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.axvline(0.0, color="0.6", lw=0.6)
        collapse = float(sel["collapse_time"]) if "collapse_time" in ds else math.nan
        extra = f", collapse at {collapse:.3g} s" if math.isfinite(collapse) else ""
        model = str(sel["story_model"].values[0])
        ax.set_title(f"{name}: {model} stories (F_y up to {fy:.4g} kN){extra}", fontsize="small")
        ax.set_xlabel("drift [mm]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize="x-small", loc="upper left")
    axes[0, 0].set_ylabel("story spring force [kN]")
    return fig


# --------------------------------------------------------------------------------------------------
# Studies
# --------------------------------------------------------------------------------------------------


def _laws(ds: xr.Dataset) -> list[str]:
    return [str(v) for v in ds["law"].values if str(v) != _NO_CONTACT] if "law" in ds.dims else []


def amplification(
    ds: xr.Dataset, variable: str = "displacement_amplification", x: str = "gap"
) -> Figure:
    """Median amplification (with contact / without) against axis ``x``, a line per law, a panel per
    building; the band spans the 16th-84th percentiles over the records."""
    da = ds[variable]
    names = _buildings(ds)
    fig, axes = _figure(3.4, ncols=len(names), sharey=True)
    laws = _laws(ds) or [None]
    for ax, name in zip(axes[0], names, strict=True):
        sub = da.sel(building=name)
        for law in laws:
            s = sub.sel(law=law) if law is not None else sub
            if x in s.dims:
                keep = [x]
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", RuntimeWarning)
                    med = _median(s, keep)
                    others = [d for d in s.dims if d != x]
                    lo = s.quantile(0.16, dim=others, skipna=True) if others else s
                    hi = s.quantile(0.84, dim=others, skipna=True) if others else s
                xs = ds[x].values
                line = ax.plot(xs, med.values, marker="o", ms=3, label=plain_text(law or variable))
                ax.fill_between(xs, lo.values, hi.values, color=line[0].get_color(), alpha=0.12)
                ax.set_xlabel(label(ds[x]))
            else:
                med = float(_median(s, []))
                ax.bar(str(law), med)
        ax.axhline(1.0, color="k", lw=0.8, ls="--")
        ax.set_title(f"building {plain_text(name)}", fontsize="small")
        ax.grid(True, alpha=0.3)
    axes[0, 0].set_ylabel(label(da, "amplification", units="1"))
    if laws != [None] and any(not ln.get_label().startswith("_") for ln in axes[0, 0].lines):
        axes[0, -1].legend(fontsize="x-small")
    fig.suptitle(da.attrs.get("long_name", variable), fontsize="small")
    return fig


def heatmap(
    ds: xr.Dataset,
    variable: str,
    x: str,
    y: str,
    *,
    building: str | None = None,
    scale: float = 1.0,
    units: str | None = None,
    fmt: str = "{:.2f}",
    name: str | None = None,
) -> Figure:
    """Median of ``variable`` over all axes but ``x`` and ``y`` as an annotated heat map."""
    da = ds[variable]
    if building is not None and "building" in da.dims:
        da = da.sel(building=building)
    if "contact" in da.dims:
        da = da.max("contact", skipna=True, keep_attrs=True)
    if y == "law":
        da = da.sel(law=_laws(ds))
    med = _median(da, [y, x]).transpose(y, x) * scale
    fig, axes = _figure(0.9 + 0.32 * med.sizes[y] + 0.6)
    ax = axes[0, 0]
    values = med.values
    finite = values[np.isfinite(values)]
    vmin, vmax = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    ratio = variable.endswith("_amplification")
    if ratio:
        # a ratio to the no-contact run: diverging about 1 with symmetric limits 1 ± d, so more
        # and less than without contact read at a glance
        d = max(abs(vmin - 1.0), abs(vmax - 1.0), 0.05) if finite.size else 0.5
        vmin, vmax = 1.0 - d, 1.0 + d
        im = ax.imshow(values, aspect="auto", cmap="RdBu_r", vmin=vmin, vmax=vmax)
    else:
        im = ax.imshow(values, aspect="auto", cmap="viridis", vmin=vmin, vmax=vmax)
    for (i, j), v in np.ndenumerate(values):
        if math.isfinite(v):
            if ratio:  # white text on the strong ends of the diverging map
                light = abs(v - 1.0) > 0.6 * (vmax - 1.0)
            else:
                light = (v - vmin) / (vmax - vmin or 1.0) < 0.6
            ax.text(
                j,
                i,
                fmt.format(v),
                ha="center",
                va="center",
                fontsize="small",
                color="w" if light else "k",
            )
    ax.set_xticks(
        range(med.sizes[x]),
        [f"{v:g}" if isinstance(v, float) else plain_text(v) for v in med[x].values],
    )
    ax.set_yticks(range(med.sizes[y]), [plain_text(v) for v in med[y].values])
    ax.set_xlabel(label(ds[x]))
    ax.set_ylabel(label(ds[y]))
    cbar = fig.colorbar(im, ax=ax)
    cbar.set_label(label(da, name, units=units), fontsize="small")
    title = da.attrs.get("long_name", variable) + (
        f", building {plain_text(building)}" if building else ""
    )
    ax.set_title(f"median: {title}", fontsize="small")
    return fig


def study_histories(runs: Sequence[tuple[str, xr.Dataset]], building: str) -> Figure:
    """Roof displacement of ``building`` over time for several runs (label, Dataset)."""
    fig, axes = _figure(3.2)
    ax = axes[0, 0]
    for text, ds in runs:
        n = _n_floors(ds, building) if "floor_elevation" in ds else ds.sizes["floor"]
        ax.plot(
            ds["time"],
            ds["displacement"].sel(building=building, floor=n),
            lw=0.8,
            label=plain_text(text),
        )
    if runs:
        ds = runs[0][1]
        ax.set_xlabel(label(ds["time"]))
        ax.set_ylabel(label(ds["displacement"], f"roof displacement of {plain_text(building)}"))
    ax.legend(fontsize="x-small", ncol=2)
    ax.grid(True, alpha=0.3)
    return fig


# --------------------------------------------------------------------------------------------------
# Separation distance (a Dataset of pounding.separation.separation_analysis)
# --------------------------------------------------------------------------------------------------


def _mark_case_gap(ax: Axes, ds: xr.Dataset, interface: str) -> None:
    """The gap the case gives this interface, as a solid red line (results written before it was
    recorded have none)."""
    if "case_gap" not in ds:
        return
    gap = float(ds["case_gap"].sel(interface=interface))
    if np.isfinite(gap):
        ax.axvline(gap, color="C3", lw=1.4, label="gap in the case")


def required_gaps(ds: xr.Dataset) -> Figure:
    """Required separation per estimate (rows) for every interface (panels): the median over the
    records as a bar, the 84th percentile and the largest value as markers."""
    interfaces = [str(f) for f in ds["interface"].values]
    stat = ds["required_gap_statistic"]
    labels = [str(x) for x in ds["estimate_label"].values]
    n_est = len(labels)
    fig, axes = _figure(1.3 + 0.32 * n_est, ncols=len(interfaces), sharey=True)
    y = np.arange(n_est)[::-1]
    for ax, f in zip(axes[0], interfaces, strict=True):
        s = stat.sel(interface=f)
        ax.barh(y, s.sel(statistic="median"), color="C0", alpha=0.7, label="median")
        if ds.sizes["record"] > 1:
            ax.plot(s.sel(statistic="p84"), y, "k|", ms=10, label="84th percentile")
            ax.plot(s.sel(statistic="max"), y, "rx", ms=5, label="largest")
        target = float(ds["gap_for_target_probability"].sel(interface=f))
        if np.isfinite(target):
            p = float(ds.attrs.get("target_probability", np.nan))
            ax.axvline(target, color="C2", ls="--", lw=1, label=f"lognormal, P = {p:.3g}")
        _mark_case_gap(ax, ds, f)
        ax.set_title(f"interface {plain_text(f)}", fontsize=9)
        ax.set_xlabel(label(stat, "required gap"))
        ax.grid(axis="x", alpha=0.3)
        ax.set_xlim(left=0.0)
    axes[0, 0].set_yticks(y, [plain_text(t) for t in labels], fontsize=7)
    handles, names = axes[0, -1].get_legend_handles_labels()
    fig.legend(handles, names, loc="outside lower center", ncols=len(names), fontsize=7)
    return fig


def pounding_probability(ds: xr.Dataset) -> Figure:
    """Probability of pounding against the gap, one panel per interface: the fraction of records
    whose exact gap exceeds it (steps), the lognormal fit, and the gap of the target probability."""
    interfaces = [str(f) for f in ds["interface"].values]
    fig, axes = _figure(2.8, ncols=len(interfaces), sharey=True)
    gap = ds["gap"]
    p = float(ds.attrs.get("target_probability", np.nan))
    for ax, f in zip(axes[0], interfaces, strict=True):
        emp = ds["pounding_probability"].sel(interface=f)
        ax.step(gap, emp, where="post", color="C0", label="fraction of records")
        ax.plot(gap, ds["pounding_probability_lognormal"].sel(interface=f), "C1", label="lognormal")
        target = float(ds["gap_for_target_probability"].sel(interface=f))
        if np.isfinite(p):
            ax.axhline(p, color="0.5", ls=":", lw=1)
        if np.isfinite(target):
            ax.axvline(target, color="C2", ls="--", lw=1, label=f"P = {p:.3g}: {target:.4g} m")
        _mark_case_gap(ax, ds, f)
        ax.set_title(f"interface {plain_text(f)}", fontsize=9)
        ax.set_xlabel(label(gap, "gap"))
        ax.set_ylim(-0.02, 1.02)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    axes[0, 0].set_ylabel(label(ds["pounding_probability"], "probability of pounding"))
    return fig


# --------------------------------------------------------------------------------------------------
# Fragility (incremental dynamic / multiple-stripe analysis)
# --------------------------------------------------------------------------------------------------


def fragility_curves(fr: xr.Dataset) -> Figure:
    """Fitted lognormal fragility curves (lines) over the observed fraction of the records that
    reached each limit state at each intensity level (markers), one panel per limit state and one
    colour per variant (the combinations of the other axes), with the bootstrap band when the fit
    has one. ``fr`` from ``ds.pounding.fragility(...)``."""
    limits = [str(v) for v in fr["limit_state"].values]
    fig, axes = _figure(3.4, ncols=len(limits))
    levels = fr["im_level"].values.astype(float) if "im_level" in fr.coords else None
    from pounding.fragility import no_contact, variants

    dims = [d for d in fr["fragility_median"].dims if d != "limit_state"]
    for ax, limit in zip(axes[0], limits, strict=False):
        sel = fr.sel(limit_state=limit)
        for j, at in enumerate(variants(fr, dims)):
            one = sel.isel(at)
            parts = []
            for d, i in at.items():
                if no_contact(fr, at) and d != "law":
                    continue  # without contact the other axes change nothing
                units = str(sel[d].attrs.get("units", ""))
                parts.append(f"{d} {sel[d].values[i]}{'' if units in ('', '1') else ' ' + units}")
            name = ", ".join(parts) or "all runs"
            theta, beta = float(one["fragility_median"]), float(one["fragility_beta"])
            color = f"C{j}"
            if levels is not None:
                ax.plot(levels, one["reached_fraction"].values, "o", ms=3.5, color=color)
            else:  # each record's capacity, as the empirical distribution (i − ½)/n
                cap = np.sort(one["capacity"].values)
                p = (np.arange(cap.size) + 0.5) / cap.size
                ax.plot(cap, p, "o", ms=3.0, color=color)
            if np.isfinite(theta):
                ax.plot(fr["im"].values, one["probability"].values, color=color, lw=1.2,
                        label=f"{name}: θ = {theta:.3g} g, β = {beta:.2g}")  # fmt: skip
                if "probability_low" in one:
                    ax.fill_between(fr["im"].values, one["probability_low"].values,
                                    one["probability_high"].values, color=color, alpha=0.15,
                                    lw=0)  # fmt: skip
            else:
                ax.plot([], [], "o", color=color, label=f"{name}: no fit")
        ax.set_title(limit, fontsize="small")
        ax.set_xlabel(f"{fr.attrs.get('im_label', 'intensity')} [g]")
        ax.set_ylim(-0.02, 1.02)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize="x-small", loc="lower right")
    axes[0, 0].set_ylabel("probability of reaching the limit state")
    return fig


def ida_curves(ds: xr.Dataset, building: str | None = None) -> Figure:
    """IDA curves: the largest peak story drift ratio of a building (or of all buildings) against the
    target intensity, one thin line per record and the median over the records (thick), one panel
    per variant (the no-contact variant once); a collapsed run is drawn at the collapse drift."""
    from pounding.fragility import no_contact, variants

    step = "ida_run" if "ida_run" in ds.dims else "im_level"
    dims = [d for d in ds["run_status"].dims if d not in ("record", step)]
    keep = variants(ds, dims)
    fig, axes = _figure(3.0, ncols=min(len(keep), 3), nrows=math.ceil(len(keep) / 3))
    drift = ds["peak_drift_ratio"].max("story")
    drift = drift.sel(building=building) if building else drift.max("building")
    analysis = json.loads(ds.attrs.get("analysis", "{}"))
    limit = float(analysis.get("collapse_drift") or 0.1)
    if "collapse_time" in ds:
        collapsed = np.isfinite(ds["collapse_time"])
        collapsed = collapsed.sel(building=building) if building else collapsed.any("building")
        drift = drift.where(~collapsed, limit)
    level_var = ds["ida_level"] if step == "ida_run" else ds["im_level"]
    grid = np.linspace(0.0, float(np.nanmax(level_var.values)), 61)
    for ax, at in zip(axes.ravel(), keep, strict=False):
        d = drift.isel(at).transpose("record", step).values * 100.0
        lv = np.broadcast_to(level_var.isel(at, missing_dims="ignore").values, d.shape)
        on_grid = np.full((d.shape[0], grid.size), np.nan)
        for r, (row, lr) in enumerate(zip(d, lv, strict=True)):
            ok = np.isfinite(row) & np.isfinite(lr)
            order = np.argsort(lr[ok])
            x, y = np.concatenate(([0.0], row[ok][order])), np.concatenate(([0.0], lr[ok][order]))
            ax.plot(x, y, color="0.6", lw=0.5)
            # drift at common intensities (up to the record's highest run) for the median
            inside = grid <= y[-1]
            on_grid[r, inside] = np.interp(grid[inside], y, x)
            if x[-1] >= 100.0 * limit:  # collapsed: the flatline goes on above its last run
                on_grid[r, ~inside] = x[-1]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # levels no record reached
            median = np.nanmedian(on_grid, axis=0)
        ax.plot(median, grid, color="C3", lw=1.8, label="median")
        ax.axvline(100.0 * limit, color="k", ls=":", lw=0.8)
        parts = []
        for dim, i in at.items():
            if no_contact(ds, at) and dim != "law":
                continue  # without contact the other axes change nothing
            units = str(ds[dim].attrs.get("units", ""))
            parts.append(f"{dim} {ds[dim].values[i]}{'' if units in ('', '1') else ' ' + units}")
        ax.set_title(plain_text(", ".join(parts) or "all runs"), fontsize="small")
        ax.set_xlabel("peak story drift ratio [%]")
        ax.grid(True, alpha=0.3)
    for ax in axes.ravel()[len(keep) :]:
        ax.set_visible(False)
    for ax in axes[:, 0]:
        ax.set_ylabel(f"{level_var.attrs.get('long_name', 'intensity')} [g]")
    axes.ravel()[0].legend(fontsize="x-small", loc="lower right")
    return fig
