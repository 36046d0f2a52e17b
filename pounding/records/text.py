"""One- or two-column text records: reader and writer."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np

from pounding._version import __version__
from pounding.ground_motion import GroundMotion
from pounding.records.common import RecordFormatError, _check_dt, _numbers
from pounding.units import acceleration_factor

_COMMENT = ("#", "%", "!", "//")
_DIRECTIVE = re.compile(r"^\s*(?:#|%|!|//)\s*(units?|dt|name)\s*[:=]\s*(.+?)\s*$", re.IGNORECASE)


def _sniff_text(lines: list[str]) -> bool:
    return True


def read_text(
    path: Path, lines: list[str], *, units: str | None = None, dt: float | None = None
) -> GroundMotion:
    """Plain text: one column of acceleration (``dt`` given) or two columns (time [s], accel).

    Lines starting with ``#``, ``%``, ``!`` or ``//`` are comments; comments of the form
    ``# units: g``, ``# dt: 0.01``, ``# name: ...`` set those fields. Columns are separated by
    blanks, commas or semicolons. One non-numeric line before the data is taken as column
    names. The acceleration unit (g, m/s2, cm/s2, gal, ...) must be given, by ``units`` or by
    a ``# units:`` comment: guessing it would silently scale the record by 9.81 or 100.
    """
    directives: dict[str, tuple[str, int]] = {}
    rows: list[list[float]] = []
    row_lines: list[int] = []
    header_seen = False
    processing: list[str] = []
    for k, text in enumerate(lines, start=1):
        stripped = text.strip()
        if not stripped:
            continue
        if stripped.startswith(_COMMENT):
            m = _DIRECTIVE.match(stripped)
            if m:
                key = m.group(1).lower().rstrip("s") if m.group(1).lower() != "dt" else "dt"
                directives[key] = (m.group(2), k)
            elif stripped.lstrip("#").strip().lower().startswith("processing:"):
                # the processing chain written by write_text, one step per line, in order
                processing.append(stripped.lstrip("#").strip()[len("processing:") :].strip())
            continue
        try:
            row = _numbers(stripped, path, k)
        except RecordFormatError:
            if rows or header_seen:
                raise
            header_seen = True  # one line of column names before the data
            continue
        if rows and len(row) != len(rows[0]):
            raise RecordFormatError(
                path, k, f"{len(rows[0])} columns like line {row_lines[0]}", text
            )
        if len(row) not in (1, 2):
            raise RecordFormatError(
                path, k, "1 column (acceleration) or 2 (time, acceleration)", text
            )
        rows.append(row)
        row_lines.append(k)
    if len(rows) < 2:
        raise RecordFormatError(path, len(lines) or 1, "at least 2 data lines")
    data = np.asarray(rows, dtype=float)
    bad = np.flatnonzero(~np.all(np.isfinite(data), axis=1))
    if bad.size:
        raise RecordFormatError(
            path, row_lines[bad[0]], "finite numbers", lines[row_lines[bad[0]] - 1]
        )
    unit = units
    if unit is None and "unit" in directives:
        unit = directives["unit"][0]
    if unit is None:
        raise RecordFormatError(
            path,
            None,
            "the acceleration unit: pass units= (g, m/s2, cm/s2, gal) or add a '# units: g' line",
        )
    try:
        factor = acceleration_factor(unit)
    except ValueError as exc:
        line = directives["unit"][1] if "unit" in directives and units is None else None
        raise RecordFormatError(path, line, str(exc).replace("unknown", "a known")) from None
    header_dt = None
    if "dt" in directives:
        value, k = directives["dt"]
        try:
            header_dt = float(value.split()[0])
        except ValueError:
            raise RecordFormatError(path, k, "a number after 'dt:'", value) from None
        header_dt = _check_dt(header_dt, path, k, None)
    start_time = 0.0
    if data.shape[1] == 1:
        step = dt if dt is not None else header_dt
        if step is None:
            raise RecordFormatError(
                path,
                None,
                "the time step for a one-column file: pass dt= or add a '# dt: 0.01' line",
            )
        step = _check_dt(float(step), path, None, None)
        acc = data[:, 0]
    else:
        t = data[:, 0]
        steps = np.diff(t)
        if np.any(steps <= 0):
            i = int(np.flatnonzero(steps <= 0)[0])
            raise RecordFormatError(
                path, row_lines[i + 1], "increasing times in column 1", lines[row_lines[i + 1] - 1]
            )
        step = float((t[-1] - t[0]) / (t.size - 1))
        dev = np.abs(steps - step)
        tol = 1e-3 * step + 1e-9 * max(abs(t[-1]), 1.0)
        if np.any(dev > tol):
            i = int(np.argmax(dev))
            raise RecordFormatError(
                path,
                row_lines[i + 1],
                f"uniform time step {step:.6g} s",
                lines[row_lines[i + 1] - 1],
            )
        step = _check_dt(step, path, None, dt if dt is not None else header_dt)
        start_time = float(t[0])
        acc = data[:, 1]
    meta = {
        "source": str(path),
        "format": "text",
        "units_read": unit,
        "columns": int(data.shape[1]),
    }
    if start_time:
        meta["start_time"] = start_time
    if processing:
        meta["processing"] = processing
    name = directives["name"][0] if "name" in directives else path.stem
    return GroundMotion(acc * factor, step, name=name, metadata=meta)


def write_text(gm: GroundMotion, path: Path, *, units: str = "g") -> None:
    """Write two columns, time [s] and acceleration in ``units``, with a commented header."""
    factor = acceleration_factor(units)
    header = [
        f"# name: {gm.name}",
        f"# units: {units}",
        f"# dt: {gm.dt:.10g}",
        f"# npts: {gm.npts}",
        f"# written by pounding {__version__}",
    ]
    source = gm.metadata.get("source")
    if source:
        header.append(f"# source: {source}")
    for key in ("generator", "parameters", "target", "achieved_tolerance", "converged"):
        if key in gm.metadata:
            header.append(f"# {key}: {json.dumps(gm.metadata[key], sort_keys=True)}")
    for step in gm.metadata.get("processing", []):
        header.append(f"# processing: {step}")
    header.append(f"# columns: time [s], ground acceleration [{units}]")
    body = np.column_stack((gm.time, gm.acceleration / factor))
    text = "\n".join(header) + "\n" + "\n".join(f"{t:.10g} {a:.10g}" for t, a in body) + "\n"
    path.write_text(text, encoding="utf-8")
