"""Result Datasets as the tables engineers open: CSV files and Excel workbooks.

An analysis (``pounding run``), a study (``pounding study``) or a separation check
(``pounding separation``) is flattened into named tables (pandas DataFrames). Every column header
carries the unit of its CF ``units`` attribute, as ``peak_displacement [m]``; columns without a
unit (names, labels) have none. Values stay in SI, exactly as stored in the Dataset.

Tables
------
analysis
    ``peaks`` (building, floor: peak displacement, absolute acceleration, and the peak drift ratio
    of the story below that floor), ``contacts`` (ends, gap, law, impacts, peak force and
    penetration), ``impacts`` (the impact log), ``energy`` (time history of every energy term),
    ``histories`` (every time history, long or wide).
study
    ``summary`` (one row per combination of the study axes), ``buildings`` (per building),
    ``peaks`` (per building and floor), ``contacts`` (per contact).
separation
    ``comparison`` (required gap by every estimate, median/p84/max over the records),
    ``probability`` (probability of pounding against the gap).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Literal

import numpy as np
import pandas as pd
import xarray as xr

from pounding.errors import PoundingInputError
from pounding.results import result_kind

Histories = Literal["long", "wide"] | None

_EXCEL_MISSING = "Excel export needs openpyxl: pip install 'pounding[excel]'"
HISTORY_FORMS = ("long", "wide", "none")
_EXCEL_ROWS = 1_048_576  # rows of a sheet, the header included


def header(name: str, units: str | None) -> str:
    """Column header ``name [units]`` (just ``name`` without a unit)."""
    return f"{name} [{units}]" if units else name


def _units(ds: xr.Dataset, name: str) -> str | None:
    u = ds[name].attrs.get("units") if name in ds.variables else None
    return str(u) if u else None


def _frame(ds: xr.Dataset, names: Sequence[str], index: Sequence[str]) -> pd.DataFrame:
    """Variables ``names`` over dims ``index`` as rows; coordinates on those dims become columns."""
    sub = ds[list(names)]
    extra = [c for c in sub.coords if c not in index and set(sub[c].dims) <= set(index)]
    sub = sub.reset_coords(drop=True)
    for c in extra:
        sub[c] = xr.Variable(ds[c].dims, ds[c].values, ds[c].attrs)
    df = sub.to_dataframe(dim_order=list(index)).reset_index()
    # NaN padding (floors above a shorter building) is no result
    values = [n for n in names if n in df]
    df = df.dropna(subset=values, how="all").reset_index(drop=True)
    return df.rename(columns={c: header(c, _units(ds, c)) for c in df.columns})


def _level_frame(
    ds: xr.Dataset, index: Sequence[str], floor_vars: list[str], story_vars: list[str]
):
    """Floor and story variables side by side; story i is the story below floor i."""
    parts = [ds[floor_vars]] if floor_vars else []
    if story_vars:
        parts.append(ds[story_vars].rename(story="floor").reset_coords(drop=True))
    merged = xr.merge(parts, compat="override", join="outer")
    for v in merged.data_vars:
        merged[v].attrs = ds[v].attrs
    if "floor_elevation" in ds:
        merged = merged.assign_coords(floor_elevation=ds["floor_elevation"])
    return _frame(merged, floor_vars + story_vars, [*index, "building", "floor"])


def _dims_vars(ds: xr.Dataset, dims: Sequence[str], numeric: bool = False) -> list[str]:
    return [
        str(v)
        for v in ds.data_vars
        if set(ds[v].dims) == set(dims) and (not numeric or ds[v].dtype.kind in "iufb")
    ]


# --- analysis ---


def _history_wide(ds: xr.Dataset) -> pd.DataFrame:
    cols: dict[str, np.ndarray] = {header("time", _units(ds, "time")): ds["time"].values}
    for v in ds.data_vars:
        da = ds[v]
        if "time" not in da.dims:
            continue
        other = [d for d in da.dims if d != "time"]
        stacked = da.transpose("time", *other)
        if not other:
            cols[header(str(v), _units(ds, v))] = stacked.values
            continue
        flat = stacked.stack(_loc=other)
        for j, loc in enumerate(flat["_loc"].values):
            series = flat.values[:, j]
            if np.all(np.isnan(series)):
                continue
            label = ":".join(str(x) for x in (loc if isinstance(loc, tuple) else (loc,)))
            cols[header(f"{v} {label}", _units(ds, v))] = series
    return pd.DataFrame(cols)


def _history_long(ds: xr.Dataset) -> pd.DataFrame:
    """One row per (variable, location, time): columns variable, location, units, time [s], value."""
    frames = []
    t = ds["time"].values
    for v in ds.data_vars:
        da = ds[v]
        if "time" not in da.dims:
            continue
        other = [d for d in da.dims if d != "time"]
        flat = da.transpose("time", *other).values.reshape(len(t), -1)
        if other:
            locs = da.isel(time=0).stack(_loc=other)["_loc"].values
            labels = [":".join(str(x) for x in (c if isinstance(c, tuple) else (c,))) for c in locs]
        else:
            labels = [""]
        for j, label in enumerate(labels):
            if np.all(np.isnan(flat[:, j])):
                continue
            frames.append(
                pd.DataFrame(
                    {
                        "variable": str(v),
                        "location": label,
                        "units": _units(ds, v) or "",
                        header("time", _units(ds, "time")): t,
                        "value": flat[:, j],
                    }
                )
            )
    return pd.concat(frames, ignore_index=True)


def _peak_like(name: str) -> bool:
    """Peaks, the no-contact baseline's peaks and their comparisons (per floor or story)."""
    return name.startswith(("peak_", "no_contact_peak_")) or name.endswith(
        ("_amplification", "impact_story_shear")
    )


