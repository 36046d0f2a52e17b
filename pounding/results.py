"""The results schema: one ``xr.Dataset`` per analysis, CF attributes on everything.

Dimensions: ``time``, ``building``, ``floor`` (1..N, NaN-padded where a building is shorter),
``story``, ``contact`` (gap elements 0..C−1), ``term`` (energy ledger), ``mode``, ``impact``.
Derived quantities live on the ``ds.pounding`` accessor (:class:`PoundingAccessor`).

Isolated buildings (base slab on sliding bearings) add, per building, ``base_displacement``,
``base_velocity``, ``friction_force``, ``stick`` (time, building) and ``peak_base_displacement``
(building), NaN for fixed-base buildings; the base slab is not a floor (floors stay 1..N, story 1
drifts relative to the slab). The energy ledger has the term ``friction_dissipated``.
"""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from pounding._schema import (  # noqa: F401  (ATTRS, energy_balance_error: public names here)
    ATTRS,
    ResultVariables,
    energy_balance_error,
    result_variables,
)
from pounding._schema import summary as _summary
from pounding.errors import PoundingInputError
from pounding.ground_motion import GroundMotion
from pounding.integrators.base import RawResult
from pounding.system import PoundingSystem


def build_dataset(
    system: PoundingSystem,
    ground: GroundMotion,
    raw: RawResult,
    *,
    provenance: dict[str, Any] | None = None,
) -> xr.Dataset:
    """Turn a :class:`RawResult` into the schema's ``xr.Dataset``."""
    return to_dataset(result_variables(system, ground, raw, provenance=provenance))


def to_dataset(result: ResultVariables) -> xr.Dataset:
    """The ``xr.Dataset`` of a :class:`~pounding._schema.ResultVariables`."""
    coords = set(result.coords)
    data, coord_vars = {}, {}
    for name, (dims, values, attrs) in result.variables.items():
        (coord_vars if name in coords else data)[name] = xr.Variable(dims, values, dict(attrs))
    return xr.Dataset(data, coords=coord_vars, attrs=dict(result.attrs))


def save(ds: xr.Dataset, path: str | Path) -> Path:
    """Write a result to NetCDF-4 (an HDF5 file that xarray reads with the h5netcdf engine).

    Float, integer and string variables whose dimensions all have coordinates (every result
    pounding makes) are written by :mod:`pounding._netcdf` on h5py directly, ~10x faster than
    ``to_netcdf``; anything else (other dtypes, an encoding asking for compression, packing or
    another dtype) goes through ``ds.to_netcdf(engine="h5netcdf")``."""
    from pounding import _netcdf

    path = Path(path)
    variables = {
        str(name): (tuple(map(str, v.dims)), np.asarray(v.values), v.attrs)
        for name, v in ds.variables.items()
    }
    if _netcdf.supported(variables) and not any(map(_encoded, ds.variables.values())):
        _netcdf.write(path, variables, map(str, ds.coords), ds.attrs)
    else:
        with _netcdf.replacing(path) as tmp:
            ds.to_netcdf(tmp, engine="h5netcdf", invalid_netcdf=False)
    return path


def _encoded(var: xr.Variable) -> bool:
    """True when ``var.encoding`` changes what is stored (packing, another dtype, compression):
    left to xarray's encoder."""
    enc = var.encoding
    return (
        any(k in enc for k in ("scale_factor", "add_offset", "units", "calendar"))
        or any(enc.get(k) for k in ("zlib", "compression", "szip"))
        or ("dtype" in enc and np.dtype(enc["dtype"]) != var.dtype and var.dtype.kind != "U")
    )


