"""PEER NGA ``.AT2``/``.VT2``/``.DT2`` records: reader and writer."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from pounding._version import __version__
from pounding.ground_motion import GroundMotion
from pounding.records.common import (
    _NUMBER,
    RecordFormatError,
    _check_dt,
    _finite,
    _numbers,
    _to_acceleration,
    _unit_from_label,
)
from pounding.units import G

_PEER_NEW = re.compile(
    rf"NPTS\s*=\s*(?P<npts>\d+)\s*,?\s*DT\s*=\s*(?P<dt>{_NUMBER})\s*(?:SEC)?", re.IGNORECASE
)
_PEER_OLD = re.compile(rf"^\s*(?P<npts>\d+)\s+(?P<dt>{_NUMBER})\s+NPTS\s*,\s*DT", re.IGNORECASE)
_PEER_QUANTITY = {".at2": "acceleration", ".vt2": "velocity", ".dt2": "displacement"}


def _sniff_peer(lines: list[str]) -> bool:
    return len(lines) >= 4 and (
        "PEER" in lines[0].upper() or bool(_PEER_NEW.search(lines[3]) or _PEER_OLD.search(lines[3]))
    )


def read_peer(
    path: Path, lines: list[str], *, units: str | None = None, dt: float | None = None
) -> GroundMotion:
    """PEER NGA record (.AT2 acceleration, .VT2 velocity, .DT2 displacement).

    Header: three text lines (database, event/station/component, quantity and units), then the
    count and step in either style, ``NPTS=  5590, DT=   .0050 SEC`` (NGA-West2) or
    ``5590   .00500   NPTS, DT`` (older NGA). Velocity and displacement are differentiated to
    acceleration by second-order central differences.
    """
    if len(lines) < 4:
        raise RecordFormatError(path, len(lines) + 1, "a 4-line PEER header")
    match = _PEER_NEW.search(lines[3]) or _PEER_OLD.search(lines[3])
    if match is None:
        raise RecordFormatError(path, 4, "'NPTS= n, DT= dt SEC' or 'n dt NPTS, DT'", lines[3])
    npts = int(match["npts"])
    step = _check_dt(float(match["dt"]), path, 4, dt)
    suffix = path.suffix.lower()
    quantity = _PEER_QUANTITY.get(suffix, "acceleration")
    unit = {"acceleration": "g", "velocity": "cm/s", "displacement": "cm"}[quantity]
    label = re.search(r"UNITS\s+OF\s+([A-Za-z/0-9*^ ]+?)\s*$", lines[2].strip(), re.IGNORECASE)
    if label:
        try:
            quantity, unit = _unit_from_label(label.group(1))
        except KeyError:
            raise RecordFormatError(
                path, 3, "units G, CM/S/S, CM/S or CM after 'UNITS OF'", label.group(1)
            ) from None
    if units is not None:
        unit = units
    # a velocity or displacement is differentiated by second-order differences: 3 points at least
    least, what = (
        (2, "an acceleration record")
        if quantity == "acceleration"
        else (3, f"a {quantity} record (differentiated by central differences)")
    )
    if npts < least:
        raise RecordFormatError(path, 4, f"NPTS >= {least} for {what}", lines[3])
    values: list[float] = []
    per_line: list[int] = []
    for k, text in enumerate(lines[4:], start=5):
        if not text.strip():
            per_line.append(0)
            continue
        row = _numbers(text, path, k)
        values.extend(row)
        per_line.append(len(row))
        if len(values) > npts:
            raise RecordFormatError(path, k, f"NPTS={npts} values in all", f"{len(values)} values")
    if len(values) != npts:
        raise RecordFormatError(path, len(lines), f"NPTS={npts} values", f"{len(values)} values")
    data = np.asarray(values, dtype=float)
    _finite(data, path, 5, per_line)
    acc = _to_acceleration(data, step, quantity, unit)
    title = lines[1].strip()
    meta = {
        "source": str(path),
        "format": "peer",
        "header": [line.rstrip() for line in lines[:4]],
        "quantity_read": quantity,
        "units_read": unit,
        "header_style": "NGA-West2 (NPTS=, DT=)" if _PEER_NEW.search(lines[3]) else "old NGA",
    }
    gm = GroundMotion(acc, step, name=title or path.stem, metadata=meta)
    if quantity != "acceleration":
        gm = gm.with_step(f"differentiated from {quantity} (central differences)", gm.acceleration)
    return gm


def write_peer(gm: GroundMotion, path: Path) -> None:
    """Write a PEER NGA-West2 style .AT2 file (acceleration in g, 5 values per line)."""
    acc = gm.acceleration / G
    lines = [
        "PEER NGA STRONG MOTION DATABASE RECORD (format; written by pounding "
        f"{__version__}, not from the PEER database)",
        gm.name.replace("\n", " "),
        "ACCELERATION TIME SERIES IN UNITS OF G",
        f"NPTS={gm.npts:7d}, DT={gm.dt:.10g} SEC",
    ]
    for i in range(0, acc.size, 5):
        lines.append("".join(f"{v:15.7E}" for v in acc[i : i + 5]))
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