def _analysis_tables(ds: xr.Dataset, histories: Histories) -> dict[str, pd.DataFrame]:
    tables: dict[str, pd.DataFrame] = {}
    floor = [v for v in _dims_vars(ds, ("building", "floor"), True) if _peak_like(v)]
    story = [v for v in _dims_vars(ds, ("building", "story"), True) if _peak_like(v)]
    tables["peaks"] = _level_frame(ds, [], floor, story)
    contact = _dims_vars(ds, ("contact",), True)
    if ds.sizes.get("contact", 0):
        tables["contacts"] = _frame(ds, contact, ["contact"])
    impacts = _dims_vars(ds, ("impact",), True)
    if impacts:
        tables["impacts"] = _frame(ds, impacts, ["impact"])
    else:
        tables["impacts"] = pd.DataFrame(columns=["impact"])
    energy = ds["energy"].transpose("time", "term")
    u = _units(ds, "energy")
    tables["energy"] = pd.DataFrame(
        {
            header("time", _units(ds, "time")): ds["time"].values,
            **{header(str(k), u): energy.sel(term=k).values for k in ds["term"].values},
        }
    )
    if histories == "wide":
        tables["histories"] = _history_wide(ds)
    elif histories == "long":
        tables["histories"] = _history_long(ds)
    return tables


# --- study ---


def _study_tables(ds: xr.Dataset) -> dict[str, pd.DataFrame]:
    import json

    axes = [str(a) for a in json.loads(ds.attrs.get("axes", "[]"))] or [
        d for d in ("law", "gap", "record") if d in ds.dims
    ]
    tables = {"summary": _frame(ds, _dims_vars(ds, axes), axes)}
    per_building = _dims_vars(ds, [*axes, "building"], True)
    if per_building:
        tables["buildings"] = _frame(ds, per_building, [*axes, "building"])
    floor = _dims_vars(ds, [*axes, "building", "floor"], True)
    story = _dims_vars(ds, [*axes, "building", "story"], True)
    if floor or story:
        tables["peaks"] = _level_frame(ds, axes, floor, story)
    contact = _dims_vars(ds, [*axes, "contact"], True)
    if contact:
        tables["contacts"] = _frame(ds, contact, [*axes, "contact"])
    return tables


# --- separation ---


def _separation_tables(ds: xr.Dataset) -> dict[str, pd.DataFrame]:
    from pounding.separation import STATISTICS, separation_table

    comp = separation_table(ds)
    units = _units(ds, "required_gap_statistic")
    comp = comp.rename(columns={s: header(s, units) for s in STATISTICS})
    prob = _dims_vars(ds, ("interface", "gap"), True)
    return {"comparison": comp, "probability": _frame(ds, prob, ["interface", "gap"])}


