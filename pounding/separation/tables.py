"""A separation Dataset as a comparison table and as plain data for reports."""

from __future__ import annotations

from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from pounding.separation.variables import STATISTICS


def separation_table(ds: xr.Dataset) -> pd.DataFrame:
    """The comparison table of a :func:`separation_analysis` Dataset, one row per interface and estimate.

    Columns: ``interface``, ``estimate`` (key of :data:`ESTIMATES`), ``label``, ``basis`` (formula,
    clause and edition), ``median``, ``p84``, ``max`` [m] over the records; then one row per interface
    for the lognormal gap at the target probability (estimate ``lognormal_target``, the value in
    ``median``, NaN elsewhere).
    """
    stat = ds["required_gap_statistic"]
    p = float(ds.attrs.get("target_probability", np.nan))
    rows = []
    for f in ds["interface"].values:
        for e in ds["estimate"].values:
            values = stat.sel(interface=f, estimate=e)
            rows.append(
                {
                    "interface": str(f),
                    "estimate": str(e),
                    "label": str(ds["estimate_label"].sel(estimate=e).item()),
                    "basis": str(ds["estimate_basis"].sel(estimate=e).item()),
                    **{s: float(values.sel(statistic=s)) for s in STATISTICS},
                }
            )
        rows.append(
            {
                "interface": str(f),
                "estimate": "lognormal_target",
                "label": f"lognormal fit of the exact gaps, P(pounding) = {p:.3g}",
                "basis": (
                    f"median {float(ds['lognormal_median'].sel(interface=f)):.4g} m, "
                    f"beta {float(ds['lognormal_beta'].sel(interface=f)):.3g} "
                    "(maximum likelihood; Lin & Weng 2001)"
                ),
                "median": float(ds["gap_for_target_probability"].sel(interface=f)),
                "p84": np.nan,
                "max": np.nan,
            }
        )
    return pd.DataFrame(rows, columns=["interface", "estimate", "label", "basis", *STATISTICS])


def separation_summary(ds: xr.Dataset) -> dict[str, Any]:
    """What a report section needs: the comparison table and the probability curves, as plain data.

    Returns
    -------
    dict
        ``title``, ``records`` (names), ``spectrum`` (description), ``method``, ``dt`` [s],
        ``target_probability``, ``units`` ("m"), and ``interfaces``: a list with, per interface,
        ``name``, ``pairs`` (labels), ``exact_gaps`` (per record, largest over the pairs [m]),
        ``table`` (rows of :func:`separation_table` as dicts), ``lognormal`` (``median`` [m],
        ``beta``, ``fraction``, ``gap_for_target`` [m]) and ``curve`` (``gap`` [m], ``empirical``,
        ``lognormal``: probability of pounding at each gap).
    """
    table = separation_table(ds)
    out: dict[str, Any] = {
        "title": str(ds.attrs.get("title", "")),
        "records": [str(r) for r in ds["record"].values],
        "spectrum": str(ds.attrs.get("spectrum_description", "")),
        "method": str(ds.attrs.get("method", "")),
        "dt": float(ds.attrs.get("dt", np.nan)),
        "target_probability": float(ds.attrs.get("target_probability", np.nan)),
        "units": "m",
        "interfaces": [],
    }
    th = ds["required_gap"].sel(estimate="time_history")
    for f in ds["interface"].values:
        f = str(f)
        sel = ds["pair_interface"].values == f
        out["interfaces"].append(
            {
                "name": f,
                "pairs": [str(x) for x in ds["pair_label"].values[sel]],
                "exact_gaps": [float(x) for x in th.sel(interface=f).values],
                "table": table[table["interface"] == f]
                .drop(columns="interface")
                .to_dict("records"),
                "lognormal": {
                    "median": float(ds["lognormal_median"].sel(interface=f)),
                    "beta": float(ds["lognormal_beta"].sel(interface=f)),
                    "fraction": float(ds["lognormal_fraction"].sel(interface=f)),
                    "gap_for_target": float(ds["gap_for_target_probability"].sel(interface=f)),
                },
                "curve": {
                    "gap": [float(x) for x in ds["gap"].values],
                    "empirical": [
                        float(x) for x in ds["pounding_probability"].sel(interface=f).values
                    ],
                    "lognormal": [
                        float(x)
                        for x in ds["pounding_probability_lognormal"].sel(interface=f).values
                    ],
                },
            }
        )
    return out