def open_result(path: str | Path) -> xr.Dataset:
    """Read a result written by :func:`save` (loaded into memory, file closed)."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"no result file at {path}")
    with path.open("rb") as fh:
        head = fh.read(8)
    if head != _HDF5_SIGNATURE:
        raise PoundingInputError(
            f"{path} is not a pounding result (NetCDF-4 file); allowed: the .nc written by "
            "`pounding run -o`, `pounding study -o` or `pounding separation -o`"
        )
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        return ds.load()


def result_kind(ds: xr.Dataset) -> str:
    """``"analysis"``, ``"study"`` or ``"separation"``: which verb made the Dataset.

    Raises :class:`~pounding.errors.PoundingInputError` for a Dataset that is none of them.
    """
    kind = ds.attrs.get("pounding_kind")
    if kind == "study":
        return "study"
    # files written before the kind attribute was recorded are recognised by their variables
    if kind == "separation" or (kind is None and "required_gap_statistic" in ds):
        return "separation"
    if "displacement" in ds and "time" in ds.dims:
        return "analysis"
    raise PoundingInputError(
        "the Dataset is none of an analysis (pounding run), a study (pounding study) or a "
        "separation check (pounding separation)"
    )


# NetCDF-4 files are HDF5 files: their first 8 bytes (the HDF5 format signature)
_HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"


@xr.register_dataset_accessor("pounding")
class PoundingAccessor:
    """Derived quantities of a pounding result: ``ds.pounding.impacts()``, ``ds.pounding.summary()``."""

    def __init__(self, ds: xr.Dataset) -> None:
        self._ds = ds

    def impacts(self) -> pd.DataFrame:
        """One row per impact: contact, start, end [s], v0 [m/s], peak force [N], max penetration [m],
        impulse [N s], the rebound/approach speed ratio ``rebound_ratio`` (−v_end/v0; NaN while still
        in contact, and for a contact that closed slower than the run's v0 floor, attribute
        ``v0_floor``: one that started from rest has no rebound ratio) beside the contact law's
        nominal coefficient of restitution ``nominal_e`` (NaN for an elastic law). In a row of
        buildings the rebound ratio is not the law's e: the floors behind the struck one keep
        pushing or pull away (values above 1 occur). ``restitution`` is the former name of
        ``rebound_ratio``, kept as an alias column."""
        ds = self._ds
        if "impact" not in ds.dims or ds.sizes["impact"] == 0:
            cols = ["contact", "start", "end", "v0", "peak_force", "max_penetration", "impulse"]
            return pd.DataFrame(columns=[*cols, "rebound_ratio", "nominal_e", "restitution"])
        df = pd.DataFrame(
            {
                "contact": ds["impact_contact"].values,
                "start": ds["impact_start"].values,
                "end": ds["impact_end"].values,
                "v0": ds["impact_v0"].values,
                "peak_force": ds["impact_peak_force"].values,
                "max_penetration": ds["impact_max_penetration"].values,
                "impulse": ds["impact_impulse"].values,
            }
        )
        v0 = df["v0"].to_numpy()
        floor = float(ds.attrs.get("v0_floor", 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = -ds["impact_v_end"].values / v0
        df["rebound_ratio"] = np.where((v0 > 0) & (v0 >= floor), ratio, np.nan)
        df["nominal_e"] = ds["contact_e"].values[df["contact"].to_numpy()]
        df["restitution"] = df["rebound_ratio"]  # the former name
        return df

    def summary(self) -> dict[str, Any]:
        """Headline numbers: periods, peaks per building, impacts per contact, energy balance error."""
        ds = self._ds.transpose(*_DIM_ORDER, ..., missing_dims="ignore")
        return _summary({n: (v.dims, v.values) for n, v in ds.variables.items()}, ds.attrs)

    def statistics(self, over: str = "record") -> xr.Dataset:
        """Record-to-record statistics of a study: for each combination of the other axes (law,
        gap, and ``scale`` kept apart: a scale axis is intensity, never pooled with record-to-record
        scatter), over the ``over`` axis, the median, the 84th percentile (empirical, linear
        interpolation) and the maximum of the drift, floor-acceleration and displacement
        amplifications (per building) and of the run's peak impact force [N] (the largest over
        the contacts); ``pounding_fraction``, the share of the runs with at least one impact; and
        ``n_runs``, the runs that finished (failed runs are left out of every statistic)."""
        ds = self._ds
        if result_kind(ds) != "study" or over not in ds.dims:
            raise PoundingInputError(
                f"statistics() needs a study Dataset with a {over!r} axis (pounding study)"
            )
        stat = xr.DataArray(["median", "p84", "max"], dims="statistic", name="statistic")
        ok = ds["run_status"] == "ok" if "run_status" in ds else xr.ones_like(ds[over], bool)

        def three(da: xr.DataArray) -> xr.DataArray:
            da = da.where(ok)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN: every run failed
                return xr.concat(
                    [da.median(over), da.quantile(0.84, over).drop_vars("quantile"), da.max(over)],
                    dim=stat,
                )

        out = xr.Dataset(coords={"statistic": stat})
        out["statistic"].attrs = {
            "long_name": f"statistic over {over}: median, 84th percentile, max"
        }
        for name in (
            "drift_amplification",
            "acceleration_amplification",
            "displacement_amplification",
        ):
            if name in ds:
                out[name] = three(ds[name])
                out[name].attrs = {"units": "1", "long_name": ds[name].attrs.get("long_name", name)}
        if "peak_contact_force" in ds and "contact" in ds.dims:
            force = ds["peak_contact_force"].max("contact")
            out["peak_impact_force"] = three(force)
            out["peak_impact_force"].attrs = {
                "units": "N",
                "long_name": "largest peak contact force of a run",
            }
            hit = (ds["impact_count"].sum("contact") > 0).where(ok)
            out["pounding_fraction"] = hit.mean(over)
            out["pounding_fraction"].attrs = {
                "units": "1",
                "long_name": f"fraction of the runs over {over} with at least one impact",
            }
        out["n_runs"] = ok.sum(over).astype(np.int64)
        out["n_runs"].attrs = {"units": "1", "long_name": f"runs over {over} that finished"}
        out.attrs = {"title": ds.attrs.get("title", ""), "pooled_over": over}
        return out

    def fragility(
        self,
        limit_state: str | float | list[str | float] = "collapse",
        *,
        building: str | None = None,
        method: str | None = None,
        n_boot: int = 0,
        level: float = 0.9,
    ) -> xr.Dataset:
        """Lognormal fragility of a study with ``im_level`` stripes, or of a hunt-and-fill IDA
        (:func:`pounding.fragility.study_fragility`): per limit state (``"collapse"`` or a story
        drift ratio) and combination of the other axes, the median [g] and β, the fraction of the
        records reaching it per level and the median ratio with/without contact."""
        from pounding.fragility import study_fragility

        return study_fragility(
            self._ds, limit_state, building=building, method=method, n_boot=n_boot, level=level
        )


# the schema's dimension order (pounding._schema.summary indexes by position)
_DIM_ORDER = ("time", "building", "floor", "story", "contact", "term", "mode", "impact")