# --- public ---


def tables(
    ds: xr.Dataset, *, names: Sequence[str] | None = None, histories: Histories = "long"
) -> dict[str, pd.DataFrame]:
    """The tables of a result Dataset, by name.

    Parameters
    ----------
    ds
        An analysis, study or separation Dataset (:func:`pounding.results.result_kind`).
    names
        Tables to keep (default all of the kind's tables); an unknown name raises ``ValueError``
        listing the allowed ones.
    histories
        ``"long"`` (one row per variable, location and time; the unit in column ``units``),
        ``"wide"`` (one row per time, one column per variable and location, e.g.
        ``displacement A:3 [m]``) or ``None`` (no ``histories`` table). Analyses only.

    Returns
    -------
    dict of str to pandas.DataFrame
        Column headers carry units as ``name [unit]``; values in SI.
    """
    if histories not in ("long", "wide", None):
        raise PoundingInputError(f"histories: {histories!r} is not one of 'long', 'wide', None")
    kind = result_kind(ds)
    if kind == "study":
        allowed = ["summary", "buildings", "peaks", "contacts"]
    elif kind == "separation":
        allowed = ["comparison", "probability"]
    else:
        allowed = ["peaks", "contacts", "impacts", "energy", "histories"]
    for n in names or ():
        if n not in allowed:
            raise PoundingInputError(
                f"table: {n!r} is not a table of the {kind} result; allowed: {', '.join(allowed)}"
            )
    if names and "histories" in names and histories is None:
        histories = "long"
    if kind == "study":
        out = _study_tables(ds)
    elif kind == "separation":
        out = _separation_tables(ds)
    else:
        out = _analysis_tables(ds, histories)
    return {k: v for k, v in out.items() if not names or k in names}


def export(
    ds: xr.Dataset,
    path: str | Path,
    *,
    format: Literal["csv", "xlsx"] | None = None,
    names: Sequence[str] | None = None,
    histories: Histories = "long",
) -> list[Path]:
    """Write the tables of a result Dataset as CSV or as an Excel workbook.

    Parameters
    ----------
    ds
        An analysis, study or separation Dataset.
    path
        ``.xlsx``: one workbook, one sheet per table. ``.csv`` with one table chosen: that file.
        Otherwise a directory (created) with ``NAME.csv`` per table.
    format
        ``"csv"`` or ``"xlsx"``; default from the extension of ``path`` (csv without one).
    names, histories
        As :func:`tables`.

    Returns
    -------
    list of Path
        The files written.

    Raises
    ------
    ImportError
        Excel asked for without ``openpyxl`` installed.
    """
    path = Path(path)
    if format is None:
        format = "xlsx" if path.suffix.lower() == ".xlsx" else "csv"
    if format not in ("csv", "xlsx"):
        raise PoundingInputError(f"format: {format!r} is not one of 'csv', 'xlsx'")
    if format == "xlsx":
        try:
            import openpyxl  # noqa: F401
        except ImportError:
            raise ImportError(_EXCEL_MISSING) from None
    chosen = tables(ds, names=names, histories=histories)
    if format == "xlsx":
        for name, df in chosen.items():
            if len(df) >= _EXCEL_ROWS:
                raise PoundingInputError(
                    f"table {name}: {len(df)} rows, more than an Excel sheet holds "
                    f"({_EXCEL_ROWS - 1}); use --histories wide or csv"
                )
        path.parent.mkdir(parents=True, exist_ok=True)
        with pd.ExcelWriter(path, engine="openpyxl") as xw:
            for name, df in chosen.items():
                df.to_excel(xw, sheet_name=name[:31], index=False)
        return [path]
    if path.suffix.lower() == ".csv":
        if len(chosen) != 1:
            raise PoundingInputError(
                f"-o {path}: a .csv file holds one table, {len(chosen)} chosen "
                f"({', '.join(chosen)}); give a directory or one --table"
            )
        path.parent.mkdir(parents=True, exist_ok=True)
        next(iter(chosen.values())).to_csv(path, index=False)
        return [path]
    path.mkdir(parents=True, exist_ok=True)
    written = []
    for name, df in chosen.items():
        df.to_csv(path / f"{name}.csv", index=False)
        written.append(path / f"{name}.csv")
    return written
