"""A NetCDF-4 writer on h5py alone, for pounding's result Datasets.

Writing through ``xr.Dataset.to_netcdf(engine="h5netcdf")`` costs ~0.2 s for a one-run result
(58 small variables): xarray's per-variable encoding and h5netcdf's per-variable HDF5 look-ups
by path, not the data. This module writes the same NetCDF-4 layout directly: each dimension a
coordinate variable that is an HDF5 dimension scale (``CLASS``/``NAME``, ``_Netcdf4Dimid``),
every variable with its scales attached (``DIMENSION_LIST``/``REFERENCE_LIST``) and
``_Netcdf4Coordinates``, floats with ``_FillValue`` NaN, strings as variable-length UTF-8,
non-dimension coordinates named in each variable's CF ``coordinates`` attribute (xarray's rule),
creation order tracked and ``_NCProperties`` on the root group, as netCDF-C expects.

It takes plain arrays (no xarray), so a caller that never builds a Dataset need not import
xarray; :func:`pounding.results.save` is the one public entry point.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterable, Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from pounding.errors import PoundingError, ResultWriteError

#: Variable: (dimension names, values, attributes).
Variable = tuple[tuple[str, ...], np.ndarray, Mapping[str, Any]]


# dtype kinds written here; anything else (bool, datetime, complex, ...) goes to xarray
_KINDS = frozenset("fiuUO")


def supported(variables: Mapping[str, Variable]) -> bool:
    """True when every variable is float, integer or string data and every dimension has a
    coordinate variable (the layout :func:`write` produces)."""
    dims: set[str] = set()
    for dims_, values, attrs in variables.values():
        kind = values.dtype.kind
        if kind not in _KINDS or "_FillValue" in attrs or "coordinates" in attrs:
            return False
        if kind == "O" and not all(isinstance(v, str) for v in values.ravel().tolist()):
            return False
        dims.update(dims_)
    return all(d in variables and variables[d][0] == (d,) for d in dims)


def _attr(value: Any) -> np.ndarray:
    """An attribute as netCDF stores it: a string as a scalar, numbers as 1-element arrays."""
    if isinstance(value, str):
        return np.array(value, dtype=object)
    arr = np.asarray(value)
    if arr.dtype.kind in "UO":
        return np.array(arr.tolist(), dtype=object)
    return arr.reshape(1) if arr.ndim == 0 else arr


class _Attrs:
    """Creates attributes with h5py's low-level calls (h5py's ``attrs[...] =`` costs ~50 us
    each in checks for a new file's 300 attributes), HDF5 types cached per dtype."""

    def __init__(self, h5py: Any) -> None:
        self._h5py = h5py
        self._types: dict[Any, tuple[Any, Any]] = {}
        self._str = h5py.string_dtype("utf-8")

    def set(self, obj: Any, name: str, value: np.ndarray) -> None:
        h5a, h5s, h5t = self._h5py.h5a, self._h5py.h5s, self._h5py.h5t
        dtype = self._str if value.dtype.kind == "O" else value.dtype
        types = self._types.get(dtype)
        if types is None:
            types = self._types[dtype] = (
                h5t.py_create(dtype, logical=True),
                h5t.py_create(dtype),
            )
        space = h5s.create(h5s.SCALAR) if value.ndim == 0 else h5s.create_simple(value.shape)
        attr = h5a.create(obj.id, name.encode(), types[0], space)
        try:
            attr.write(np.ascontiguousarray(value), mtype=types[1])
        finally:
            attr.close()


@contextlib.contextmanager
def replacing(path: str | Path) -> Iterator[Path]:
    """A temporary path beside ``path`` to write to; on success it is flushed to disk and renamed
    over ``path`` in one step, on failure removed: a failed write never leaves a half-written file
    nor destroys a good result already at ``path``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.writing")
    try:
        yield tmp
        with open(tmp, "rb+") as fh:
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            tmp.unlink()
        if isinstance(exc, Exception) and not isinstance(exc, PoundingError):
            raise ResultWriteError(
                f"{path}: the result could not be written ({type(exc).__name__}: "
                f"{' '.join(str(exc).split())}); "
                + ("the previous file there is untouched" if path.exists() else "nothing written")
            ) from exc
        raise


def write(
    path: str | Path,
    variables: Mapping[str, Variable],
    coords: Iterable[str],
    attrs: Mapping[str, Any],
    *,
    producer: str = "pounding",
) -> None:
    """Write ``variables`` (data variables and coordinates) to a NetCDF-4 file at ``path``.

    Parameters
    ----------
    path
        Output file, overwritten.
    variables
        name -> (dimension names, values, attributes); every dimension must have a 1-D
        coordinate variable of the same name (see :func:`supported`).
    coords
        Names of the coordinates among ``variables`` (dimension coordinates included).
    attrs
        Global attributes (strings, numbers, arrays of numbers).
    producer
        Written into ``_NCProperties`` with the HDF5 and h5py versions.
    """
    import h5py

    coords = set(coords)
    dim_names = list(dict.fromkeys(d for dims, _, _ in variables.values() for d in dims))
    dimid = {d: np.int32(i) for i, d in enumerate(dim_names)}
    # xarray's rule: a non-dimension coordinate is named in the `coordinates` attribute of
    # every other variable whose dimensions include all of its own
    aux = sorted(c for c in coords if c not in dimid)
    str_dtype = h5py.string_dtype("utf-8")
    put = _Attrs(h5py).set
    with replacing(path) as tmp, h5py.File(tmp, "w", track_order=True) as f:
        scales: dict[str, h5py.Dataset] = {}
        named: set[str] = set()
        # dimension coordinates first: the others attach to them
        order = dim_names + [n for n in variables if n not in dimid]
        for name in order:
            dims, values, vattrs = variables[name]
            kind = values.dtype.kind
            kw: dict[str, Any] = {}
            if kind in "UO":
                data = np.asarray(values, dtype=object)
                dtype = str_dtype
            else:
                data = values
                dtype = values.dtype
                if kind == "f":
                    kw["fillvalue"] = np.nan
            ds = f.create_dataset(name, data=data, dtype=dtype, track_order=True, **kw)
            if name in dimid:
                ds.make_scale(name)
                scales[name] = ds
            else:
                for i, d in enumerate(dims):
                    ds.dims[i].attach_scale(scales[d])
            if dims:
                ids = np.array([dimid[d] for d in dims], dtype=np.int32)
                put(ds, "_Netcdf4Coordinates", ids)
                put(ds, "_Netcdf4Dimid", ids[0].reshape(()))
            if kind == "f":
                put(ds, "_FillValue", np.array([np.nan], dtype=values.dtype))
            for key, value in vattrs.items():
                put(ds, str(key), _attr(value))
            if name not in coords:
                sdims = set(dims)
                linked = [c for c in aux if set(variables[c][0]) <= sdims]
                if linked:
                    put(ds, "coordinates", _attr(" ".join(linked)))
                    named.update(linked)
        for key, value in attrs.items():
            put(f, str(key), _attr(value))
        if set(aux) - named:  # coordinates of no variable: xarray reads them from here
            put(f, "coordinates", _attr(" ".join(c for c in aux if c not in named)))
        props = f"version=2,{producer},hdf5={h5py.version.hdf5_version},h5py={h5py.__version__}"
        f.attrs["_NCProperties"] = np.array(
            props, dtype=h5py.string_dtype("ascii", length=len(props))
        )
